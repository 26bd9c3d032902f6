"""Train the universal model on a study: split, scale, fit both ensembles, calibrate the
intervals, and measure everything on runs never seen in training or early stopping."""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..errors import InputError, InputWarning
from . import space
from .dataset import SHAPE_GRID
from .model import (
    COR_COLUMN,
    FEATURES,
    FORMAT,
    INTERVAL_LEVEL,
    Scaler,
    UniversalModel,
)
from .networks import Architecture, gaussian_interval_scale, predict, train_ensemble
from ..comparison import noisy_features
from .design import DESIGNS
from .similarity import BallSize
from .study import design_space, load_config, load_dataset

#: shares of the finished runs: held out for the report (never seen in training or early
#: stopping), and validation (early stopping and the interval calibration)
TEST_SHARE = 0.2
VALIDATION_SHARE = 0.15
#: How the noisy copies' pulses are described (`extract_features(method=...)`): as `process`
#: describes a measured test by default, recorded in the model (`UniversalModel.feature_method`).
FEATURE_METHOD = "fit"
#: default noise augmentation of the inverse's training (fraction of the peak force)
NOISE_AUGMENT = 0.02
#: fewest successful runs to train on (the split leaves 8 held out and 6 for validation)
MIN_RUNS = 40
#: features learned on a linear scale; the others (times, forces, rates, speeds) in log scale
#: when positive in every run
LINEAR_FEATURES = ("P11", "P12", "P13", "P14", "P17")


def split(run_ids: np.ndarray, seed: int) -> dict[str, np.ndarray]:
    """Seeded random split of row indices into train, validation and test."""
    order = np.random.default_rng(seed).permutation(len(run_ids))
    n_test = int(round(TEST_SHARE * len(order)))
    n_val = int(round(VALIDATION_SHARE * len(order)))
    return {"test": np.sort(order[:n_test]), "validation": np.sort(order[n_test:n_test + n_val]),
            "train": np.sort(order[n_test + n_val:])}


def more_runs(folder: Path, finished: int, config: dict[str, Any]) -> str:
    """How to get more runs: finish the study, or grow it (to the default 600, else double)."""
    if finished < config["runs"]:
        return (f"finish the study ({finished} of {config['runs']} runs done) with "
                f"`ballimpact universal run {folder} --resume`")
    extra = 600 - finished if finished < 600 else finished
    return f"add runs with `ballimpact universal run {folder} --extend {extra}`"


def train(folder: Path, *, seed: int = 0, steps: int = 1500, width: int = 128, depth: int = 3,
          members: int = 5, noise_augment: float = NOISE_AUGMENT,
          force: bool = False) -> tuple[UniversalModel, dict[str, Any]]:
    """Train on the finished, successful runs of the study in `folder`.

    With `noise_augment` > 0 the inverse also learns from one noisy copy of each training and
    validation run: its pulse at 100 kHz with white noise of a level drawn uniformly up to
    `noise_augment` times the peak force, processed as a measured test (so that measured,
    noisy features do not fall outside what the network has seen). Held-out runs stay clean.

    A model that fails its held-out check (`evaluate.held_out_check`) is refused with
    `InputError`; with `force` it is returned with an `InputWarning`, the failed check recorded
    in its metadata (`held_out_check`)."""
    folder = Path(folder)
    started = time.perf_counter()
    config = load_config(folder)
    columns, curves = load_dataset(folder, config)
    ok = columns["status"] == "ok"
    if ok.sum() < MIN_RUNS:
        raise InputError(f"DIR: {folder}: {int(ok.sum())} successful runs of {len(ok)} finished;"
                         f" training needs at least {MIN_RUNS} (a useful model several hundred):"
                         f" {more_runs(folder, len(ok), config)}")
    ranges = {k: tuple(v) for k, v in config["ranges"].items()}
    design = DESIGNS[design_space(config)]
    size = BallSize(config["template"]["radius_m"], config["template"]["mass_kg"])
    params = np.column_stack([columns[k][ok] for k in space.PARAMETERS])
    features_si = np.column_stack([columns[k][ok] for k in FEATURES])
    features = design.inputs(features_si, size)
    shapes = curves["force_shape"][ok]
    targets = space.to_unit(design.truth(params, size), design.target_ranges(ranges),
                            design.targets)
    parts = split(columns["run_id"][ok], seed)
    tr, va, te = parts["train"], parts["validation"], parts["test"]

    log_features = np.array([key not in LINEAR_FEATURES for key in design.features])
    feature_scaler = Scaler.fit(features[tr], log_features)
    target_scaler = Scaler.fit(targets[tr])
    shape_scaler = Scaler.fit(shapes[tr])
    x_inv = feature_scaler.forward(features)
    y_inv = target_scaler.forward(targets)
    x_tr, y_tr, x_va, y_va = x_inv[tr], y_inv[tr], x_inv[va], y_inv[va]
    if noise_augment > 0:
        copies = _noisy_copies(curves["force_n_100khz"][ok], params, features_si,
                               config["template"]["mass_kg"], noise_augment, seed, (tr, va))
        (x_tr, y_tr), (x_va, y_va) = (
            (np.concatenate([x_inv[rows], feature_scaler.forward(design.inputs(noisy, size))]),
             np.concatenate([y_inv[rows], y_inv[kept]]))
            for rows, (noisy, kept) in zip((tr, va), copies))
    inv_arch = Architecture(len(design.features), len(design.targets), width, depth, members)
    inverse, inv_fig = train_ensemble(inv_arch, x_tr, y_tr, x_va, y_va,
                                      seed=seed, steps=steps, label="inverse")

    model = UniversalModel(inverse, None, feature_scaler, target_scaler, shape_scaler,
                           np.ones(len(design.targets)),
                           {"ranges": ranges, "design_space": design.name})
    x_fwd = model.forward_inputs(design.forward_rows(params, size))
    y_fwd = np.column_stack([x_inv, shape_scaler.forward(shapes)])
    fwd_arch = Architecture(x_fwd.shape[1], y_fwd.shape[1], width, depth, members)
    forward, fwd_fig = train_ensemble(fwd_arch, x_fwd[tr], y_fwd[tr], x_fwd[va], y_fwd[va],
                                      seed=seed + 100, steps=steps, label="forward")
    model.forward = forward

    # split conformal calibration on the validation runs: scale each target's sigma so that the
    # 90% intervals hold 90% of the validation truths
    mean, sigma = (np.asarray(a, np.float64) for a in predict(inverse, x_va.astype(np.float32)))
    z = np.abs(y_va - mean) / np.maximum(sigma, 1e-12)
    level = min(1.0, INTERVAL_LEVEL * (1 + 1 / len(y_va)))
    model.interval_scale = np.quantile(z, level, axis=0) / gaussian_interval_scale(INTERVAL_LEVEL)

    import jax
    import equinox
    import optax

    model.metadata = {
        "format": FORMAT, "ballimpact_version": __version__,
        "versions": {"jax": jax.__version__, "equinox": equinox.__version__,
                     "optax": optax.__version__, "numpy": np.__version__},
        "ranges": {k: list(v) for k, v in ranges.items()}, "template": config["template"],
        "design_space": design.name,
        "features": list(design.features), "targets": list(design.targets),
        "log_scaled_parameters": [k for k in space.LOG_SCALED if k in ranges],
        "shape_grid_points": len(SHAPE_GRID),
        "feature_range": {k: [float(features[:, j].min()), float(features[:, j].max())]
                          for j, k in enumerate(design.features)},
        "architecture": {"inverse": inv_arch.to_dict(), "forward": fwd_arch.to_dict()},
        "interval_level": INTERVAL_LEVEL,
        "interval_scale": dict(zip(design.targets, model.interval_scale.tolist())),
        "study": {k: config[k] for k in ("runs", "seed", "method", "element_size_m",
                                         "precision", "integration")},
        "study_folder": folder.name,
        "runs": {"finished": int(len(ok)), "successful": int(ok.sum()),
                 "failed": int((~ok).sum()), "train": len(tr), "validation": len(va),
                 "test": len(te)},
        "split_seed": seed, "noise_augment_of_peak": noise_augment,
        "feature_method": FEATURE_METHOD,
        "training": {"inverse": inv_fig, "forward": fwd_fig, "steps": steps},
    }
    from .evaluate import held_out_report

    report, held = held_out_report(model, params[te], features_si[te], shapes[te],
                                   columns["run_id"][ok][te])
    model.held_out = held
    model.metadata["held_out"] = report
    model.metadata["training"]["wall_time_s"] = time.perf_counter() - started
    print(f"trained in {model.metadata['training']['wall_time_s']:.1f} s", file=sys.stderr)
    model.metadata["held_out_check"] = _held_out_check(report, force, folder, config, len(tr),
                                                       len(ok))
    return model, report


def _noisy_copies(pulses, params, features, mass_kg, noise_augment, seed, row_sets
                  ) -> list[tuple[np.ndarray, list[int]]]:
    """Per set of rows: the features (n, 19) of one noisy copy of each run (its pulse at 100 kHz
    with white noise of a level drawn uniformly up to `noise_augment` times the peak force,
    processed as a measured test) and the rows they are of. One seeded generator through the
    sets in order; a pulse the processing refuses gets no copy."""
    rng = np.random.default_rng(seed)
    out = []
    for rows in row_sets:
        noisy, kept = [], []
        for i in rows:
            try:
                values = noisy_features(pulses[i], params[i, 4], features[i, COR_COLUMN],
                                        mass_kg, rng.uniform(0.0, noise_augment), rng,
                                        method=FEATURE_METHOD)
            except InputError:
                continue
            noisy.append([values[k] for k in FEATURES])
            kept.append(i)
        out.append((np.array(noisy), kept))
    return out


def _held_out_check(report: dict[str, Any], force: bool, folder: Path, config: dict[str, Any],
                    n_train: int, n_ok: int) -> dict[str, Any]:
    """The held-out check of the model (`evaluate.held_out_check`) as its metadata records it;
    a failed one is an `InputError` naming the fix, or with `force` an `InputWarning`."""
    from .evaluate import held_out_check

    check = held_out_check(report)
    if not check["passed"]:
        worst = check["worst"]
        problem = (f"the model fails its held-out check: {worst} has held-out R^2 "
                   f"{check['r2'][worst]:.3g} on {report['runs']} runs it never saw (needs >= "
                   f"{check['min_r2']:g} for {', '.join(check['r2'])}), trained on "
                   f"{n_train} of {n_ok} runs")
        fix = f"{more_runs(folder, n_ok, config)} and train again"
        if not force:
            raise InputError(f"{problem}; {fix} (or --force to write it anyway, marked failed)")
        warnings.warn(f"{problem}: written because of --force and marked failed "
                      f"(held_out_check in its JSON); its identifications are not to be "
                      f"trusted; {fix}", InputWarning, stacklevel=3)
    return {**check, "forced": bool(force and not check["passed"])}
