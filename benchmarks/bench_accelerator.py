"""Benchmark: the FE engines on an accelerator (issue 28 item 5), printed as JSON.

- `single`: the universal ball at 25 m/s (axisymmetric, default mesh) in float64 and float32:
  the first call (mostly compilation) and the median of 3 later calls, with the run's figures
  (to compare with a CPU's: the same physics within round-off);
- `batch`: universal-ball parameter sets over the table 6-2 ranges at 5-45 m/s
  (`bench_fe.universal_sets`), one vmapped group of each size in `--groups`, float32 and float64:
  the first call (compiles that group size) and a second call's runs per second; the first two
  members against single runs of the same sets (the batch equal to single runs);
- `oblique`: the thesis' oblique case (37 m/s, 56 degrees from the normal, friction 0.3,
  `--divisions` 24) in float32 and float64, first and compiled;
- `cpu_reference`: the same single run and a batch of 16 on this machine's CPU (a child process
  with JAX_PLATFORMS=cpu, `CPU_GROUP_SIZE`), the baseline measured in the same run.

Stops starting new measurements once `--budget-s` seconds have passed; the JSON written so far
goes to `--out` after each one (a run cut short keeps what it measured).

    python benchmarks/bench_accelerator.py [--groups 1,16,64,256,1024] [--budget-s 420]
                                           [--divisions 24] [--out FILE] [--no-cpu]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

import jax

sys.path.insert(0, str(Path(__file__).parent))
from bench_fe import universal_sets  # noqa: E402

from ballimpact.fe import SolverOptions, load_ball, simulate, simulate_batch  # noqa: E402
from ballimpact.fe.engine import default_group_size  # noqa: E402

START = time.perf_counter()

#: the CPU baseline, run in a child process so that JAX there sees no accelerator
_CPU_CHILD = """
import json, sys
sys.path.insert(0, sys.argv[1])
from bench_accelerator import single_run, batch_run
out = {"single_float64": single_run("float64"),
       "batch_16_float64": batch_run(16, "float64", group_size=None)}
print(json.dumps(out))
"""


def elapsed() -> float:
    return time.perf_counter() - START


def timed(fn, *args, **kwargs):
    start = time.perf_counter()
    out = fn(*args, **kwargs)
    return time.perf_counter() - start, out


def figures(result) -> dict:
    return {"peak_force_n": result.peak_force_n, "contact_time_s": result.contact_time_s,
            "cor": result.cor, "steps": result.steps, "elements": result.elements}


def single_run(precision: str) -> dict:
    ball = load_ball("cricket-universal", impact_speed_m_s=25.0)
    options = SolverOptions(precision=precision)
    first, result = timed(simulate, ball, 25.0, options)
    wall = statistics.median(timed(simulate, ball, 25.0, options)[0] for _ in range(3))
    return {"precision": precision, "first_call_s": first, "wall_s": wall,
            "element_updates_per_s": result.elements * result.steps / wall, **figures(result)}


def batch_run(n: int, precision: str, group_size: int | None) -> dict:
    balls, speeds = universal_sets(n)
    options = SolverOptions(precision=precision)
    first, _ = timed(simulate_batch, balls, speeds, options, group_size=group_size)
    wall, results = timed(simulate_batch, balls, speeds, options, group_size=group_size)
    singles = [simulate(b, s, options) for b, s in zip(balls[:2], speeds[:2])]
    worst = max(abs(r.peak_force_n - s.peak_force_n) / s.peak_force_n
                + abs(r.cor - s.cor) for r, s in zip(results, singles))
    updates = sum(r.elements * r.steps for r in results)
    return {"sets": n, "precision": precision, "group_size": group_size or default_group_size(n),
            "first_call_s": first, "wall_s": wall, "simulations_per_s": n / wall,
            "element_updates_per_s": updates / wall,
            "steps_max": max(r.steps for r in results),
            "batch_vs_single_worst_relative_peak_plus_cor_difference": worst}


def oblique_run(precision: str, divisions: int) -> list:
    from ballimpact.fe import Hexahedral, simulate
    from ballimpact.oblique import ImpactCondition, Options3D

    ball = load_ball("cricket-universal", impact_speed_m_s=37.0)
    condition = ImpactCondition(37.0, 56.0, 0.0, 0.3)
    options = Options3D(divisions=divisions, precision=precision)
    runs = []
    for label in ("first", "compiled"):
        wall, r = timed(lambda: simulate(ball, condition, geometry=Hexahedral(options)))
        runs.append({"precision": precision, "call": label, "wall_s": wall,
                     "element_updates_per_s": r.elements * r.steps / wall, "steps": r.steps,
                     "elements": r.elements, "normal_cor": r.normal_cor,
                     "rebound_spin_rad_s": r.rebound_spin_rad_s,
                     "peak_force_n": r.peak_force_n})
    return runs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--groups", default="1,16,64,256,1024")
    parser.add_argument("--budget-s", type=float, default=420.0)
    parser.add_argument("--divisions", type=int, default=24)
    parser.add_argument("--out", type=Path)
    parser.add_argument("--no-cpu", action="store_true")
    args = parser.parse_args()
    devices = jax.devices()
    out = {"machine": {"platform": platform.platform(), "cpus": os.cpu_count(),
                       "jax": jax.__version__, "backend": jax.default_backend(),
                       "device": devices[0].device_kind if devices else None},
           "single": [], "batch": [], "oblique": [], "skipped": []}

    def keep(section, label, fn, *fn_args):
        if elapsed() > args.budget_s:
            out["skipped"].append(label)
            return
        try:
            value = fn(*fn_args)
        except Exception as error:  # noqa: BLE001 - a benchmark records what failed and goes on
            value = {"failed": label, "error": f"{type(error).__name__}: {error}"}
        if isinstance(value, list):
            out[section].extend(value)
        elif section in ("single", "batch", "oblique"):
            out[section].append(value)
        else:
            out[section] = value
        print(f"{elapsed():7.1f} s  {label}: done", file=sys.stderr, flush=True)
        if args.out is not None:
            args.out.write_text(json.dumps(out, indent=1))

    for precision in ("float64", "float32"):
        keep("single", f"single {precision}", single_run, precision)
    for precision in ("float32", "float64"):
        for group in (int(g) for g in args.groups.split(",")):
            keep("batch", f"batch {group} {precision}", batch_run, group, precision, group)
    if not args.no_cpu:
        def cpu_reference():
            env = dict(os.environ, JAX_PLATFORMS="cpu")
            child = subprocess.run([sys.executable, "-c", _CPU_CHILD, str(Path(__file__).parent)],
                                   capture_output=True, text=True, env=env, check=True)
            return json.loads(child.stdout.strip().splitlines()[-1])
        keep("cpu_reference", "cpu reference", cpu_reference)
    for precision in ("float32", "float64"):
        keep("oblique", f"oblique {precision}", oblique_run, precision, args.divisions)
    out["total_s"] = elapsed()
    print(json.dumps(out, indent=1))
    if args.out is not None:
        args.out.write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
