"""The gripping regime of oblique impacts: the 3D FE solver against the elastic-sphere theory with
tangential compliance (Maw, Barber & Fawcett; `oblique.elastic_reference`).

A homogeneous elastic sphere (the cricket ball's size, 800 kg/m^3, E 100 MPa) on a rigid plane,
the incidence set by the tangential speed at a held normal speed: 0.25 m/s for the comparison
(Hertz contact radius 2.5 mm, a / R = 0.069: the theory is the small-contact limit) with friction
0.5 (above the coupling of normal pressure and tangential displacement, see `diagnosis`) and a
contact penalty 3 times the default (see `penalty`), and the softer 2 m/s impact (a / R = 0.164)
of the first probes for the diagnosis. Parts:

- `sweep`: Poisson's ratio 0.23 and 0.45, Psi 0.5 to 10: FE tangential COR (centre) against the
  reference, the rebound spin's relative error, the contact point's COR;
- `convergence`: the same at Psi 1 and 3 on three meshes (2, 2.9 and 4.3 elements across the
  Hertz radius);
- with `--slab`, `sweep` and `convergence` run on a slab of the sphere's own material instead of
  the rigid plane: Dundurs' beta = 0, where the theory's uncoupled contact is exact (the rigid
  plane couples normal pressure and tangential displacement, beta 0.35 for nu 0.23);
- `penalty`: Psi 0.5 on the sweep's mesh with the normal penalty scaled 1 to 16: the penalty's
  normal compliance against the mesh's tangential stiffness;
- `defaults`: Psi 0.5, 1 and 3 with `Options3D()` (the mesh and penalty chosen from the
  contact) against the defaults before (grading 2, penalty 1);
- `diagnosis`: what moves the FE result at Psi 0.5 and 2 (nu 0.23): friction (the coupling of
  normal pressure and tangential displacement), the stick spring, the normal penalty, the time
  step, the hourglass stiffness, the integration and a target of the ball's own material.

Prints one JSON object (and each run's row on stderr as it ends); `--plot` writes the sweep's
plot. Each run is made alone: on a CPU that is faster than a vmapped batch (docs/oblique.md,
"Cost"), and a run does not depend on its batch.

    python examples/oblique_gripping.py --part sweep --part convergence --part penalty \
        --plot docs/oblique-gripping.png
    python examples/oblique_gripping.py --slab --part sweep --part convergence \
        --plot docs/oblique-gripping.png
    python examples/oblique_gripping.py --part diagnosis
    python examples/oblique_gripping.py --part defaults
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
import time

import numpy as np

from ballimpact.balls.ball import BallModel, Layer
from ballimpact.fe.estimates import hertz_contact_radius_m
from ballimpact.constitutive import material_from_dict
from ballimpact.fe import Hexahedral, simulate_batch
from ballimpact.oblique import ImpactCondition, Options3D
from ballimpact.oblique.elastic_reference import ElasticSphere, oblique_impact
from ballimpact.fe.hex.target import Target, TargetLayer

RADIUS_M, DENSITY_KG_M3, YOUNGS_PA = 0.036, 800.0, 100e6
NORMAL_SPEED_M_S, DIAGNOSIS_NORMAL_SPEED_M_S = 0.25, 2.0
FRICTION = 0.5
PSI = (0.5, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0)
#: normal penalty over the default: at the default the penalty's normal compliance leaves the
#: small contact's tangential response too soft, at 8 and more the mesh's own tangential
#: stiffness makes it too stiff; 3 balances the two (`part_penalty`)
PENALTY_SCALE = 3.0
PENALTY_SCALES = (1.0, 2.0, 3.0, 4.0, 8.0, 16.0)
#: the sweep's mesh: 16 divisions graded so that 2.9 elements span the Hertz radius
MESH = Options3D(divisions=16, contact_elements=2.9, penalty_scale=PENALTY_SCALE)
#: the convergence study's elements across the Hertz radius (16 divisions); the sweep's mesh is
#: the middle one (its runs at Psi 1 and 3 are reused when the sweep ran first)
ACROSS = (2.0, 2.9, 4.3)
#: `--slab`: the same-material slab's cells through its depth grow by this from the pole spacing
SLAB_DEPTH_GROWTH = 1.15


def sphere(nu: float) -> BallModel:
    material = {"model": "linear_elastic", "youngs_modulus_pa": YOUNGS_PA, "poissons_ratio": nu}
    return BallModel(f"elastic sphere nu {nu:g}",
                     (Layer("sphere", RADIUS_M, DENSITY_KG_M3, material_from_dict(material)),))


def conditions(psi_values, friction: float, normal_speed: float) -> list[ImpactCondition]:
    """Normal speed held (m/s); tan(theta) = Psi mu (1 + e_n) / 2 with e_n = 1."""
    out = []
    for psi in psi_values:
        theta = math.atan(psi * friction)
        out.append(ImpactCondition(normal_speed / math.cos(theta), math.degrees(theta), 0.0,
                                   friction))
    return out


def compare(ball: BallModel, nu: float, results, same_material_plane: bool = False) -> list[dict]:
    """Each FE run against the reference at its own condition (on a rigid plane, or on a
    half-space of the ball's material)."""
    plane = dict(plane_youngs_modulus_pa=YOUNGS_PA, plane_poissons_ratio=nu) \
        if same_material_plane else {}
    ref_sphere = ElasticSphere(RADIUS_M, ball.mass_kg, YOUNGS_PA, nu, **plane)
    rows = []
    for r in results:
        c = r.condition
        theta = math.radians(c.angle_deg)
        v_n, v_x = c.speed_m_s * math.cos(theta), c.speed_m_s * math.sin(theta)
        ref = oblique_impact(ref_sphere, v_n, v_x, 0.0, c.friction)
        rows.append({
            "psi": float(ref["psi"][0]), "angle_deg": c.angle_deg, "friction": c.friction,
            "fe_tangential_cor": r.tangential_cor,
            "reference_tangential_cor": float(ref["tangential_cor"][0]),
            "tangential_cor_error": r.tangential_cor - float(ref["tangential_cor"][0]),
            "fe_spin_rad_s": r.rebound_spin_rad_s,
            "reference_spin_rad_s": float(ref["spin_rad_s"][0]),
            "spin_relative_error": r.rebound_spin_rad_s / float(ref["spin_rad_s"][0]) - 1.0,
            "fe_contact_point_cor": r.contact_point_tangential_cor,
            "reference_contact_point_cor": float(ref["contact_point_cor"][0]),
            "fe_normal_cor": r.normal_cor, "energy_balance_error": r.energy_balance_error,
            "contact_radius_over_radius": hertz_contact_radius_m(ball, v_n) / RADIUS_M,
            "slipping_load_fraction_at_peak_force": float(r.history["slipping_load_fraction"][
                int(np.argmax(r.history["contact_force_n"]))]),
            "elements": r.elements, "pole_grading": r.pole_grading,
            "pole_spacing_m": r.pole_spacing_m, "steps": r.steps})
    return rows


_DONE: dict = {}  # (nu, options, friction, target, speed) -> {psi: (result, row)}: this process' runs


def run(nu: float, psi_values, options: Options3D = MESH, friction: float = FRICTION,
        target=None, label: str = "", normal_speed: float = NORMAL_SPEED_M_S
        ) -> tuple[list, list[dict]]:
    """FE runs of the sphere at these Psi, one at a time, each compared with the reference; runs
    made before in this process are reused (results, rows). Each row goes to stderr as one JSON
    line as soon as it exists."""
    key = (nu, options, friction, None if target is None else target.name, normal_speed)
    done = _DONE.setdefault(key, {})
    ball = sphere(nu)
    for psi in psi_values:
        if psi in done:
            continue
        started = time.perf_counter()
        (result,) = simulate_batch(ball, conditions([psi], friction, normal_speed),
                                   geometry=Hexahedral(options), target=target)
        (row,) = compare(ball, nu, [result], same_material_plane=target is not None)
        row["wall_time_s"] = time.perf_counter() - started
        done[psi] = (result, row)
        print(json.dumps({"case": label or f"nu {nu:g}", **row}), file=sys.stderr, flush=True)
    return [done[psi][0] for psi in psi_values], [done[psi][1] for psi in psi_values]


def matched_slab(nu: float) -> Target:
    """A slab of the sphere's own material (Dundurs' beta = 0: the theory's uncoupled contact is
    exact), 0.06 m half width (about 20 contact radii) and 0.04 m thick on a fixed base."""
    material = material_from_dict({"model": "linear_elastic", "youngs_modulus_pa": YOUNGS_PA,
                                   "poissons_ratio": nu})
    return Target(f"same material nu {nu:g}, 0.06 x 0.04 m", 0.06,
                  (TargetLayer("slab", 0.04, DENSITY_KG_M3, material),))


def setting(nu: float, on_slab: bool, across: float = 2.9) -> tuple[Options3D, Target | None]:
    """The sweep's mesh with `across` elements across the rigid plane's Hertz radius, on the
    rigid plane or on `matched_slab` (cells matched to the ball's at the contact:
    `SLAB_DEPTH_GROWTH`)."""
    options = dataclasses.replace(MESH, contact_elements=across)
    if not on_slab:
        return options, None
    return dataclasses.replace(options, slab_depth_growth=SLAB_DEPTH_GROWTH), matched_slab(nu)


def part_sweep(plot, on_slab: bool = False) -> dict:
    out = {}
    all_results = []
    where = "on a slab of its own material" if on_slab else "on the rigid plane"
    for nu in (0.23, 0.45):
        options, target = setting(nu, on_slab)
        results, rows = run(nu, PSI, options, target=target, label=f"nu {nu:g} {where}")
        all_results.append((nu, results))
        out[f"nu_{nu:g}"] = {
            "rows": rows,
            "max_abs_tangential_cor_error": max(abs(r["tangential_cor_error"]) for r in rows),
            "max_abs_spin_relative_error": max(abs(r["spin_relative_error"]) for r in rows),
            "reversal_agrees": all((r["fe_contact_point_cor"] > 0)
                                   == (r["reference_contact_point_cor"] > 0) for r in rows)}
    if plot:
        from ballimpact.oblique.elastic_reference import normalised_curves
        from ballimpact.oblique.plots import plot_gripping

        for nu, results in all_results:
            grid = np.linspace(0.05, 12.0, 200)
            path = str(plot).replace(".png", f"{'-slab' if on_slab else ''}-nu{nu:g}.png")
            surface = ("slab of its own material 0.06 x 0.04 m" if on_slab else "rigid plane")
            plot_gripping(results, path, reference=normalised_curves(grid, nu),
                          poissons_ratio=nu,
                          title=f"elastic sphere E 100 MPa, nu {nu:g}, v_n "
                                f"{NORMAL_SPEED_M_S:g} m/s, mu {FRICTION:g}, {surface}; 3D FE "
                                f"{results[0].elements} hexahedra (half model), penalty "
                                f"x{PENALTY_SCALE:g}")
            out[f"nu_{nu:g}"]["plot"] = path
    return out


def part_convergence(on_slab: bool = False) -> dict:
    """Psi 1 and 3 with each of `ACROSS` elements across the Hertz radius."""
    out = {}
    for nu in (0.23, 0.45):
        for across in ACROSS:
            options, target = setting(nu, on_slab, across)
            _, rows = run(nu, (1.0, 3.0), options, target=target,
                          label=f"nu {nu:g}, {across:g} across{', slab' if on_slab else ''}")
            out[f"nu_{nu:g}_{across:g}_across"] = rows
    return out


def part_penalty() -> dict:
    """Psi 0.5 on the sweep's mesh with each of `PENALTY_SCALES`."""
    out = {}
    for nu in (0.23, 0.45):
        for scale in PENALTY_SCALES:
            options = dataclasses.replace(MESH, penalty_scale=scale)
            _, rows = run(nu, (0.5,), options, label=f"nu {nu:g}, penalty scale {scale:g}")
            out[f"nu_{nu:g}_penalty_{scale:g}"] = rows[0]
    return out


#: the 3D defaults before they were chosen from the contact (grading 2, penalty 1)
DEFAULTS_BEFORE = Options3D(divisions=16, pole_grading=2.0, penalty_scale=1.0)


def part_defaults() -> dict:
    """Psi 0.5, 1 and 3 with `Options3D()` (mesh and penalty chosen from the contact), and Psi
    0.5 and 1 with the defaults before (`DEFAULTS_BEFORE`)."""
    out = {}
    for nu in (0.23, 0.45):
        for label, options, psi in (("now", Options3D(), (0.5, 1.0, 3.0)),
                                    ("before", DEFAULTS_BEFORE, (0.5, 1.0))):
            results, rows = run(nu, psi, options, label=f"nu {nu:g}, defaults {label}")
            for result, row in zip(results, rows):
                out[f"nu_{nu:g}_psi_{row['psi']:.2g}_{label}"] = {
                    **row, "penalty_scale": result.penalty_scale}
    return out


def same_material_slab(nu: float) -> Target:
    material = material_from_dict({"model": "linear_elastic", "youngs_modulus_pa": YOUNGS_PA,
                                   "poissons_ratio": nu})
    return Target("same material", 0.12, (TargetLayer("slab", 0.08, DENSITY_KG_M3, material),))


#: the diagnosis' mesh: 16 divisions and pole grading 2 (2.4 elements across the Hertz radius at
#: 2 m/s) with the default penalty, the defaults before they were chosen from the contact
DIAGNOSIS_MESH = Options3D(divisions=16, pole_grading=2.0, penalty_scale=1.0)


def part_diagnosis(extended: bool = False) -> dict:
    """Each suspect at Psi 0.5 and 2 on the 2 m/s impact of the first probes (a / R = 0.164)."""
    psi = (0.5, 2.0)
    cases = {  # name: (Poisson's ratio, option changes, friction, target)
        "nu 0.23, mu 0.1": (0.23, {}, 0.1, None),
        "nu 0.23, mu 0.5": (0.23, {}, 0.5, None),
        "nu 0.23, mu 0.1, on a slab of the ball's material": (0.23, {}, 0.1,
                                                               same_material_slab(0.23)),
        "nu 0.45, mu 0.1": (0.45, {}, 0.1, None),
        "nu 0.45, mu 0.5": (0.45, {}, 0.5, None)}
    if extended:  # the other suspects (about 15 min more on 2 cores)
        cases.update({
            "nu 0.45, mu 0.5, stick_scale 2": (0.45, {"stick_scale": 2.0}, 0.5, None),
            "nu 0.45, mu 0.5, stick_scale 32": (0.45, {"stick_scale": 32.0}, 0.5, None),
            "nu 0.45, mu 0.5, penalty_scale 2": (0.45, {"penalty_scale": 2.0}, 0.5, None),
            "nu 0.45, mu 0.5, time_step_scale 0.4": (0.45, {"time_step_scale": 0.4}, 0.5,
                                                     None),
            "nu 0.45, mu 0.5, hourglass_scale 0.2": (0.45, {"hourglass_scale": 0.2}, 0.5,
                                                     None),
            "nu 0.45, mu 0.5, integration full": (0.45, {"integration": "full"}, 0.5, None),
            "nu 0.45, mu 0.5, contact_elements 4.3": (0.45, {"contact_elements": 4.3}, 0.5,
                                                      None)})
    out = {}
    for name, (nu, changes, friction, target) in cases.items():
        options = dataclasses.replace(DIAGNOSIS_MESH, **changes)
        _, rows = run(nu, psi, options, friction, target, label=name,
                      normal_speed=DIAGNOSIS_NORMAL_SPEED_M_S)
        out[name] = rows
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", action="append",
                        choices=("sweep", "convergence", "penalty", "diagnosis", "defaults"),
                        help="the parts to run (repeatable; default: sweep)")
    parser.add_argument("--plot", help="PNG of the sweep (one per Poisson's ratio: -nu0.23.png)")
    parser.add_argument("--slab", action="store_true",
                        help="sweep and convergence on a slab of the sphere's own material "
                             "(Dundurs' beta = 0) instead of the rigid plane")
    parser.add_argument("--all-suspects", action="store_true",
                        help="diagnosis: also the stick spring, penalty, time step, hourglass "
                             "control, full integration and a finer contact")
    args = parser.parse_args()
    started = time.perf_counter()
    out: dict = {"friction": FRICTION, "normal_speed_m_s": NORMAL_SPEED_M_S,
                 "youngs_modulus_pa": YOUNGS_PA, "penalty_scale": PENALTY_SCALE,
                 "surface": "same-material slab" if args.slab else "rigid plane"}
    parts = args.part or ["sweep"]
    if "sweep" in parts:
        out["sweep"] = part_sweep(args.plot, args.slab)
    if "convergence" in parts:
        out["convergence"] = part_convergence(args.slab)
    if "penalty" in parts:
        out["penalty"] = part_penalty()
    if "defaults" in parts:
        out["defaults"] = part_defaults()
    if "diagnosis" in parts:
        out["diagnosis"] = part_diagnosis(args.all_suspects)
    out["wall_time_s"] = time.perf_counter() - started
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
