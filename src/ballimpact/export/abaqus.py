"""ABAQUS/Explicit and CalculiX input decks (flat format: no parts or assemblies, which both read).

A complete deck is the ball hitting a rigid plane: mesh, one element set, section and material
per layer, the initial velocity, the plane, contact, the step and output requests (the plane's
reaction force, i.e. the contact force, and the energies). `ball_only` writes the ball alone
(mesh, sets, sections, materials) for inclusion in a larger model (`*INCLUDE`).

- ABAQUS: CAX4R or C3D8R, a rigid plane of RAX2 or R3D4 elements on a fixed reference node,
  its positive side (SPOS) toward the ball (RAX2: the normal is the direction from node 1 to
  node 2 turned 90 degrees counter-clockwise; R3D4: the right-hand rule), penalty contact pair
  with Coulomb friction, `*DYNAMIC, EXPLICIT` with the bulk viscosity we use (0.06, 1.2).
- CalculiX (ccx 2.20): C3D8 ball; the plane is one layer of C3D8 elements with every node fixed,
  surface-to-surface penalty contact, implicit `*DYNAMIC, DIRECT` with fixed increments.
  CalculiX loses initial velocities on axisymmetric elements (they are expanded to 3D), so an
  axisymmetric CalculiX deck is ball-only.
"""

from __future__ import annotations

import math

import numpy as np

from .. import __version__
from ..balls.ball import BallModel
from .geometry import HEX_FACES, QUAD_FACES, BallGeometry
from .materials import ExportError, abaqus_material, number
from .setup import ImpactSetup, layer_labels
from .units import UnitSystem

#: CalculiX contact: pressure-overclosure slope = this x the wave modulus / the smallest surface
#: element edge (stiff enough that the overclosure is ~1% of the ball's compression)
CALCULIX_PENALTY = 10.0
#: CalculiX increments per estimated contact time
CALCULIX_INCREMENTS_PER_CONTACT = 100
#: output requests per step (history) and field frames per step
HISTORY_POINTS, FIELD_FRAMES = 500, 50


def _id_lines(ids, per_line: int = 16) -> list[str]:
    ids = [str(i) for i in ids]
    return [", ".join(ids[i:i + per_line]) for i in range(0, len(ids), per_line)]


def _coords(p: np.ndarray, scale: float) -> str:
    return ", ".join(f"{float(v) * scale:.15g}" for v in p)  # full precision: radii read back


def _smallest_surface_edge_m(geom: BallGeometry) -> float:
    faces = QUAD_FACES if geom.dimension == 2 else HEX_FACES
    lengths = []
    for e, f in geom.surface_faces:
        corners = geom.nodes_m[geom.elements[e, list(faces[f - 1])]]
        lengths.append(np.linalg.norm(corners - np.roll(corners, 1, axis=0), axis=1).min())
    return float(min(lengths))


def write_deck(ball: BallModel, geom: BallGeometry, units: UnitSystem, code: str = "abaqus",
               setup: ImpactSetup | None = None, ball_only: bool = False,
               moduli: str | None = None) -> tuple[str, list[str]]:
    """The deck's text and the notes it carries (also for stderr). `code`: abaqus or calculix;
    `moduli`: the elastic ball CalculiX gets for a viscoelastic one (default the material's)."""
    calculix = code == "calculix"
    two_d = geom.dimension == 2
    if calculix and two_d and not ball_only:
        raise ExportError("calculix: CalculiX 2.20 drops initial velocities on axisymmetric "
                          "elements (it expands them to 3D), so an axisymmetric impact deck "
                          "would not move; use --solver 3d, or --ball-only for the mesh and "
                          "materials")
    L = units.length
    element_type = ("CAX4" if calculix else "CAX4R") if two_d else ("C3D8" if calculix else "C3D8R")
    names = layer_labels(ball)
    notes: list[str] = []
    material_cards = []
    for layer, name in zip(ball.layers, names):
        cards = abaqus_material(name, layer.density_kg_m3, layer.material, units, code, moduli)
        material_cards.append(cards)
        notes += cards.notes
    if geom.half:
        notes.append("half model (y >= 0, symmetry on y = 0): reaction forces and energies are "
                     "half the ball's")

    out = ["*HEADING", f"ballimpact {__version__} {'ball' if ball_only else 'impact'}: "
           f"{ball.name}" + ("" if ball_only else f" at {setup.speed_m_s:g} m/s")]
    out += [f"** written by ballimpact {__version__} for {'CalculiX' if calculix else 'ABAQUS'}",
            f"** {units.header()}",
            f"** ballimpact ball: {ball.name}",
            f"** mesh: {geom.solver}, {len(geom.nodes_m)} nodes, {len(geom.elements)} "
            f"{element_type} elements, mesh mass {geom.mass_kg(ball):.6g} kg "
            f"(ball {ball.mass_kg:.6g} kg)",
            "** layers (centre out): " + ", ".join(
                f"{n} r={layer.outer_radius_m:g} m" for n, layer in zip(names, ball.layers))]
    if not ball_only:
        out += [f"** impact: {setup.speed_m_s:g} m/s at {setup.angle_deg:g} deg from the normal, "
                f"friction {setup.friction:g}, step {setup.step_time(ball):.6g} s",
                "** contact force: the plane's reaction force (" +
                ("sum over the fixed plane nodes" if calculix else "reference node PLANE_REF") +
                ")"]
    out += [f"** note: {note}" for note in notes]

    # one *NODE block for the whole model (meshio's reader keeps only the last block)
    n_ball = len(geom.nodes_m)
    plane_nodes = ([] if ball_only else
                   (_calculix_plane_nodes if calculix else _abaqus_plane_nodes)(ball, geom, setup))
    out.append("*NODE")
    out += [f"{i}, {_coords(p, L)}" for i, p in
            enumerate([*geom.nodes_m, *plane_nodes], start=1)]
    out += ["*NSET, NSET=BALL_NODES, GENERATE", f"1, {n_ball}, 1"]
    if not ball_only:
        first = n_ball + (1 if calculix else 2)
        if not calculix:
            out += ["*NSET, NSET=PLANE_REF", str(n_ball + 1)]
        out += ["*NSET, NSET=PLANE_NODES, GENERATE", f"{first}, {n_ball + len(plane_nodes)}, 1"]
    for k, name in enumerate(names):
        ids = np.flatnonzero(geom.element_layer == k)
        out.append(f"*ELEMENT, TYPE={element_type}, ELSET={name}")
        out += [f"{e + 1}, " + ", ".join(str(n + 1) for n in geom.elements[e]) for e in ids]
    out += ["*ELSET, ELSET=BALL_ELEMENTS", *_id_lines(names, 8)]
    out.append("*SURFACE, TYPE=ELEMENT, NAME=BALL_SURFACE")
    out += [f"{e + 1}, S{f}" for e, f in geom.surface_faces]
    if two_d:
        out += ["*NSET, NSET=AXIS", *_id_lines(geom.axis_nodes + 1)]
    if geom.half:
        out += ["*NSET, NSET=SYMMETRY", *_id_lines(geom.symmetry_nodes + 1)]
    for name in names:
        out.append(f"*SOLID SECTION, ELSET={name}, MATERIAL={name}")
    for cards in material_cards:
        out += cards.lines
    boundary = []
    if two_d:
        boundary.append("AXIS, 1, 1")
    if geom.half:
        boundary.append("SYMMETRY, 2, 2")
    if not ball_only:
        out += (_calculix_plane(ball, geom, units, setup) if calculix
                else _abaqus_plane(ball, geom, setup))
        boundary.append("PLANE_NODES, 1, 3" if calculix else "PLANE_REF, ENCASTRE")
    if boundary:
        out += ["*BOUNDARY", *boundary]
    if ball_only:
        return "\n".join(out) + "\n", notes
    out.append("*INITIAL CONDITIONS, TYPE=VELOCITY")
    v = setup.velocity_m_s(geom.dimension)
    out += [f"BALL_NODES, {i + 1}, {number(c * units.velocity)}" for i, c in enumerate(v) if c]
    out += (_calculix_step(ball, geom, units, setup) if calculix
            else _abaqus_step(ball, geom, units, setup))
    return "\n".join(out) + "\n", notes


def _plane_extent_m(ball: BallModel, setup: ImpactSetup) -> tuple[float, float]:
    """x range of the plane: the contact patch and the ball's travel along it during the step."""
    r = ball.outer_radius_m
    travel = setup.speed_m_s * math.sin(math.radians(setup.angle_deg)) * setup.step_time(ball)
    return -1.2 * r, 1.2 * r + travel


def _abaqus_plane_nodes(ball, geom, setup) -> list[np.ndarray]:
    """The reference node (origin), then the plane's corners (normal toward the ball)."""
    r = ball.outer_radius_m
    if geom.dimension == 2:  # node 1 at the axis, node 2 out along +x: normal +y
        return [np.zeros(2), np.zeros(2), np.array([1.5 * r, 0.0])]
    x0, x1 = _plane_extent_m(ball, setup)
    return [np.zeros(3)] + [np.array([x, y, 0.0]) for x, y in
                            ((x0, -1.2 * r), (x1, -1.2 * r), (x1, 1.2 * r), (x0, 1.2 * r))]


def _abaqus_plane(ball, geom, setup) -> list[str]:
    n = len(geom.nodes_m)
    corners = ", ".join(str(n + 2 + i) for i in range(2 if geom.dimension == 2 else 4))
    kind = "RAX2" if geom.dimension == 2 else "R3D4"
    return [f"*ELEMENT, TYPE={kind}, ELSET=PLANE", f"{len(geom.elements) + 1}, {corners}",
            f"*RIGID BODY, REF NODE={n + 1}, ELSET=PLANE",
            "*SURFACE, TYPE=ELEMENT, NAME=PLANE_SURFACE", "PLANE, SPOS",
            "*SURFACE INTERACTION, NAME=BALL_PLANE", "*FRICTION", number(setup.friction)]


def _abaqus_step(ball, geom, units, setup) -> list[str]:
    t = setup.step_time(ball) * units.time
    rf = "RF1, RF2" if geom.dimension == 2 else "RF1, RF2, RF3"
    return ["*STEP, NAME=IMPACT, NLGEOM=YES", "*DYNAMIC, EXPLICIT", f", {number(t)}",
            "*BULK VISCOSITY", "0.06, 1.2",
            "*CONTACT PAIR, INTERACTION=BALL_PLANE, MECHANICAL CONSTRAINT=PENALTY",
            "BALL_SURFACE, PLANE_SURFACE",
            f"*OUTPUT, HISTORY, TIME INTERVAL={number(t / HISTORY_POINTS)}",
            "*NODE OUTPUT, NSET=PLANE_REF", rf,
            "*ENERGY OUTPUT", "ALLKE, ALLSE, ALLIE, ALLVD, ALLAE, ALLCD, ALLFD, ETOTAL",
            f"*OUTPUT, FIELD, NUMBER INTERVAL={FIELD_FRAMES}",
            "*NODE OUTPUT", "U, V", "*ELEMENT OUTPUT", "S, LE",
            "*END STEP"]


def _calculix_grid(ball, geom, setup) -> tuple[np.ndarray, np.ndarray, float]:
    """x and y lines of the plane's slab (about R/6 apart) and its thickness (m)."""
    r = ball.outer_radius_m
    x0, x1 = _plane_extent_m(ball, setup)
    y0 = 0.0 if geom.half else -1.2 * r
    xs = np.linspace(x0, x1, max(2, round((x1 - x0) / (r / 6))) + 1)
    ys = np.linspace(y0, 1.2 * r, max(2, round((1.2 * r - y0) / (r / 6))) + 1)
    return xs, ys, r / 6


def _calculix_plane_nodes(ball, geom, setup) -> list[np.ndarray]:
    xs, ys, thickness = _calculix_grid(ball, geom, setup)
    return [np.array([x, y, z]) for z in (-thickness, 0.0) for y in ys for x in xs]


def _calculix_plane(ball, geom, units, setup) -> list[str]:
    """One layer of fixed C3D8 elements under the ball, top face z = 0."""
    n, m = len(geom.nodes_m), len(geom.elements)
    xs, ys, _ = _calculix_grid(ball, geom, setup)
    ids = (n + 1 + np.arange(2 * len(ys) * len(xs))).reshape(2, len(ys), len(xs))
    out = ["*ELEMENT, TYPE=C3D8, ELSET=PLANE"]
    e = m
    for j in range(len(ys) - 1):
        for i in range(len(xs) - 1):
            e += 1
            bottom = [ids[0, j, i], ids[0, j, i + 1], ids[0, j + 1, i + 1], ids[0, j + 1, i]]
            top = [ids[1, j, i], ids[1, j, i + 1], ids[1, j + 1, i + 1], ids[1, j + 1, i]]
            out.append(f"{e}, " + ", ".join(str(v) for v in bottom + top))
    wave = max(layer.material.wave_modulus_pa() for layer in ball.layers)
    density = ball.layers[-1].density_kg_m3
    e_plane = ball.layers[-1].material.shear_modulus_pa() * 3.0  # fixed: only sets the increment
    slope = CALCULIX_PENALTY * wave / _smallest_surface_edge_m(geom) * units.stress / units.length
    out += ["*SURFACE, TYPE=ELEMENT, NAME=PLANE_SURFACE", "PLANE, S2",
            "*MATERIAL, NAME=PLANE", "*ELASTIC", f"{number(e_plane * units.stress)}, 0.3",
            "*DENSITY", number(density * units.density),
            "*SOLID SECTION, ELSET=PLANE, MATERIAL=PLANE",
            "*SURFACE INTERACTION, NAME=BALL_PLANE",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            f"{number(slope)}, {number(1e-3 * wave * units.stress)}"]
    if setup.friction > 0.0:
        out += ["*FRICTION", f"{number(setup.friction)}, {number(slope)}"]
    out += ["*CONTACT PAIR, INTERACTION=BALL_PLANE, TYPE=SURFACE TO SURFACE",
            "BALL_SURFACE, PLANE_SURFACE"]
    return out


def _calculix_step(ball, geom, units, setup) -> list[str]:
    t = setup.step_time(ball)
    dt = setup.contact_time_estimate_s(ball) / CALCULIX_INCREMENTS_PER_CONTACT
    n_inc = math.ceil(t / dt)
    dt = t / n_inc
    frames = max(1, n_inc // FIELD_FRAMES)
    T = units.time
    return ["*STEP, NLGEOM, INC=1000000", "*DYNAMIC, DIRECT",
            f"{number(dt * T)}, {number(t * T)}, {number(dt * T * 1e-3)}, {number(dt * T)}",
            f"*NODE FILE, FREQUENCY={frames}", "U, V",
            f"*EL FILE, FREQUENCY={frames}", "S",
            "** .dat every increment (after the .frd requests: ccx applies the last FREQUENCY)",
            "*NODE PRINT, NSET=PLANE_NODES, TOTALS=ONLY, FREQUENCY=1", "RF",
            "*EL PRINT, ELSET=BALL_ELEMENTS, TOTALS=ONLY, FREQUENCY=1", "ELKE, ELSE",
            "*END STEP"]
