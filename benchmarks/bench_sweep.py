"""Benchmark: a speed sweep as one batch against single runs (issue 26 item 5), in the same run.

The `cricket-universal` preset (table 7-3 interpolated per speed) at 5, 10, 20 and 30 m/s on the
default mesh, float64:
- `library`: `sweep.run_sweep` (one `simulate_batch` call: on a CPU one vmapped group of four)
  against four `fe.simulate` calls; the first call of each (mostly compilation) and the median of
  `REPEATS` later calls, and the ratio single / batch; the largest relative difference of the
  figures between the two (round-off);
- `cli`: whole processes with a warm compilation cache (a fresh `BALLIMPACT_CACHE_DIR`, filled by
  one cold call of each first): `ballimpact simulate --speed-m-s 5,10,20,30` against four
  `ballimpact simulate --speed-m-s V` calls, median of `REPEATS`.

Prints one JSON object. Run: python benchmarks/bench_sweep.py [--quick]   (--quick: no `cli`)
"""

from __future__ import annotations

import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import jax

from ballimpact.fe import SolverOptions, simulate
from ballimpact.fe.engine import default_group_size
from ballimpact.fe.sweep import ROW_KEYS, run_sweep, sweep_balls, sweep_row

BALL = "cricket-universal"
SPEEDS = (5.0, 10.0, 20.0, 30.0)
REPEATS = 3


def timed(fn, *args):
    start = time.perf_counter()
    out = fn(*args)
    return time.perf_counter() - start, out


def library() -> dict:
    options = SolverOptions()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # 5 and 30 m/s: table 7-3's end rows held
        balls = sweep_balls(BALL, SPEEDS)

        def batch():
            return run_sweep(balls, SPEEDS, options, label=BALL)

        def singles():
            return [simulate(b, s, options) for b, s in zip(balls, SPEEDS)]

        first_batch, sweep = timed(batch)
        first_singles, runs = timed(singles)
        batch_s = statistics.median(timed(batch)[0] for _ in range(REPEATS))
        singles_s = statistics.median(timed(singles)[0] for _ in range(REPEATS))
    difference = max(abs(sweep_row(a)[k] - sweep_row(b)[k]) / abs(sweep_row(b)[k])
                     for a, b in zip(sweep.results, runs) for k in ROW_KEYS if sweep_row(b)[k])
    return {"ball": BALL, "speeds_m_s": list(SPEEDS), "group_size": default_group_size(4),
            "elements": runs[0].elements, "steps": [r.steps for r in runs],
            "batch_first_call_s": first_batch, "singles_first_calls_s": first_singles,
            "batch_s": batch_s, "four_singles_s": singles_s,
            "single_over_batch": singles_s / batch_s,
            "max_relative_difference_batch_vs_single": difference,
            "rows": sweep.rows()}


def cli() -> dict:
    script = Path(sys.executable).parent / "ballimpact"  # the installed command
    launcher = [str(script)] if script.exists() else [sys.executable, "-m", "ballimpact.cli"]
    base = launcher + ["simulate", "--ball", BALL, "--json", "--speed-m-s"]
    with tempfile.TemporaryDirectory() as folder:
        env = dict(os.environ, BALLIMPACT_CACHE_DIR=str(Path(folder) / "cache"))

        def run(speeds: str):
            return subprocess.run(base + [speeds], capture_output=True, env=env, check=True)

        def sweep():
            return run(",".join(f"{s:g}" for s in SPEEDS))

        def singles():
            return [run(f"{s:g}") for s in SPEEDS]

        cold_sweep, _ = timed(sweep)
        cold_singles, _ = timed(singles)
        sweep_s = statistics.median(timed(sweep)[0] for _ in range(REPEATS))
        singles_s = statistics.median(timed(singles)[0] for _ in range(REPEATS))
    return {"sweep_cold_cache_s": cold_sweep, "four_singles_cold_cache_s": cold_singles,
            "sweep_warm_cache_s": sweep_s, "four_singles_warm_cache_s": singles_s,
            "singles_over_sweep": singles_s / sweep_s}


def main() -> None:
    out = {"machine": {"platform": platform.platform(), "processor": platform.processor(),
                       "cpu_count": os.cpu_count(), "python": platform.python_version(),
                       "jax": jax.__version__, "backend": jax.default_backend()},
           "library": library()}
    print("library: done", file=sys.stderr, flush=True)
    if "--quick" not in sys.argv:
        out["cli"] = cli()
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
