"""Benchmark: the explicit FE ball (issue: universal ball at 25 m/s, goal < 0.5 s on one core;
the thesis' ABAQUS/Explicit runs took 25 s (universal) and 87 s (detailed) on a 2008 PC).

Prints one JSON object:
- per ball (`cricket-universal` at 25 m/s, `cricket-3layer` at 20.8 m/s, default mesh): the first
  call (`first_call_s`, mostly JAX compilation), the median of 3 later calls
  (`wall_time_per_simulation_s`), elements, steps, element updates per second and the ratio to the
  thesis' time for the same kind of model;
- `batch`: 64 universal-ball parameter sets (C10, C01, g1, tau1 spread over table 7-3's range)
  through `simulate_batch` (vmapped groups of `CPU_GROUP_SIZE` on a CPU, all 64 at once on an
  accelerator): simulations per second, against single runs of the same sets measured in the same
  process (`speedup_vs_single_runs`).

Run: python benchmarks/bench_fe.py [--quick]   (--quick: 16 sets in the batch)
"""

import json
import os
import platform
import statistics
import sys
import time

import jax
import numpy as np

from ballimpact.fe import SolverOptions, load_ball, simulate, simulate_batch
from ballimpact.fe.ball import BallModel, Layer
from ballimpact.fe.materials import MooneyRivlin, PronyTerm
from ballimpact.fe.solver import default_group_size

THESIS_S = {"cricket-universal": 25.0, "cricket-3layer": 87.0}


def timed(fn, *args):
    start = time.perf_counter()
    out = fn(*args)
    return time.perf_counter() - start, out


def one_ball(name, speed, options):
    ball = load_ball(name, impact_speed_m_s=speed)
    first, result = timed(simulate, ball, speed, options)
    walls = [timed(simulate, ball, speed, options)[0] for _ in range(3)]
    wall = statistics.median(walls)
    return {"ball": name, "impact_speed_m_s": speed, "first_call_s": first,
            "compilation_s_estimate": first - wall, "wall_time_per_simulation_s": wall,
            "elements": result.elements, "steps": result.steps,
            "element_updates_per_s": result.elements * result.steps / wall,
            "thesis_abaqus_s": THESIS_S[name], "speedup_vs_thesis": THESIS_S[name] / wall,
            "peak_force_n": result.peak_force_n, "contact_time_s": result.contact_time_s,
            "cor": result.cor, "energy_balance_error": result.energy_balance_error}


def universal_sets(n, seed=0):
    rng = np.random.default_rng(seed)
    radius = 0.036
    density = 0.16 / (4.0 / 3.0 * np.pi * radius ** 3)
    balls = []
    for i in range(n):
        material = MooneyRivlin(c10_pa=rng.uniform(4.0e6, 6.1e6), c01_pa=rng.uniform(-0.51e6, -0.35e6),
                                prony=(PronyTerm(g=rng.uniform(0.75, 0.79), k=0.0,
                                                 tau_s=rng.uniform(7e-5, 8e-5)),))
        balls.append(BallModel(f"set{i}", (Layer("ball", radius, density, material),)))
    return balls


def main():
    quick = "--quick" in sys.argv
    options = SolverOptions()
    out = {"machine": {"platform": platform.platform(), "processor": platform.processor(),
                       "cpu_count": os.cpu_count(), "python": platform.python_version()},
           "element_size_m": options.element_size_m, "balls": []}
    for name, speed in (("cricket-universal", 25.0), ("cricket-3layer", 20.8)):
        out["balls"].append(one_ball(name, speed, options))
        print(f"{name}: done", file=sys.stderr, flush=True)
    n = 16 if quick else 64
    balls = universal_sets(n)
    timed(simulate_batch, balls[:default_group_size(n)], 25.0, options)  # compile the kernel
    wall_batch, results = timed(simulate_batch, balls, 25.0, options)
    singles = [timed(simulate, b, 25.0, options)[0] for b in balls[:8]]
    per_single = statistics.median(singles)
    out["batch"] = {"sets": n, "wall_s": wall_batch, "simulations_per_s": n / wall_batch,
                    "single_run_s_median_of_8": per_single,
                    "speedup_vs_single_runs": per_single * n / wall_batch,
                    "group_size": default_group_size(n),
                    "backend": jax.default_backend(), "steps_max": max(r.steps for r in results)}
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
