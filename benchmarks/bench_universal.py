"""Timing of the universal model's workflow on this machine, printed as JSON:

- a design of experiments of RUNS runs (default 600, the thesis' size) plus the training of the
  model on it (target < 5 minutes in all on the 2-core reference machine; the thesis needed about
  600 x 25 s = 4 hours of solver time);
- `ballimpact identify` with the built-in model, whole process (Python start, model load, FE
  verification run), target < 10 s.

    python benchmarks/bench_universal.py [RUNS]
"""

import json
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from importlib import resources
from pathlib import Path

import jax


def main(runs: int = 600) -> None:
    from ballimpact.universal.study import make_config, run_study
    from ballimpact.universal.training import train

    out = {"machine": platform.machine(), "cpus": __import__("os").cpu_count(),
           "jax": jax.__version__, "backend": jax.default_backend()}
    folder = Path(tempfile.mkdtemp(prefix="bench-universal-"))
    try:
        started = time.perf_counter()
        study = run_study(folder / "study", make_config(runs=runs, seed=1))
        study_s = time.perf_counter() - started
        started = time.perf_counter()
        model, report = train(folder / "study")
        train_s = time.perf_counter() - started
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    out["study"] = {"runs": runs, "wall_time_s": study_s, "runs_per_s": runs / study_s,
                    "finished_runs": study["finished_runs"]}
    out["training"] = {"wall_time_s": train_s, "held_out_mu0_median_relative_error":
                       report["inverse"]["mu0_pa"]["relative_error"]["median"]}
    out["study_plus_training_s"] = study_s + train_s
    out["thesis_solver_time_s"] = runs * 25.0
    sample = Path(str(resources.files("ballimpact") / "data" / "sample_impact.csv"))
    script = Path(sys.executable).with_name("ballimpact")
    command = [str(script)] if script.exists() else [sys.executable, "-m", "ballimpact.cli"]
    walls = []
    for _ in range(2):  # the first fills JAX's compilation cache
        started = time.perf_counter()
        subprocess.run([*command, "identify", str(sample), "--json"], check=True,
                       capture_output=True)
        walls.append(time.perf_counter() - started)
    out["identify_whole_process_s"] = {"cold_cache": walls[0], "warm_cache": walls[1]}
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]))
