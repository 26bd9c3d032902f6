"""Layered balls from tests (issue 42, item 4): when one homogeneous layer cannot give a ball's
impact and its compression together, say so, and calibrate a core and a cover against both.

SYNTHETIC tests with a known answer. The "true" ball is a 73 mm, 0.143 kg two-layer ball: a
lossy core (28 mm radius, Mooney-Rivlin C10 2 MPa long-term, one Prony term g1 0.8, tau1 50 us)
under a stiffer elastic cover (C10 10 MPa), the make-up of a baseball or a softball. Its tests:

- `impact.csv`: the FE pulse at 26.8 m/s (60 mph, ASTM F1887's speed), 100 kHz, 1% noise and a
  load cell (`pulses.load_cell_record`), with a JSON side file (mass, speeds);
- `compression.csv`: its slow (long-term) FE compression between two platens to 6.35 mm
  (0.25 in, ASTM F1888's approach), 20 points in mm and kN.

Then three commands, each printed before it runs:

1. `identify --compression`: the sports-ball universal model finds the homogeneous ball of the
   impact; squeezed, it misses the compression, and the FE check says so (exit 3);
2. `calibrate` of a one-layer ball against both tests (its long-term C10 from the compression,
   then g1 and tau1 from the impact): it cannot give the impact at that compression, and warns;
3. `calibrate` of the core and cover against both: the two long-term C10 from the compression,
   then the core's g1 and tau1 from the impact. With long-term moduli (the ball files'
   default) the Prony terms leave the relaxed curve alone, so the second stage keeps the
   first's fit: both tests are matched.

    python examples/layered_from_tests.py [--out DIR] [--element-size-m H]

prints a JSON summary (per path: force NRMSE, COR and contact-time errors, compression NRMSE;
the constants against the truth). About 3 minutes on 2 CPU cores (default mesh).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
from pathlib import Path

import numpy as np

SPEED_M_S = 26.8
DEFLECTION_M = 0.00635
RATE_HZ = 100e3
DIAMETER_M = 0.073
CORE_RADIUS_M = 0.028


def ball(name: str, core: dict, cover: dict | None) -> dict:
    """A ball of density 700 kg/m^3 and diameter `DIAMETER_M`: one layer of `core`, or a core of
    radius `CORE_RADIUS_M` under a `cover`."""
    layer = lambda name, r, material: {"name": name, "outer_radius_m": r,  # noqa: E731
                                       "density_kg_m3": 700.0, "material": material}
    if cover is None:
        return {"name": name, "layers": [layer("ball", DIAMETER_M / 2, core)]}
    return {"name": name, "layers": [layer("core", CORE_RADIUS_M, core),
                                     layer("cover", DIAMETER_M / 2, cover)]}


def mooney(c10_pa: float, g1: float | None = None, tau1_s: float | None = None) -> dict:
    material = {"model": "mooney_rivlin", "c10_pa": c10_pa, "c01_pa": 0.0}
    if g1 is not None:
        material["prony"] = [{"g": g1, "tau_s": tau1_s}]
    return material


TRUTH = ball("core-cover-truth", mooney(2.0e6, 0.8, 5e-5), mooney(10e6))
#: the templates' start values: every constant wrong
CORE_COVER = ball("core-cover", mooney(3.0e6, 0.6, 8e-5), mooney(6e6))
ONE_LAYER = ball("one-layer", mooney(3.0e6, 0.6, 8e-5), None)
TRUE_VALUES = {"layers.core.material.c10_pa": 2.0e6, "layers.cover.material.c10_pa": 10e6,
               "layers.core.material.prony.0.g": 0.8, "layers.core.material.prony.0.tau_s": 5e-5}
#: each calibration in two stages: the long-term C10 from the compression, then the Prony term
#: from the impact
STAGES = ["name=long-term;free=*c10_pa;tests=compression",
          "name=prony;free=*prony*;tests=impact"]
BOUNDS = {"core-cover": {"layers.core.material.c10_pa": "0.5e6:5e6",
                         "layers.cover.material.c10_pa": "2e6:20e6",
                         "layers.core.material.prony.0.g": "0.3:0.95",
                         "layers.core.material.prony.0.tau_s": "1e-5:5e-4"},
          "one-layer": {"layers.ball.material.c10_pa": "0.5e6:10e6",
                        "layers.ball.material.prony.0.g": "0.3:0.95",
                        "layers.ball.material.prony.0.tau_s": "1e-5:5e-4"}}


def write_tests(folder: Path, element_size_m: float | None = None, seed: int = 1) -> dict:
    """The true ball's impact and compression tests and the two templates, in `folder`.
    Returns the true ball's figures."""
    from ballimpact.fe import SolverOptions, compress, load_ball, simulate
    from ballimpact.records import pulses

    options = SolverOptions() if element_size_m is None else \
        SolverOptions(element_size_m=element_size_m)
    run = simulate(load_ball(TRUTH), SPEED_M_S, options)
    fe = run.record()
    pulse = lambda t: np.interp(t, fe.time_s - fe.time_s[0], fe.force_n, right=0.0)  # noqa: E731
    record = pulses.load_cell_record(pulse, fe.time_s[-1] - fe.time_s[0], RATE_HZ, noise=0.01,
                                     rng=np.random.default_rng(seed))
    np.savetxt(folder / "impact.csv", np.column_stack([record.time_s, record.force_n]),
               delimiter=",", header="time_s,force_n", comments="")
    (folder / "impact.json").write_text(json.dumps({
        "mass_kg": fe.mass_kg, "impact_speed_m_s": SPEED_M_S,
        "rebound_speed_m_s": round(run.cor * SPEED_M_S, 2),
        "comment": "synthetic: examples/layered_from_tests.py's core-cover truth, 1% noise"}))
    curve = compress(load_ball(TRUTH), DEFLECTION_M)  # the mesh that resolves the platens
    np.savetxt(folder / "compression.csv",
               np.column_stack([curve.deflection_m[1:] * 1e3, curve.force_n[1:] * 1e-3]),
               delimiter=",", fmt="%.6f", header="deflection_mm,force_kn",
               comments="# synthetic: the core-cover truth, long-term, 0.25 in\n")
    for spec in (CORE_COVER, ONE_LAYER):
        (folder / f"{spec['name']}.json").write_text(json.dumps(spec, indent=1))
    return {"cor": float(run.cor), "contact_time_s": float(run.contact_time_s),
            "peak_force_n": float(run.peak_force_n), "mass_kg": float(fe.mass_kg),
            "compression_force_n": float(curve.force_n[-1])}


def run_command(command: list[str]) -> tuple[int, dict]:
    """`ballimpact COMMAND --json`: (exit code, the JSON it printed)."""
    from ballimpact.cli import main

    print("ballimpact " + " ".join(command), file=sys.stderr)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(command + ["--json"])
    text = out.getvalue()
    return code, json.loads(text[text.index("{"):]) if "{" in text else {}


def calibrate(folder: Path, template: str, element_size_m: float | None) -> dict:
    command = ["calibrate", "--ball", str(folder / f"{template}.json"),
               "--test", str(folder / "impact.csv"),
               "--compression", str(folder / "compression.csv"),
               "--method", "gradient", "--out", str(folder / f"calibrated-{template}")]
    for path, bounds in BOUNDS[template].items():
        command += ["--free", f"{path}={bounds}"]
    for stage in STAGES:
        command += ["--stage", stage]
    if element_size_m is not None:
        command += ["--element-size-m", f"{element_size_m:g}"]
    code, result = run_command(command)
    if code:
        raise SystemExit(f"calibrate {template}: exit {code}")
    last: dict[str, float] = {}
    for stage in result["stages"]:
        last.update(stage["chosen"]["objectives"])
    return {"exit_code": code, "parameters": result["chosen"]["parameters"], "objectives": last,
            "fe_runs": result["evaluations"], "wall_time_s": result["wall_time_s"],
            "warnings": result.get("warnings", [])}


def main(argv: list[str] | None = None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path("layered-from-tests"))
    parser.add_argument("--element-size-m", type=float, default=None,
                        help="mesh of the truth's impact and of the calibrations (m); default: "
                             "the engine's")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    truth = write_tests(args.out, args.element_size_m)
    code, found = run_command(["identify", str(args.out / "impact.csv"),
                               "--model", "sports-ball-universal-model",
                               "--ball-diameter-m", f"{DIAMETER_M:g}",
                               "--compression", str(args.out / "compression.csv")])
    check = found["verification"]
    summary = {
        "truth": truth, "true_values": TRUE_VALUES,
        "identify_one_layer": {
            "exit_code": code, "passed": check["passed"], "missed": check["missed"],
            "force_nrmse": check["force_nrmse"], "cor_error": check["cor_error"],
            "contact_time_relative_error": check["contact_time_relative_error"],
            "compression_nrmse": check["compression"]["compression_nrmse"],
            "compression_end_force_relative_error":
                check["compression"]["end_force_relative_error"],
            "params": found["params"]},
        "calibrate_one_layer": calibrate(args.out, "one-layer", args.element_size_m),
        "calibrate_core_cover": calibrate(args.out, "core-cover", args.element_size_m)}
    recovered = summary["calibrate_core_cover"]["parameters"]
    summary["calibrate_core_cover"]["relative_error_vs_truth"] = {
        path: recovered[path] / value - 1 for path, value in TRUE_VALUES.items()}
    print(json.dumps(summary, indent=2))
    return summary


if __name__ == "__main__":
    main()
