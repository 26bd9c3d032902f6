"""LS-DYNA keyword decks (fixed format) and a small validator of that format.

Every card is written from `CARDS`, the field widths and types of the keywords used here, and the
validator reads a deck back against the same table: lines of at most 80 characters, each field
blank or of its type, the card count of each keyword (viscoelastic cards counted from NV), and
the references between entities (element nodes, part, section and material ids, node sets).

Model: 3D ball of constant-stress hexahedra (`*SECTION_SOLID`, ELFORM 1, as C3D8R) or an
axisymmetric ball (`*SECTION_SHELL`, ELFORM 15, volume weighted; x radial, y the axis),
`*RIGIDWALL_PLANAR` (the plane through the origin, normal +y in 2D, +z in 3D, with friction),
`*INITIAL_VELOCITY`, `*CONTROL_TERMINATION`, bulk viscosity as ours, and output of the wall force
(`*DATABASE_RWFORC`), the energies (`*DATABASE_GLSTAT`, `*DATABASE_MATSUM`) and `d3plot` states.
"""

from __future__ import annotations

import math
import re

import numpy as np

from .. import __version__
from ..errors import InputError
from ..balls.ball import BallModel
from .geometry import BallGeometry
from .materials import ExportError, lsdyna_material
from .setup import ImpactSetup
from .units import UnitSystem

I, F, T = "I", "F", "T"  # integer, real, title (80 characters of text)

#: keyword -> cards: each card is a tuple of (type, width); "rows" repeats the last card
CARDS: dict[str, dict] = {
    "*KEYWORD": {"cards": []},
    "*TITLE": {"cards": [((T, 80),)]},
    "*CONTROL_TERMINATION": {"cards": [((F, 10), (I, 10), (F, 10), (F, 10), (F, 10))]},
    "*CONTROL_TIMESTEP": {"cards": [((F, 10), (F, 10))]},
    "*CONTROL_BULK_VISCOSITY": {"cards": [((F, 10), (F, 10), (I, 10))]},
    "*CONTROL_HOURGLASS": {"cards": [((I, 10), (F, 10))]},
    "*DATABASE_GLSTAT": {"cards": [((F, 10), (I, 10))]},
    "*DATABASE_MATSUM": {"cards": [((F, 10), (I, 10))]},
    "*DATABASE_RWFORC": {"cards": [((F, 10), (I, 10))]},
    "*DATABASE_BINARY_D3PLOT": {"cards": [((F, 10),)]},
    "*PART": {"cards": [((T, 80),), ((I, 10),) * 8]},
    "*SECTION_SOLID": {"cards": [((I, 10), (I, 10), (I, 10))]},
    "*SECTION_SHELL": {"cards": [((I, 10), (I, 10), (F, 10), (I, 10), (F, 10), (I, 10), (I, 10)),
                                 ((F, 10),) * 4]},
    "*MAT_HYPERELASTIC_RUBBER_TITLE": {"cards": [((T, 80),), ((I, 10), (F, 10), (F, 10),
                                                              (I, 10), (I, 10), (F, 10), (F, 10),
                                                              (F, 10)), ((F, 10),) * 7],
                                       "visco": ((F, 10), (F, 10))},
    "*MAT_OGDEN_RUBBER_TITLE": {"cards": [((T, 80),), ((I, 10), (F, 10), (F, 10), (I, 10),
                                                       (I, 10), (F, 10), (F, 10), (F, 10)),
                                          ((F, 10),) * 8, ((F, 10),) * 8],
                                "visco": ((F, 10), (F, 10))},
    "*MAT_ELASTIC_TITLE": {"cards": [((T, 80),), ((I, 10), (F, 10), (F, 10), (F, 10))]},
    "*NODE": {"cards": [((I, 8), (F, 16), (F, 16), (F, 16), (I, 8), (I, 8))], "rows": True},
    "*ELEMENT_SOLID": {"cards": [((I, 8),) * 10], "rows": True},
    "*ELEMENT_SHELL": {"cards": [((I, 8),) * 6], "rows": True},
    "*SET_NODE_LIST": {"cards": [((I, 10),) * 5, ((I, 10),) * 8], "rows": True},
    "*INITIAL_VELOCITY": {"cards": [((I, 10),) * 4, ((F, 10),) * 6]},
    "*RIGIDWALL_PLANAR": {"cards": [((I, 10), (I, 10), (I, 10), (F, 10), (F, 10), (F, 10),
                                     (F, 10)), ((F, 10),) * 8]},
    "*BOUNDARY_SPC_SET": {"cards": [((I, 10),) * 8]},
    "*END": {"cards": []},
}


def field(value, kind: str, width: int) -> str:
    """One fixed-width field: integers as they are, reals with as many digits as fit in all but
    one column."""
    if value is None:
        return " " * width
    if kind == T:
        return str(value)[:width]
    if kind == I:
        text = str(int(value))
    else:
        x = float(value)
        if not math.isfinite(x):
            raise ExportError(f"LS-DYNA field: non-finite value {x!r}")
        text = "0.0" if x == 0.0 else None
        room = width - 1  # a blank column between fields, for the eye
        for digits in range(room - 1, 0, -1):
            if text is not None:
                break
            candidate = f"{x:.{digits}g}"
            if "e" in candidate:  # 1.5e-05 -> 1.5e-5: one more digit fits
                mantissa, exponent = candidate.split("e")
                candidate = f"{mantissa}e{int(exponent)}"
            elif "." not in candidate:
                candidate += "."
            if len(candidate) <= room:
                text = candidate
    if len(text) > width:
        raise ExportError(f"LS-DYNA field: {value} does not fit {width} characters")
    return text.rjust(width)


def card(values, spec) -> str:
    values = list(values) + [None] * (len(spec) - len(values))
    return "".join(field(v, kind, width) for v, (kind, width) in zip(values, spec)).rstrip()


def _set_node_list(sid: int, nodes) -> list[str]:
    spec = CARDS["*SET_NODE_LIST"]["cards"]
    ids = [int(n) for n in nodes]
    return ["*SET_NODE_LIST", card([sid], spec[0])] + [card(ids[i:i + 8], spec[1])
                                                        for i in range(0, len(ids), 8)]


def write_deck(ball: BallModel, geom: BallGeometry, units: UnitSystem,
               setup: ImpactSetup | None = None, ball_only: bool = False,
               approximate: bool = False) -> tuple[str, list[str]]:
    """The keyword deck's text and its notes (also for stderr)."""
    two_d = geom.dimension == 2
    c = CARDS
    L = units.length
    notes: list[str] = []
    materials = []
    for k, layer in enumerate(ball.layers, start=1):
        keyword, cards, extra = lsdyna_material(k, layer.name, layer.density_kg_m3,
                                                layer.material, units, approximate)
        materials.append((keyword, cards))
        notes += extra
    if geom.half:
        notes.append("half model (y >= 0, symmetry on y = 0): wall forces and energies are half "
                     "the ball's")
    out = ["*KEYWORD", "*TITLE", f"ballimpact {__version__} "
           f"{'ball' if ball_only else 'impact'}: {ball.name}"[:80],
           f"$ written by ballimpact {__version__} for LS-DYNA (fixed format)",
           f"$ {units.header()}",
           f"$ ballimpact ball: {ball.name}",
           f"$ mesh: {geom.solver}, {len(geom.nodes_m)} nodes, {len(geom.elements)} elements, "
           f"mesh mass {geom.mass_kg(ball):.6g} kg (ball {ball.mass_kg:.6g} kg)",
           "$ Prony terms as *MAT_077 GI, BETAI: G_i = g_i x instantaneous mu0, BETA_i = 1/tau_i, "
           "on long-term C10, C01 (mu_i)",
           "$ PR gives our bulk modulus from the long-term shear modulus 2(C10 + C01) "
           "(D1 = 0: K0 = 20 x instantaneous mu0)"]
    out += [f"$ note: {note}" for note in notes]
    if not ball_only:
        t = setup.step_time(ball) * units.time
        out += [f"$ impact: {setup.speed_m_s:g} m/s at {setup.angle_deg:g} deg from the normal, "
                f"friction {setup.friction:g}",
                "*CONTROL_TERMINATION", card([t], c["*CONTROL_TERMINATION"]["cards"][0]),
                "*CONTROL_TIMESTEP", card([None, 0.8], c["*CONTROL_TIMESTEP"]["cards"][0]),
                "*CONTROL_BULK_VISCOSITY", card([1.2, 0.06, 1],
                                                c["*CONTROL_BULK_VISCOSITY"]["cards"][0]),
                "$ stiffness-form hourglass control (Flanagan-Belytschko), as our solvers",
                "*CONTROL_HOURGLASS", card([4, 0.05], c["*CONTROL_HOURGLASS"]["cards"][0])]
        for keyword in ("*DATABASE_GLSTAT", "*DATABASE_MATSUM", "*DATABASE_RWFORC"):
            out += [keyword, card([t / 500, 1], c[keyword]["cards"][0])]
        out += ["*DATABASE_BINARY_D3PLOT", card([t / 50], c["*DATABASE_BINARY_D3PLOT"]["cards"][0])]
    section_id = 1
    if two_d:
        out += ["$ axisymmetric solid, volume weighted: x radial, y the axis; LS-DYNA may "
                "report its forces per radian (check d3hsp; x 2 pi for the whole ball)",
                "*SECTION_SHELL", card([section_id, 15, 1.0, None, None, None, 0],
                                       c["*SECTION_SHELL"]["cards"][0]),
                card([0.0] * 4, c["*SECTION_SHELL"]["cards"][1])]
    else:
        out += ["$ constant-stress hexahedron (one point, as C3D8R)",
                "*SECTION_SOLID", card([section_id, 1, 0], c["*SECTION_SOLID"]["cards"][0])]
    for k, (layer, (keyword, cards)) in enumerate(zip(ball.layers, materials), start=1):
        spec = c[keyword]
        out += [keyword, layer.name[:80]]
        n_fixed = len(spec["cards"]) - 1  # after the title card
        out += [card(values, spec["cards"][i + 1]) for i, values in enumerate(cards[:n_fixed])]
        out += [card(values, spec["visco"]) for values in cards[n_fixed:]]
        out += ["*PART", layer.name[:80], card([k, section_id, k, 0, 0, 0, 0, 0],
                                                c["*PART"]["cards"][1])]
    out.append("*NODE")
    spec = c["*NODE"]["cards"][0]
    coords = geom.nodes_m * L
    out += [card([i, *p], spec) for i, p in enumerate(coords.tolist(), start=1)]
    if two_d:
        out.append("*ELEMENT_SHELL")
        spec = c["*ELEMENT_SHELL"]["cards"][0]
    else:
        out.append("*ELEMENT_SOLID")
        spec = c["*ELEMENT_SOLID"]["cards"][0]
    out += [card([e, part + 1, *[n + 1 for n in conn]], spec) for e, (part, conn) in
            enumerate(zip(geom.element_layer.tolist(), geom.elements.tolist()), start=1)]
    out += _set_node_list(1, range(1, len(geom.nodes_m) + 1))
    spc = []
    if two_d:
        out += _set_node_list(2, geom.axis_nodes + 1)
        spc.append([2, 0, 1, 0, 0, 0, 0, 0])
    if geom.half:
        out += _set_node_list(3, geom.symmetry_nodes + 1)
        spc.append([3, 0, 0, 1, 0, 0, 0, 0])
    for row in spc:
        out += ["*BOUNDARY_SPC_SET", card(row, c["*BOUNDARY_SPC_SET"]["cards"][0])]
    if not ball_only:
        v = [x * units.velocity for x in setup.velocity_m_s(geom.dimension)]
        v3 = (v + [0.0])[:3] if two_d else v
        head = (0.0, 1.0, 0.0) if two_d else (0.0, 0.0, 1.0)
        out += ["*INITIAL_VELOCITY", card([1, 0, 0, 0], c["*INITIAL_VELOCITY"]["cards"][0]),
                card([*v3, 0.0, 0.0, 0.0], c["*INITIAL_VELOCITY"]["cards"][1]),
                "$ the plane through the origin; normal from tail to head, toward the ball",
                "*RIGIDWALL_PLANAR", card([1, 0, 0, None, None, None, 1.0],  # blank: defaults
                                          c["*RIGIDWALL_PLANAR"]["cards"][0]),
                card([0.0, 0.0, 0.0, *head, setup.friction, 0.0],
                     c["*RIGIDWALL_PLANAR"]["cards"][1])]
    out.append("*END")
    return "\n".join(out) + "\n", notes


# ---- validation --------------------------------------------------------------------------------
def _check_field(text: str, kind: str, where: str) -> int | float | str | None:
    stripped = text.strip()
    if kind == T:
        return text
    if not stripped:
        return None
    try:
        if kind == I:
            return int(stripped)
        return float(re.sub(r"(?<=\d)([+-]\d+)$", r"e\1", stripped))  # Fortran 1.5-5
    except ValueError:
        raise InputError(f"{where}: {'integer' if kind == I else 'real'} field holds "
                         f"{stripped!r}") from None


def validate(text: str) -> dict[str, int]:
    """Check a keyword deck written here; returns the count of each keyword. Raises `InputError`
    naming the line of the first defect."""
    blocks: list[tuple[str, int, list[tuple[int, str]]]] = []
    for number_, line in enumerate(text.splitlines(), start=1):
        if line.startswith("$"):
            continue
        if len(line) > 80:
            raise InputError(f"line {number_}: {len(line)} characters (at most 80)")
        if line.startswith("*"):
            blocks.append((line.strip().upper(), number_, []))
        elif not blocks:
            raise InputError(f"line {number_}: data before the first keyword")
        else:
            blocks[-1][2].append((number_, line))
    if not blocks or blocks[0][0] != "*KEYWORD" or blocks[-1][0] != "*END":
        raise InputError("a keyword deck starts with *KEYWORD and ends with *END")
    counts: dict[str, int] = {}
    nodes, parts, sections, mats, node_sets, elements = set(), {}, set(), set(), set(), []
    for keyword, line_no, lines in blocks:
        if keyword not in CARDS:
            raise InputError(f"line {line_no}: keyword {keyword} is not one this deck uses")
        counts[keyword] = counts.get(keyword, 0) + 1
        spec = CARDS[keyword]
        cards = list(spec["cards"])
        expected = len(cards)
        parsed = []
        for i, (n, line) in enumerate(lines):
            if i < len(cards):
                layout = cards[i]
            elif spec.get("rows"):
                layout = cards[-1]
            elif "visco" in spec:
                layout = spec["visco"]
            else:
                raise InputError(f"line {n}: {keyword} takes {expected} card(s), found more")
            values, column = [], 0
            for kind, width in layout:
                values.append(_check_field(line[column:column + width], kind, f"line {n}"))
                column += width
            if line[column:].strip():
                raise InputError(f"line {n}: text beyond the last field of {keyword}")
            parsed.append(values)
        if len(parsed) < expected:
            raise InputError(f"line {line_no}: {keyword} needs {expected} card(s), found "
                             f"{len(parsed)}")
        if "visco" in spec:
            nv = parsed[1][4] or 0
            if len(parsed) - expected != nv:
                raise InputError(f"line {line_no}: {keyword} has NV = {nv} but "
                                 f"{len(parsed) - expected} viscoelastic cards")
            mats.add(parsed[1][0])
        if keyword == "*MAT_ELASTIC_TITLE":
            mats.add(parsed[1][0])
        if keyword == "*NODE":
            nodes.update(row[0] for row in parsed)
        if keyword in ("*SECTION_SOLID", "*SECTION_SHELL"):
            sections.add(parsed[0][0])
        if keyword == "*PART":
            parts[parsed[1][0]] = (parsed[1][1], parsed[1][2], line_no)
        if keyword in ("*ELEMENT_SOLID", "*ELEMENT_SHELL"):
            elements += [(row, n) for row, (n, _) in zip(parsed, lines)]
        if keyword == "*SET_NODE_LIST":
            node_sets.add(parsed[0][0])
            missing = [v for row in parsed[1:] for v in row if v is not None and v not in nodes]
            if missing:
                raise InputError(f"line {line_no}: node set {parsed[0][0]} names node "
                                 f"{missing[0]}, which no *NODE defines")
        if keyword in ("*INITIAL_VELOCITY", "*BOUNDARY_SPC_SET", "*RIGIDWALL_PLANAR"):
            if parsed[0][0] not in node_sets and parsed[0][0] != 0:
                raise InputError(f"line {line_no}: {keyword} uses node set {parsed[0][0]}, "
                                 "which is not defined before it")
    for pid, (sid, mid, line_no) in parts.items():
        if sid not in sections or mid not in mats:
            raise InputError(f"line {line_no}: part {pid} refers to section {sid} / material "
                             f"{mid}, not defined")
    for row, n in elements:
        if row[1] not in parts:
            raise InputError(f"line {n}: element {row[0]} is in part {row[1]}, not defined")
        bad = [v for v in row[2:] if v is not None and v not in nodes]
        if bad:
            raise InputError(f"line {n}: element {row[0]} uses node {bad[0]}, not defined")
    return counts


def read_nodes_elements(text: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(node coordinates, element connectivity 0-based, part id) of a deck written here."""
    nodes, elements, parts = {}, [], []
    keyword = ""
    for line in text.splitlines():
        if line.startswith("$"):
            continue
        if line.startswith("*"):
            keyword = line.strip().upper()
            continue
        if keyword == "*NODE":
            nodes[int(line[:8])] = [float(line[8 + 16 * i:24 + 16 * i].strip() or 0.0)
                                    for i in range(3)]
        elif keyword in ("*ELEMENT_SOLID", "*ELEMENT_SHELL"):
            ids = [int(line[i:i + 8]) for i in range(0, len(line), 8)]
            parts.append(ids[1])
            elements.append(ids[2:])
    order = sorted(nodes)
    index = {n: i for i, n in enumerate(order)}
    return (np.array([nodes[n] for n in order]), np.array([[index[n] for n in e] for e in elements]),
            np.array(parts))
