"""The cost of the ball in use on this machine, printed as JSON (issue 41, docs/equipment.md).

Each run twice (the first compiles; the second, "warm", reuses the program), with references
measured in the same run:
- the FE `baseball` at 61 m/s: alone on the rigid plane (the reference), on the free
  `baseball-wood-34in` bat at 0.70 m (12 modes coupled in the kernel), a sweep of 9 impact
  points along the bat as one batched run (`bats.impact_sweep`) against a loop of single runs
  of the same points, and the ball's contact law on the same bat (`bats.bat_impact`); the
  barrel's curvature run as a convex cap of the same Hertz equivalent radius (`barrel_figures`);
- the FE `cricket-men` ball at 19 and 45 m/s: alone on the rigid plane (the reference), on the
  `cricket-helmet` preset (a shell and liner on a spherical cap, backed by a 5 kg headform;
  the axisymmetric geometry), with its headform figures.

    python benchmarks/bench_equipment.py [--points N] [--bat-only]

`--points`: the sweep's impact points (default 9, 2 cm apart from 24 cm off the barrel end; more
are spread over the same span); `--bat-only`: no helmet runs. On an accelerator the sweep's
points run as one vmapped group (`fe.Axisymmetric.ACCELERATOR_GROUP_SIZE`).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

import numpy as np


def _timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def _twice(fn) -> tuple:
    """(result, first call s, warm call s)."""
    _, first = _timed(fn)
    out, warm = _timed(fn)
    return out, first, warm


def bat_figures(points: int = 9) -> dict:
    from ballimpact import fe
    from ballimpact.bats import ball_law, bat_impact, bat_model, impact_sweep
    from ballimpact.bats.fe_impact import fe_bat_impact

    speed, x = 61.0, 0.70
    ball = fe.load_ball("baseball", impact_speed_m_s=speed)
    wood = bat_model("baseball-wood-34in")
    alone, alone_first, alone_warm = _twice(lambda: fe.simulate(ball, speed))
    on_bat, bat_first, bat_warm = _twice(
        lambda: fe_bat_impact(wood, ball, speed, x, reference=alone))
    points = wood.bat.length_m - np.linspace(0.24, 0.08, points)
    sweep, sweep_first, sweep_warm = _twice(
        lambda: impact_sweep(wood, ball, speed, points, reference=alone))
    loop, loop_s = _timed(lambda: [fe_bat_impact(wood, ball, speed, float(p), reference=alone)
                                   for p in points])
    same = max(abs(a.collision_efficiency - b.collision_efficiency)
               for a, b in zip(sweep.results, loop))
    law = ball_law("baseball", speed)
    by_law, law_first, law_warm = _twice(lambda: bat_impact(wood, law, speed, x))
    return {
        "ball": "baseball", "bat": "baseball-wood-34in", "speed_m_s": speed, "impact_m": x,
        "ball_alone_rigid_plane": {"first_s": alone_first, "warm_s": alone_warm,
                                   "steps": alone.steps, "cor": alone.cor},
        "fe_ball_on_bat": {"first_s": bat_first, "warm_s": bat_warm,
                           "steps": on_bat.ball["fe"]["bat_run_steps"],
                           "collision_efficiency": on_bat.collision_efficiency,
                           "rigid_collision_efficiency": on_bat.rigid_collision_efficiency,
                           "energy_balance_error": on_bat.energy_balance_error,
                           "warm_over_ball_alone": bat_warm / alone_warm},
        "fe_sweep": {"points": int(points.size), "batched_first_s": sweep_first,
                     "batched_warm_s": sweep_warm, "per_point_warm_s": sweep_warm / points.size,
                     "loop_of_single_runs_warm_s": loop_s,
                     "loop_over_batched": loop_s / sweep_warm,
                     "batched_over_ball_alone": sweep_warm / alone_warm,
                     "largest_efficiency_difference_batched_vs_loop": same,
                     "least_vibration_from_barrel_end_m":
                         wood.bat.length_m - sweep.least_vibration_m,
                     "max_efficiency_from_barrel_end_m":
                         wood.bat.length_m - sweep.max_efficiency_m,
                     "max_collision_efficiency": float(sweep.collision_efficiency.max()),
                     "max_contact_rotation_rad": [r.max_contact_rotation_rad
                                                  for r in sweep.results]},
        "law_on_bat": {"first_s": law_first, "warm_s": law_warm,
                       "collision_efficiency": by_law.collision_efficiency}}


def barrel_figures(speed: float = 61.0, barrel_radius_m: float = 0.033) -> dict:
    """The barrel's curvature, run: the FE `baseball` on a stiff steel plate, flat and as a
    convex spherical cap of the same Hertz equivalent radius sqrt(R_x R_y) as the ball on the
    barrel (R_x = R along the bat, 1/R_y = 1/R + 1/R_b across it), fixed base."""
    from ballimpact import fe
    from ballimpact.fe.hex.target import Target

    ball = fe.load_ball("baseball", impact_speed_m_s=speed)
    r = ball.outer_radius_m
    equivalent = (r / (1.0 + r / barrel_radius_m)) ** 0.5 * r ** 0.5
    cap_radius = 1.0 / (1.0 / equivalent - 1.0 / r)
    steel = {"model": "linear_elastic", "youngs_modulus_pa": 200e9, "poissons_ratio": 0.3}

    def plate(**extra):
        return Target.from_dict({"name": "plate", "half_width_m": 0.05, **extra, "layers": [
            {"name": "steel", "thickness_m": 0.01, "density_kg_m3": 7800.0, "material": steel}]})

    flat = fe.simulate(ball, speed, target=plate())
    cap = fe.simulate(ball, speed, target=plate(sphere_radius_m=cap_radius))
    return {"speed_m_s": speed, "barrel_radius_m": barrel_radius_m,
            "equivalent_radius_m": equivalent, "cap_radius_m": cap_radius,
            "flat": {"peak_force_n": flat.peak_force_n, "contact_time_s": flat.contact_time_s,
                     "cor": flat.cor},
            "cap": {"peak_force_n": cap.peak_force_n, "contact_time_s": cap.contact_time_s,
                    "cor": cap.cor},
            "peak_force_change": cap.peak_force_n / flat.peak_force_n - 1.0,
            "contact_time_change": cap.contact_time_s / flat.contact_time_s - 1.0,
            "cor_change": cap.cor / flat.cor - 1.0}


def helmet_figures() -> dict:
    from ballimpact import fe
    from ballimpact.fe.hex.target import load_target
    from ballimpact.protect.headform import backing_figures

    helmet = load_target("cricket-helmet")
    ball = fe.load_ball("cricket-men", impact_speed_m_s=19.0)
    rows = []
    for speed in (19.0, 45.0):
        alone, alone_first, alone_warm = _twice(
            lambda: fe.simulate(ball, speed, allow={"speed-range"}))
        run, first, warm = _twice(
            lambda: fe.simulate(ball, speed, target=helmet, allow={"speed-range"}))
        head = backing_figures(run, histories=False)
        rows.append({"speed_m_s": speed, "ball_alone_warm_s": alone_warm,
                     "ball_alone_steps": alone.steps, "helmet_first_s": first,
                     "helmet_warm_s": warm, "helmet_steps": run.steps,
                     "elements": run.elements, "warm_over_ball_alone": warm / alone_warm,
                     "headform_peak_acceleration_g": head["backing_peak_acceleration_g"],
                     "hic15": head["hic15"], "energy_balance_error": run.energy_balance_error})
    return {"target": "cricket-helmet", "ball": "cricket-men", "runs": rows}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=9)
    parser.add_argument("--bat-only", action="store_true")
    args = parser.parse_args()
    import jax

    out = {"machine": {"platform": platform.platform(), "processor": platform.processor(),
                       "cpus": os.cpu_count(), "jax_backend": jax.default_backend(),
                       "devices": [str(d) for d in jax.devices()]},
           "bat": bat_figures(args.points), "barrel_curvature": barrel_figures()}
    if not args.bat_only:
        out["helmet"] = helmet_figures()
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
