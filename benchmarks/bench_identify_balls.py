"""`ballimpact identify` on balls of other sports with the built-in (size-free) model, whole
process, printed as JSON: for each ball of `data/sports_balls.json` the cricket sample test mapped
to that ball's size and mass by similarity (times x R / R0, forces x (m / R) / (m0 / R0) at the
same speed), identified with `--ball-diameter-m`, cold and warm compilation cache (the FE check
compiles once per mesh size), and the cricket sample itself in the same run as the reference.

    python benchmarks/bench_identify_balls.py
"""

import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from importlib import resources
from pathlib import Path

import jax
import numpy as np

from ballimpact.universal.families import nominal_size, sports_balls

R0, M0 = 0.036, 0.16


def _mapped_sample(folder: Path, name: str, radius_m: float, mass_kg: float) -> Path:
    data = resources.files("ballimpact") / "data"
    d = np.loadtxt(str(data / "sample_impact.csv"), delimiter=",", comments="#", skiprows=5)
    path = folder / f"{name}.csv"
    np.savetxt(path, np.column_stack([d[:, 0] * radius_m / R0,
                                      d[:, 1] * (mass_kg / radius_m) / (M0 / R0)]),
               delimiter=",", header="time_s,force_n", comments="")
    side = json.loads((data / "sample_impact.json").read_text())
    side["mass_kg"] = mass_kg
    path.with_suffix(".json").write_text(json.dumps(side))
    return path


def _identify(command: list[str], path: Path, diameter_m: float) -> tuple[float, dict]:
    started = time.perf_counter()
    done = subprocess.run([*command, "identify", str(path), "--ball-diameter-m",
                           f"{diameter_m!r}", "--json"], check=True, capture_output=True,
                          text=True)
    return time.perf_counter() - started, json.loads(done.stdout)


def main() -> None:
    script = Path(sys.executable).with_name("ballimpact")
    command = [str(script)] if script.exists() else [sys.executable, "-m", "ballimpact.cli"]
    out = {"machine": platform.machine(), "cpus": os.cpu_count(), "jax": jax.__version__,
           "backend": jax.default_backend(), "balls": {}}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        # one ball a size: the softball classes share the 12-inch ball's
        sizes = {}
        for name, rule in sports_balls().items():
            sizes.setdefault((tuple(rule["diameter_m"]), tuple(rule["mass_kg"])), name)
        names = ["cricket-reference", *sizes.values()]
        for name in names:
            size = nominal_size(name) if name in sports_balls() else None
            radius, mass = (size.radius_m, size.mass_kg) if size else (R0, M0)
            path = _mapped_sample(folder, name, radius, mass)
            cold, _ = _identify(command, path, 2 * radius)
            warm, result = _identify(command, path, 2 * radius)
            out["balls"][name] = {
                "diameter_m": 2 * radius, "mass_kg": mass,
                "whole_process_cold_cache_s": cold, "whole_process_warm_cache_s": warm,
                "identify_wall_time_s": result["wall_time_s"],
                "fe_check_force_nrmse": result["verification"]["force_nrmse"],
                "mu0_pa": result["params"]["mu0_pa"], "groups": result["groups"]}
            print(f"{name}: {warm:.1f} s warm", file=sys.stderr, flush=True)
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
