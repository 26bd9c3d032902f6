"""Stepwise calibration of the three-layer cricket ball, as thesis 5.2-5.3 did it, on synthetic
tests with known answers.

A "true" ball (the cricket-3layer preset with changed constants) is simulated at the thesis'
speeds: the core alone at 17.85 m/s, the core + midsole unit at 20.8 m/s, the whole ball at
20.8 m/s; each pulse is sampled at 100 kHz with 1% white noise and written as a test (CSV and
JSON side file). Then one `ballimpact calibrate` command starts from the preset and calibrates in
four stages, earlier results frozen:

1. core: C10, C01 on force NRMSE and contact time (thesis: 98 MOGA runs);
2. core: Prony g1, tau1 on force NRMSE and COR (thesis: 59 runs);
3. midsole: Ogden mu1, alpha1 on the core + midsole test (three objectives);
4. cover: C10, C01 on the ball test (three objectives),

each by NSGA-II, a knee decision and a Levenberg-Marquardt refinement with gradients through the FE runs.

    python examples/calibrate_stepwise.py [--out DIR] [--population N] [--generations G]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from ballimpact.calibrate.problem import get_value, with_values
from ballimpact.calibrate.synthetic import synthetic_record
from ballimpact.cli import main
from ballimpact.fe import SolverOptions
from ballimpact.balls.ball import CRICKET_3LAYER_SPEC

TRUTH = {"layers.core.material.c10_pa": 4.2e6, "layers.core.material.c01_pa": -0.3e6,
         "layers.core.material.prony.0.g": 0.45, "layers.core.material.prony.0.tau_s": 9e-5,
         "layers.midsole.material.terms.0.mu_pa": 60e6,
         "layers.midsole.material.terms.0.alpha": 4.5,
         "layers.cover.material.c10_pa": 5.0e6, "layers.cover.material.c01_pa": -0.6e6}
TESTS = (("core", "core", 17.85), ("core-midsole", "midsole", 20.8), ("ball", "cover", 20.8))
STAGES = (
    ("core-hyperelastic", "*core*c10_pa,*core*c01_pa", "core", "nrmse,contact_time"),
    ("core-prony", "*core*prony*", "core", "nrmse,cor"),
    ("midsole", "*midsole*", "core-midsole", "nrmse,cor,contact_time"),
    ("cover", "*cover*", "ball", "nrmse,cor,contact_time"),
)
BOUNDS = {"layers.core.material.c10_pa": "3e6:5e6", "layers.core.material.c01_pa": "-2e6:0",
          "layers.core.material.prony.0.g": "0:0.95",
          "layers.core.material.prony.0.tau_s": "1e-5:1e-3",
          "layers.midsole.material.terms.0.mu_pa": "30e6:120e6",
          "layers.midsole.material.terms.0.alpha": "2:7",
          "layers.cover.material.c10_pa": "3e6:7e6", "layers.cover.material.c01_pa": "-1.5e6:0"}


def write_tests(folder: Path, noise: float = 0.01, seed: int = 0) -> None:
    truth = with_values(CRICKET_3LAYER_SPEC, TRUTH)
    rng = np.random.default_rng(seed)
    for name, layer, speed in TESTS:
        record, fe = synthetic_record(truth, speed, SolverOptions(), noise, rng, layer)
        np.savetxt(folder / f"{name}.csv", np.column_stack([record.time_s, record.force_n]),
                   delimiter=",", header="time_s,force_n", comments="")
        (folder / f"{name}.json").write_text(json.dumps({
            "impact_speed_m_s": speed, "rebound_speed_m_s": fe.cor * speed,
            "mass_kg": fe.mass_kg, "comment": "synthetic: cricket-3layer with changed constants, "
                                              f"{noise:.0%} noise"}))
        print(f"test {name}: {speed} m/s, COR {fe.cor:.3f}, contact {fe.contact_time_s * 1e3:.3f} "
              f"ms, peak {fe.peak_force_n / 1e3:.2f} kN", file=sys.stderr)


def main_(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path("calibrate-stepwise"))
    parser.add_argument("--population", type=int, default=16)
    parser.add_argument("--generations", type=int, default=6)
    args = parser.parse_args(argv)
    args.out.mkdir(exist_ok=True)
    data = args.out / "tests"
    data.mkdir(exist_ok=True)
    write_tests(data)
    command = ["calibrate", "--ball", "cricket-3layer", "--method", "nsga2+gradient",
               "--population", str(args.population), "--generations", str(args.generations),
               "--out", str(args.out / "run"), "--json"]
    for name, layer, _ in TESTS:
        command += ["--test", f"{data / name}.csv::{layer}" if layer != "cover"
                    else f"{data / name}.csv"]
    for path, bounds in BOUNDS.items():
        command += ["--free", f"{path}={bounds}"]
    for name, free, tests, objectives in STAGES:
        command += ["--stage", f"name={name};free={free};tests={tests};objectives={objectives}"]
    print("ballimpact " + " ".join(command), file=sys.stderr)
    code = main(command)
    if code:
        return code
    result = json.loads((args.out / "run" / "calibration.json").read_text())
    print(f"\n{'parameter':<42}{'truth':>12}{'preset':>12}{'calibrated':>12}")
    for path, value in result["chosen"]["parameters"].items():
        print(f"{path:<42}{TRUTH[path]:>12.4g}{get_value(CRICKET_3LAYER_SPEC, path):>12.4g}"
              f"{value:>12.4g}")
    print(f"\n{'stage':<20}{'FE runs':>8}{'wall s':>8}  objectives")
    for stage in result["stages"]:
        objectives = ", ".join(f"{k} {v:.4g}" for k, v in stage["chosen"]["objectives"].items())
        print(f"{stage['name']:<20}{stage['fe_runs']:>8}{stage['wall_time_s']:>8.0f}  {objectives}")
    print(f"{'all':<20}{result['evaluations']:>8}{result['wall_time_s']:>8.0f}"
          "  (thesis: 98 + 59 runs for the core alone)")
    return 0


if __name__ == "__main__":
    sys.exit(main_())
