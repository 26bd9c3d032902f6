"""Read ABAQUS material blocks (and, for decks written here, the whole ball) into our ball
specification (SI).

Read: `*MATERIAL, NAME=` with `*DENSITY`, `*HYPERELASTIC, MOONEY-RIVLIN | NEO HOOKE |
POLYNOMIAL, N=1` (C10, C01, D1), `*HYPERELASTIC, YEOH` (C10, C20, C30, D1, D2, D3),
`*HYPERELASTIC, OGDEN, N=n` (mu_i, alpha_i, then D_i), with D2, D3, ... = 0 (our volumetric
energy is (J - 1)^2 / D1 alone), `*HYPERFOAM, N=n` (mu_i, alpha_i, then nu_i), `*ELASTIC` (E, nu),
`*VISCOELASTIC, TIME=PRONY` (g_i, k_i, tau_i) and `MODULI=LONG TERM | INSTANTANEOUS` (ABAQUS's
default: long term). Other hyperelastic forms, frequency-domain viscoelasticity and
temperature-dependent rows are refused with the card named; other material options (damping,
expansion, ...) are skipped with a warning. ABAQUS names are case-insensitive: they are read in
lower case.
"""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError, InputWarning
from ..balls.ball import load_ball
from ..constitutive import material_from_dict
from ..checks import check_allow
from ..fileio import check_output_folder, write_atomic
from ..balls.checks import check_material_values
from .units import UNIT_SYSTEMS, UnitSystem, unit_system

_UNITS_LINE = re.compile(r"^\*\*\s*units\s+(\S+):", re.IGNORECASE | re.MULTILINE)
_BALL_LINE = re.compile(r"^\*\*\s*ballimpact ball:\s*(.+)$", re.MULTILINE)
_MATERIAL_OPTIONS = {"DENSITY", "HYPERELASTIC", "HYPERFOAM", "VISCOELASTIC", "ELASTIC",
                     "DAMPING", "EXPANSION", "CONDUCTIVITY", "SPECIFIC HEAT", "MULLINS EFFECT",
                     "PLASTIC", "DEPVAR", "USER MATERIAL", "HYSTERESIS", "EOS", "FAIL STRESS"}


def _keyword(line: str) -> tuple[str, dict[str, str]]:
    parts = [p.strip() for p in line[1:].split(",")]
    params = {}
    for p in parts[1:]:
        if p:
            key, _, value = p.partition("=")
            params[key.strip().upper()] = value.strip()
    return parts[0].upper(), params


def blocks(text: str) -> list[tuple[str, dict[str, str], list[list[str]], int]]:
    """(keyword, parameters, data rows, line number) of every keyword in an ABAQUS input."""
    out: list = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("**"):
            continue
        if line.startswith("*"):
            out.append((*_keyword(line), [], number))
        elif out:
            out[-1][2].append([v.strip() for v in line.split(",")])
    return out


def _si(x: float) -> float:
    """A converted value rounded to 12 digits: 4.02 MPa reads as 4.02e6 Pa, not 4019999.9999."""
    return float(f"{x:.12g}")


def _order(params: dict[str, str], where: str) -> int:
    """The N= parameter of a card (default 1), a positive integer."""
    try:
        n = int(params.get("N", "1"))
    except ValueError:
        n = 0
    if n < 1:
        raise InputError(f"{where}: N={params.get('N')}: expected a positive integer")
    return n


def _floats(rows: list[list[str]], where: str) -> list[float]:
    try:
        return [float(v) for row in rows for v in row if v != ""]
    except ValueError:
        raise InputError(f"{where}: data must be numbers, got {rows}") from None


def _higher_d_zero(values: list[float], where: str) -> None:
    """D2, D3, ... of a hyperelastic card must be 0: our volumetric energy is (J - 1)^2 / D1."""
    for i, d in enumerate(values, start=2):
        if d != 0.0:
            raise InputError(f"{where}: D{i} = {d:g}: only 0 is supported (the volumetric "
                             "energy is (J - 1)^2 / D1 alone)")


def file_units(text: str, units: str | None) -> UnitSystem:
    """The deck's unit system: `units` if given, else the `** units NAME:` line we write."""
    if units is not None:
        return unit_system(units)
    match = _UNITS_LINE.search(text)
    if match and match.group(1).lower() in UNIT_SYSTEMS:
        return unit_system(match.group(1).lower())
    raise InputError("units: the file does not say its units (no '** units' line written by "
                     f"ballimpact); give --units ({', '.join(UNIT_SYSTEMS)})")


def _moduli(params: dict[str, str]) -> str:
    value = params.get("MODULI", "LONG TERM").upper().replace("_", " ")
    if value not in ("LONG TERM", "INSTANTANEOUS"):
        raise InputError(f"MODULI={value}: allowed LONG TERM, INSTANTANEOUS")
    return value.lower().replace(" ", "_")


def read_materials(text: str, units: str | None = None) -> list[dict[str, Any]]:
    """Every `*MATERIAL` of an ABAQUS input as {"name", "density_kg_m3", "material"} (SI; the
    material in our specification's form; density None where the block has none)."""
    system = file_units(text, units)
    s, rho_unit, t_unit = system.stress, system.density, system.time
    found: list[dict[str, Any]] = []
    current: dict[str, Any] | None = None
    for keyword, params, rows, line in blocks(text):
        where = f"line {line}: *{keyword}"
        if keyword == "MATERIAL":
            name = params.get("NAME")
            if not name:
                raise InputError(f"{where}: NAME= is missing")
            current = {"name": name.lower(), "density_kg_m3": None, "material": None,
                       "prony": [], "line": line}
            found.append(current)
            continue
        if keyword not in _MATERIAL_OPTIONS:
            current = None  # any other keyword ends the material block
            continue
        if current is None:
            continue
        values = _floats(rows, where)
        if keyword == "DENSITY":
            if not values:
                raise InputError(f"{where} in material {current['name']!r}: no value")
            density = _si(values[0] / rho_unit)
            if not (np.isfinite(density) and density > 0):
                raise InputError(f"{where} in material {current['name']!r}: density_kg_m3 = "
                                 f"{density:g}: must be a finite number > 0 (kg/m^3)")
            current["density_kg_m3"] = density
        elif keyword == "HYPERELASTIC":
            kind = next((k for k in params if k in ("MOONEY-RIVLIN", "NEO HOOKE", "POLYNOMIAL",
                                                     "OGDEN", "ARRUDA-BOYCE", "VAN DER WAALS",
                                                     "YEOH", "REDUCED POLYNOMIAL", "MARLOW")),
                        "POLYNOMIAL")
            if kind == "POLYNOMIAL" and params.get("N", "1") != "1" or kind not in (
                    "MOONEY-RIVLIN", "NEO HOOKE", "POLYNOMIAL", "YEOH", "OGDEN"):
                raise InputError(f"{where}, {kind}: not supported (allowed MOONEY-RIVLIN, NEO "
                                 "HOOKE, POLYNOMIAL N=1, YEOH, OGDEN)")
            if "TEST DATA INPUT" in params:
                raise InputError(f"{where}: TEST DATA INPUT is not supported (give coefficients)")
            if kind == "NEO HOOKE":
                if len(values) < 2 or len(rows) > 1:
                    raise InputError(f"{where}: expected one row C10, D1 (no temperatures)")
                current["material"] = {"model": "neo_hookean", "c10_pa": _si(values[0] / s),
                                       "d1_per_pa": _si(values[1] * s)}
            elif kind == "YEOH":
                if not 1 <= len(values) <= 6 or len(rows) > 1:
                    raise InputError(f"{where}: expected one row C10, C20, C30, D1, D2, D3 (no "
                                     "temperatures)")
                c10, c20, c30, d1, d2, d3 = values + [0.0] * (6 - len(values))
                _higher_d_zero([d2, d3], where)
                current["material"] = {"model": "yeoh", "c10_pa": _si(c10 / s),
                                       "c20_pa": _si(c20 / s), "c30_pa": _si(c30 / s),
                                       "d1_per_pa": _si(d1 * s)}
            elif kind == "OGDEN":
                n = _order(params, where)
                if len(values) != 3 * n:
                    raise InputError(f"{where}, N={n}: expected {3 * n} values (mu_i, alpha_i, "
                                     f"then D_i; no temperatures), got {len(values)}")
                _higher_d_zero(values[2 * n + 1:], where)
                current["material"] = {
                    "model": "ogden", "d1_per_pa": _si(values[2 * n] * s),
                    "terms": [{"mu_pa": _si(values[2 * i] / s), "alpha": values[2 * i + 1]}
                              for i in range(n)]}
            else:
                if len(values) < 3 or len(rows) > 1:
                    raise InputError(f"{where}: expected one row C10, C01, D1 (no temperatures)")
                current["material"] = {"model": "mooney_rivlin", "c10_pa": _si(values[0] / s),
                                       "c01_pa": _si(values[1] / s), "d1_per_pa": _si(values[2] * s)}
            current["material"]["moduli"] = _moduli(params)
        elif keyword == "HYPERFOAM":
            n = _order(params, where)
            if len(values) < 3 * n:
                raise InputError(f"{where}, N={n}: expected {3 * n} values (mu_i, alpha_i, then "
                                 f"nu_i), got {len(values)}")
            terms = [{"mu_pa": _si(values[2 * i] / s), "alpha": values[2 * i + 1],
                      "nu": values[2 * n + i]} for i in range(n)]
            current["material"] = {"model": "ogden_hyperfoam", "terms": terms,
                                   "moduli": _moduli(params)}
        elif keyword == "ELASTIC":
            if params.get("TYPE", "ISOTROPIC").upper() != "ISOTROPIC" or len(rows) > 1 \
                    or len(values) < 2:
                raise InputError(f"{where}: only TYPE=ISOTROPIC with one row E, nu is supported")
            current["material"] = {"model": "linear_elastic", "youngs_modulus_pa": _si(values[0] / s),
                                   "poissons_ratio": values[1], "moduli": _moduli(params)}
        elif keyword == "VISCOELASTIC":
            if params.get("TIME", "").upper() != "PRONY":
                raise InputError(f"{where}: only TIME=PRONY is supported")
            for row in rows:
                g, k, tau = (_floats([row], where) + [0.0, 0.0, 0.0])[:3]
                current["prony"].append({"g": g, "k": k, "tau_s": _si(tau / t_unit)})
        else:
            warnings.warn(f"{where} in material {current['name']!r}: not read (no counterpart in "
                          "the ball specification)", InputWarning, stacklevel=2)
    out = []
    for item in found:
        material = item["material"]
        if material is None:
            raise InputError(f"line {item['line']}: material {item['name']!r} has no "
                             "*HYPERELASTIC, *HYPERFOAM or *ELASTIC card")
        if item["prony"]:
            prony = item["prony"]
            if material["model"] == "ogden_hyperfoam":  # relaxes as a whole with g
                prony = [{**t, "k": 0.0} for t in prony]
            material["prony"] = prony
        # every constant checked as in a ball file: finite, moduli > 0, 0 <= g < 1, tau > 0, ...
        material_from_dict(material, where=f"line {item['line']}: material {item['name']!r}")
        out.append({"name": item["name"], "density_kg_m3": item["density_kg_m3"],
                    "material": material})
    if not out:
        raise InputError("no *MATERIAL block found")
    return out


def read_ball(text: str, units: str | None = None, name: str = "imported") -> dict[str, Any]:
    """The ball specification of a deck written by `ballimpact export`: layers are the solid
    sections (element set -> material), each layer's outer radius the largest distance of its
    nodes from the ball's centre (the ball stands on its contact pole at the origin)."""
    system = file_units(text, units)
    materials = {m["name"]: m for m in read_materials(text, units)}
    nodes: dict[int, list[float]] = {}
    sets: dict[str, list[list[int]]] = {}
    sections: list[tuple[str, str]] = []
    for keyword, params, rows, line in blocks(text):
        try:
            if keyword == "NODE":
                for row in rows:
                    nodes[int(row[0])] = [float(v) for v in row[1:] if v != ""]
            elif keyword == "ELEMENT" and "ELSET" in params:
                sets.setdefault(params["ELSET"].lower(), []).extend(
                    [int(v) for v in row[1:] if v != ""] for row in rows)
            elif keyword == "SOLID SECTION" and params.get("ELSET", "").upper() != "PLANE":
                sections.append((params.get("ELSET", "").lower(),
                                 params.get("MATERIAL", "").lower()))
        except (ValueError, IndexError):
            raise InputError(f"line {line}: *{keyword}: expected rows of a label and numbers"
                             ) from None
    sections = [(elset, material) for elset, material in sections if elset in sets]
    if not nodes or not sections:
        raise InputError("no meshed solid sections: --ball reads decks written by ballimpact "
                         "export (use import-material for the materials alone)")
    index = {n: i for i, n in enumerate(nodes)}
    coords = np.array(list(nodes.values())) / system.length
    ball_nodes = sorted({index[n] for elset, _ in sections for conn in sets[elset] for n in conn})
    centre = np.zeros(coords.shape[1])
    centre[-1] = 0.5 * coords[ball_nodes, -1].max()  # the ball stands on its pole at 0
    layers = []
    for elset, material_name in sections:
        if material_name not in materials:
            raise InputError(f"solid section of {elset!r}: material {material_name!r} is not "
                             "defined")
        used = sorted({index[n] for conn in sets[elset] for n in conn})
        radius = _si(float(np.linalg.norm(coords[used] - centre, axis=1).max()))
        m = materials[material_name]
        if m["density_kg_m3"] is None:
            raise InputError(f"material {material_name!r} has no *DENSITY")
        layers.append({"name": elset, "outer_radius_m": radius,
                       "density_kg_m3": m["density_kg_m3"], "material": m["material"]})
    layers.sort(key=lambda layer: layer["outer_radius_m"])
    match = _BALL_LINE.search(text)
    return {"name": match.group(1).strip() if match else name, "layers": layers}


def read_abaqus_file(path, units: str | None = None, *, ball: bool = False,
                     allow=()) -> dict[str, Any]:
    """An ABAQUS input file read into our form (SI): {"materials": [...]} (`read_materials`,
    each material checked as a ball file's would be: `balls.checks.check_material_values`),
    or with `ball` {"ball": specification} of a deck written by `ballimpact export`
    (`read_ball`, named after the file, checked as any ball file: `fe.load_ball`). Errors
    (`InputError`) start with the file's name."""
    path, allow = Path(path), check_allow(allow)
    if path.is_dir():
        raise InputError(f"{path}: a folder, not an ABAQUS input file (.inp)")
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as error:
        raise InputError(f"{path}: cannot read ({error.strerror or error})") from None
    try:
        if ball:
            spec = read_ball(text, units, name=path.stem)
            load_ball(spec, allow=allow)  # the same checks as any ball file
            return {"ball": spec}
        materials = read_materials(text, units)
        for m in materials:
            material = material_from_dict(m["material"], where=f"material {m['name']!r}")
            check_material_values(m["name"], m["density_kg_m3"], material, allow)
        return {"materials": materials}
    except InputError as error:
        raise InputError(f"{path}: {error}") from None


def import_abaqus_file(path, units: str | None = None, *, ball: bool = False, allow=(),
                       out_path: Path | None = None) -> dict[str, Any]:
    """`ballimpact import-material`: `read_abaqus_file`, and with `out_path` its JSON
    (`imported_json`) written there. Returns what `read_abaqus_file` returns. Raises
    `InputError` naming --out when its folder does not exist (before reading anything) or it
    cannot be written, and what `read_abaqus_file` raises."""
    check_allow(allow)
    check_output_folder(out_path, "--out")
    out = read_abaqus_file(path, units, ball=ball, allow=allow)
    if out_path is not None:
        try:
            write_atomic(Path(out_path), imported_json(out) + "\n")
        except OSError as error:
            raise InputError(f"--out: cannot write {out_path} ({error.strerror or error})") \
                from None
    return out


def imported_json(result: dict[str, Any]) -> str:
    """The JSON text of an import (`import_abaqus_file`): the ball specification of a deck read
    as a ball, else the materials."""
    return json.dumps(result.get("ball", result), indent=2)
