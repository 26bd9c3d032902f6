"""The gripping regime of oblique impacts: the 3D FE solver against the elastic-sphere theory with
tangential compliance (Maw, Barber & Fawcett; `oblique.elastic_reference`).

A homogeneous elastic sphere (the cricket ball's size, 800 kg/m^3, E 100 MPa) at a normal speed
of 2 m/s on a rigid plane, the incidence set by the tangential speed. Parts:

- `sweep`: Poisson's ratio 0.23 and 0.45, Psi 0.5 to 10, one batch per ratio: FE tangential COR
  (centre) against the reference, the rebound spin's relative error, the contact point's COR;
- `convergence`: the same at Psi 1 and 3 on three meshes;
- `diagnosis`: what moves the FE result at Psi 0.5 and 2 (nu 0.23): friction (the coupling of
  normal pressure and tangential displacement), the stick spring, the normal penalty, the time
  step, the hourglass stiffness, the integration and a target of the ball's own material.

Prints one JSON object; `--plot` writes the sweep's plot.

    python examples/oblique_gripping.py --part sweep --plot docs/oblique-gripping.png
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
import time

import numpy as np

from ballimpact.fe.ball import BallModel, Layer
from ballimpact.fe.materials import material_from_dict
from ballimpact.oblique import ImpactCondition, Options3D, simulate_oblique_batch
from ballimpact.oblique.elastic_reference import ElasticSphere, oblique_impact
from ballimpact.oblique.target import Target, TargetLayer

RADIUS_M, DENSITY_KG_M3, YOUNGS_PA, NORMAL_SPEED_M_S = 0.036, 800.0, 100e6, 2.0
FRICTION = 0.5
PSI = (0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 7.0, 10.0)
#: the sweep's mesh: 16 divisions graded so that 4 elements span the Hertz radius
MESH = Options3D(divisions=16, contact_elements=4.0)
#: the convergence study's meshes (divisions, elements across the Hertz radius)
MESHES = ((12, 2.5), (16, 4.0), (24, 6.0))


def sphere(nu: float) -> BallModel:
    material = {"model": "linear_elastic", "youngs_modulus_pa": YOUNGS_PA, "poissons_ratio": nu}
    return BallModel(f"elastic sphere nu {nu:g}",
                     (Layer("sphere", RADIUS_M, DENSITY_KG_M3, material_from_dict(material)),))


def conditions(psi_values, friction: float) -> list[ImpactCondition]:
    """Normal speed held at NORMAL_SPEED_M_S; tan(theta) = Psi mu (1 + e_n) / 2 with e_n = 1."""
    out = []
    for psi in psi_values:
        theta = math.atan(psi * friction)
        out.append(ImpactCondition(NORMAL_SPEED_M_S / math.cos(theta), math.degrees(theta), 0.0,
                                   friction))
    return out


def compare(ball: BallModel, nu: float, results) -> list[dict]:
    """Each FE run against the reference at its own condition."""
    ref_sphere = ElasticSphere(RADIUS_M, ball.mass_kg, YOUNGS_PA, nu)
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
            "peak_slipping_load_fraction": float(np.max(r.history["slipping_load_fraction"])),
            "elements": r.elements, "pole_grading": r.pole_grading,
            "pole_spacing_m": r.pole_spacing_m, "steps": r.steps})
    return rows


def run(nu: float, psi_values, options: Options3D = MESH, friction: float = FRICTION,
        target=None, label: str = "") -> tuple[list, list[dict]]:
    ball = sphere(nu)
    started = time.perf_counter()
    results = simulate_oblique_batch(ball, conditions(psi_values, friction), options, target)
    wall = time.perf_counter() - started
    rows = compare(ball, nu, results)
    for row in rows:
        row["wall_time_s_batch"] = wall
    print(f"  {label or f'nu {nu:g}'}: {len(rows)} runs, {wall:.1f} s", file=sys.stderr,
          flush=True)
    return results, rows


def part_sweep(plot) -> dict:
    out = {}
    all_results = []
    for nu in (0.23, 0.45):
        results, rows = run(nu, PSI)
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
            path = str(plot).replace(".png", f"-nu{nu:g}.png")
            plot_gripping(results, path, reference={**normalised_curves(grid, nu),
                                                     "poissons_ratio": nu},
                          title=f"elastic sphere E 100 MPa, nu {nu:g}, v_n 2 m/s, mu "
                                f"{FRICTION:g}, rigid plane; 3D FE {results[0].elements} "
                                "hexahedra (half model)")
            out[f"nu_{nu:g}"]["plot"] = path
    return out


def part_convergence() -> dict:
    out = {}
    for nu in (0.23, 0.45):
        for divisions, across in MESHES:
            options = Options3D(divisions=divisions, contact_elements=across)
            _, rows = run(nu, (1.0, 3.0), options, label=f"nu {nu:g}, {divisions} divisions, "
                                                         f"{across:g} across")
            out[f"nu_{nu:g}_{divisions}_{across:g}"] = rows
    return out


def same_material_slab(nu: float) -> Target:
    material = material_from_dict({"model": "linear_elastic", "youngs_modulus_pa": YOUNGS_PA,
                                   "poissons_ratio": nu})
    return Target("same material", 0.12, (TargetLayer("slab", 0.08, DENSITY_KG_M3, material),))


def part_diagnosis() -> dict:
    nu, psi = 0.23, (0.5, 2.0)
    cases = {"mu 0.1": ({}, 0.1, None), "mu 0.3": ({}, 0.3, None), "mu 0.5": ({}, 0.5, None),
             "mu 0.1, slab of the ball's material": ({}, 0.1, same_material_slab(nu)),
             "stick_scale 2": ({"stick_scale": 2.0}, FRICTION, None),
             "stick_scale 32": ({"stick_scale": 32.0}, FRICTION, None),
             "penalty_scale 0.5": ({"penalty_scale": 0.5}, FRICTION, None),
             "penalty_scale 2": ({"penalty_scale": 2.0}, FRICTION, None),
             "time_step_scale 0.4": ({"time_step_scale": 0.4}, FRICTION, None),
             "hourglass_scale 0.2": ({"hourglass_scale": 0.2}, FRICTION, None),
             "integration full": ({"integration": "full"}, FRICTION, None)}
    out = {}
    for name, (changes, friction, target) in cases.items():
        options = dataclasses.replace(MESH, **changes)
        _, rows = run(nu, psi, options, friction, target, label=name)
        out[name] = rows
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=("sweep", "convergence", "diagnosis", "all"),
                        default="sweep")
    parser.add_argument("--plot", help="PNG of the sweep (one per Poisson's ratio: -nu0.23.png)")
    args = parser.parse_args()
    started = time.perf_counter()
    out: dict = {"friction": FRICTION, "normal_speed_m_s": NORMAL_SPEED_M_S,
                 "youngs_modulus_pa": YOUNGS_PA}
    if args.part in ("sweep", "all"):
        out["sweep"] = part_sweep(args.plot)
    if args.part in ("convergence", "all"):
        out["convergence"] = part_convergence()
    if args.part in ("diagnosis", "all"):
        out["diagnosis"] = part_diagnosis()
    out["wall_time_s"] = time.perf_counter() - started
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
