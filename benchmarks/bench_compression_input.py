"""Does a compression test earn its place as an input of the universal model designed in the
groups? (issue 42, item 1)

A slow compression of a homogeneous ball measures its long-term shear modulus mu0 (Hertz
between two platens at small deflections: E = 3 mu0 for a nearly incompressible ball; C01 / C10
only bends the curve at larger ones), which an impact sees only through mu0 / (1 - g1) and the
pulse's shape. Given with the impact's 18 dimensionless features, rho v^2 / mu0 is then known,
and g1 (and through it tau1) should follow better.

This trains the inverse ensemble of a groups study twice on the same split, seed and settings:
the 18 features alone, and the 18 features plus rho v^2 / mu0 as a compression test gives it
(the true value times a log-normal error of `--compression-error`, 3% by default: a lab's
compression force and a Hertz fit). No noise augmentation in either (both see clean features).
It prints, per group and variant, R^2 on the learned axis (log for the log-scaled groups), the
median and 90th percentile of the error in units of the group's range, and the coverage of the
90% intervals (split-conformal on the validation runs, as `universal train` calibrates them)
on the held-out runs.

    python benchmarks/bench_compression_input.py STUDY_DIR [--steps 1500] [--members 5]

STUDY_DIR: a study of `universal run --design groups` (the built-in sports-ball model's 4,096
runs took 1,169 s to run on 2 CPU cores). About 15 s of training a variant on 2 CPU
cores.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

from ballimpact.universal import space
from ballimpact.universal.design import DESIGNS
from ballimpact.universal.model import FEATURES, INTERVAL_LEVEL, Scaler
from ballimpact.universal.networks import (Architecture, gaussian_interval_scale, predict,
                                           train_ensemble)
from ballimpact.universal.similarity import BallSize
from ballimpact.universal.study import design_space, load_config, load_dataset
from ballimpact.universal.training import LINEAR_FEATURES, split


def figures(truth_unit: np.ndarray, mean: np.ndarray, sigma: np.ndarray, scale: np.ndarray,
            names: tuple[str, ...]) -> dict:
    """Per target: R^2, median and p90 of |error| (unit axis) and the intervals' coverage."""
    out = {}
    for j, name in enumerate(names):
        t, p = truth_unit[:, j], mean[:, j]
        half = scale[j] * gaussian_interval_scale(INTERVAL_LEVEL) * sigma[:, j]
        error = np.abs(p - t)
        out[name] = {"r2": float(1 - np.sum((t - p) ** 2) / np.sum((t - t.mean()) ** 2)),
                     "median_error_of_range": float(np.median(error)),
                     "p90_error_of_range": float(np.percentile(error, 90)),
                     "coverage_90": float(np.mean(error <= half))}
    return out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("study", type=Path)
    parser.add_argument("--steps", type=int, default=1500)
    parser.add_argument("--members", type=int, default=5)
    parser.add_argument("--compression-error", type=float, default=0.03,
                        help="log-normal error of the compression's mu0 (fraction)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    config = load_config(args.study)
    design = DESIGNS["groups"]
    if design_space(config) != "groups":
        raise SystemExit(f"{args.study}: not a study of --design groups")
    columns, _ = load_dataset(args.study, config)
    ok = columns["status"] == "ok"
    size = BallSize(config["template"]["radius_m"], config["template"]["mass_kg"])
    params = np.column_stack([columns[k][ok] for k in space.PARAMETERS])
    features = design.inputs(np.column_stack([columns[k][ok] for k in FEATURES]), size)
    truth = design.truth(params, size)
    ranges = design.target_ranges({k: tuple(v) for k, v in config["ranges"].items()})
    y = space.to_unit(truth, ranges, design.targets)
    parts = split(columns["run_id"][ok], args.seed)
    tr, va, te = parts["train"], parts["validation"], parts["test"]
    rng = np.random.default_rng(args.seed)
    group = design.targets.index("rho_v2_over_mu0")
    measured = truth[:, group] * np.exp(args.compression_error * rng.standard_normal(len(y)))
    log = [k not in LINEAR_FEATURES for k in design.features]
    variants = {"impact": (features, log),
                "impact_and_compression": (np.column_stack([features, measured]), log + [True])}
    result = {"study": str(args.study), "runs": {"train": len(tr), "validation": len(va),
                                                 "held_out": len(te)},
              "compression_error": args.compression_error, "steps": args.steps,
              "members": args.members, "machine": f"{platform.machine()}, "
                                                  f"{platform.python_version()}"}
    target_scaler = Scaler.fit(y[tr])
    z = target_scaler.forward(y)
    for name, (x, log_columns) in variants.items():
        started = time.perf_counter()
        scaler = Scaler.fit(x[tr], np.array(log_columns))
        xs = scaler.forward(x).astype(np.float32)
        arch = Architecture(x.shape[1], len(design.targets), 128, 3, args.members)
        ensemble, _ = train_ensemble(arch, xs[tr], z[tr], xs[va], z[va], seed=args.seed,
                                     steps=args.steps, label=name)
        # split-conformal scale of sigma on the validation runs, as training.train does
        mean, sigma = (np.asarray(a, np.float64) for a in predict(ensemble, xs[va]))
        level = min(1.0, INTERVAL_LEVEL * (1 + 1 / len(va)))
        scale = np.quantile(np.abs(z[va] - mean) / np.maximum(sigma, 1e-12), level, axis=0) \
            / gaussian_interval_scale(INTERVAL_LEVEL)
        mean, sigma = (np.asarray(a, np.float64) for a in predict(ensemble, xs[te]))
        # back to the unit axis of the groups (the target scaler only standardises them)
        result[name] = figures(y[te], target_scaler.inverse(mean), sigma * target_scaler.std,
                               scale, design.targets)
        result[name]["wall_time_s"] = time.perf_counter() - started
        print(f"{name}: trained in {result[name]['wall_time_s']:.0f} s", file=sys.stderr)
    print(json.dumps(result, indent=2))
    return result


if __name__ == "__main__":
    main()
