"""The three steps of `ballimpact universal` as library calls: a design of experiments run into a
study folder (`run_design`, its configuration by `design_config`), a model trained on it and
saved (`train_model`), and a model's held-out figures (`held_out`), with the closed loop and a
plot (`report_model`). Each checks its arguments first (`InputError` naming the command's flag)
and returns the data the command prints."""

from __future__ import annotations

import time
from collections.abc import Callable, Collection
from pathlib import Path
from typing import Any

from ..checks import check_fraction, check_integer, check_range
from ..errors import InputError
from ..fileio import check_output_folder, check_plot_path
from ..records.filters import check_filter_name
from .evaluate import check_study_matches, closed_loop
from .identify import warn_failed_model
from .model import UniversalModel, load_model
from .study import load_config, load_dataset, make_config, run_study
from .training import train

#: failed runs a run's summary lists (`run_design`'s `failures`)
LISTED_FAILURES = 20


def design_config(*, template: str | Path | None = None, ranges: dict | None = None,
                  allow: Collection[str] = (), stored: bool = False, design: str | None = None,
                  **settings: Any) -> dict[str, Any] | None:
    """The configuration `run_design` gets. A new study (`stored` False): `make_config` with
    `template` (default cricket-universal), `ranges`, `allow` and `settings` (None values left
    out; `design`: the design space, default "material"). A stored study (resumed or extended):
    only what is given, to be compared with what the study holds (`make_config`'s values of the
    given keys), or None when nothing is given."""
    given = [k for k, v in settings.items() if v is not None]
    if stored and not (given or ranges or template or allow or design):
        return None
    config = make_config(template=template or "cricket-universal", ranges=ranges, allow=allow,
                         design=design or "material", **settings)
    if not stored:
        return config
    if design:
        given.append("design_space")
    return {k: config[k] for k in (*given, *(["ranges"] if ranges else []),
                                   *(["template"] if template else []),
                                   *(["allow"] if allow else []))}


def run_design(folder: Path, *, template: str | Path | None = None, ranges: dict | None = None,
               allow: Collection[str] = (), design: str | None = None,
               runs: int | None = None, seed: int | None = None,
               method: str | None = None, batch_size: int | None = None,
               group_size: int | None = None, element_size_m: float | None = None,
               precision: str | None = None, resume: bool = False, extend: int | None = None,
               workers: int | None = None, scheduler: str | None = None,
               progress: Callable[[int, int, float, int], None] | None = None) -> dict[str, Any]:
    """Run (`resume`: continue; `extend`: add that many runs to) the design of experiments in
    `folder` (`study.run_study`, on `workers` local Dask processes or the `scheduler` at an
    address), its configuration by `design_config` (None settings: the defaults, or the stored
    study's); `design`: "material" (default) or "groups" (`study.make_config`); `ranges` in SI
    (a study of the groups: the groups'), `element_size_m` in m. Returns the study's summary
    with its failed runs: `failed_runs` (their number), `failures` (the first
    `LISTED_FAILURES`, each `run_id` and `reason`) and `runs_per_s` of this run (None when
    nothing ran). `InputError`, before
    anything is written, for a count below its least value, an element size <= 0, `extend`
    with `runs`, and what `make_config` and `run_study` refuse."""
    for flag, value, low, what in (("--runs", runs, 1, "the number of runs"),
                                   ("--seed", seed, 0, "the design's seed"),
                                   ("--batch-size", batch_size, 1, "runs per batch"),
                                   ("--group-size", group_size, 1, "balls per FE group")):
        _at_least(value, flag, low, what)
    if element_size_m is not None:
        check_range("--element-size-m", element_size_m, 0.0, low_open=True, unit="m",
                    note="default 1.5e-3")
    if extend is not None and runs is not None:
        raise InputError(f"--extend {extend} and --runs {runs}: give one (--runs sets a new "
                         "study's size, --extend adds runs to the study in DIR)")
    config = design_config(template=template, ranges=ranges, allow=allow, design=design,
                           stored=resume or extend is not None, runs=runs, seed=seed,
                           method=method, batch_size=batch_size, group_size=group_size,
                           element_size_m=element_size_m, precision=precision)
    summary = run_study(folder, config, resume=resume, extend=extend, workers=workers,
                        scheduler=scheduler, progress=progress)
    columns, _ = load_dataset(folder)
    failed = [(int(i), r) for i, s, r in zip(columns["run_id"], columns["status"],
                                               columns["reason"]) if s != "ok"]
    summary["failed_runs"] = len(failed)
    summary["failures"] = [{"run_id": i, "reason": r} for i, r in failed[:LISTED_FAILURES]]
    summary["runs_per_s"] = (summary["new_runs"] / summary["wall_time_s"]
                             if summary["wall_time_s"] > 0 else None)
    return summary


def train_model(study: Path, out: Path, *, seed: int = 0, steps: int = 1500, width: int = 128,
                members: int = 5, noise_augment: float = 0.02,
                force: bool = False) -> dict[str, Any]:
    """`training.train` on the study in `study` (`noise_augment`: a fraction of the peak force;
    `force`: save a model that fails its held-out check), the model saved to OUT.json and
    OUT.npz: their paths (`model_json`, `model_npz`), the `held_out` report and
    `held_out_check`, the `runs` used and the training's `wall_time_s`. `InputError`, before
    the training, for an `out` in a missing folder or that is a folder, a setting out of range
    and a missing or damaged study."""
    check_output_folder(out, "--out")
    if Path(out).is_dir():
        raise InputError(f"--out {out}: a folder; give a model path (writes OUT.json and "
                         "OUT.npz)")
    _check_noise_fraction(noise_augment, "--noise-augment")
    for flag, value, low, what in (("--steps", steps, 100, "validation every 100 steps"),
                                   ("--width", width, 1, "hidden units per layer"),
                                   ("--members", members, 1, "ensemble members"),
                                   ("--seed", seed, 0, "the split's seed")):
        _at_least(value, flag, low, what)
    load_config(study)  # a missing or damaged study: said before the training starts
    model, report = train(study, seed=seed, steps=steps, width=width, members=members,
                          noise_augment=noise_augment, force=force)
    npz, meta = model.save(out)
    return {"model_json": str(meta), "model_npz": str(npz), "held_out": report,
            "held_out_check": model.metadata["held_out_check"], "runs": model.metadata["runs"],
            "wall_time_s": model.metadata["training"]["wall_time_s"]}


def held_out(model: str | Path | None = None, study: Path | None = None
             ) -> tuple[UniversalModel, dict[str, Any]]:
    """The model (`load_model`: a path, or None for the built-in one) and its held-out figures:
    `model`, `held_out`, `held_out_check`, `runs` and `study`. With `study` (the closed loop's
    folder) that folder must hold the model's study (`evaluate.check_study_matches`), checked
    first; a model that failed its held-out check is warned of."""
    loaded = load_model(model)
    if study is not None:
        check_study_matches(loaded, load_config(study, "--closed-loop"), study)
    warn_failed_model(loaded)
    meta = loaded.metadata
    return loaded, {"model": model or "built-in", "held_out": meta["held_out"],
                    "held_out_check": meta.get("held_out_check"), "runs": meta["runs"],
                    "study": meta["study"]}


def report_model(model: str | Path | None = None, *, study: Path | None = None,
                 runs: int | None = None, noise: float | None = None,
                 filter_name: str | None = None, refine: str | None = None,
                 plot_path: Path | None = None,
                 shown: Callable[[dict[str, Any]], None] | None = None) -> dict[str, Any]:
    """`held_out`'s figures of `model` (None: the built-in one), passed to `shown` as soon as
    they are known; with `study` (the model's study folder) the closed loop
    (`evaluate.closed_loop` on `runs` held-out runs, default 60, with white `noise` as a
    fraction of the peak force, default 0, records filtered by `filter_name` and estimates
    refined by `refine`, default none) under `closed_loop`; with `plot_path` (PNG) the
    predictions against truth (`plots.plot_held_out`) under `plot`; and `wall_time_s`.
    `InputError`, before any model is loaded, for a closed-loop setting without `study`, a
    noise outside [0, 0.5), `runs` < 1, an unknown filter or a plot path that is not a PNG in
    an existing folder."""
    check_plot_path(plot_path)
    loop_only = [flag for flag, value in (("--runs", runs), ("--noise", noise),
                                          ("--filter", filter_name), ("--refine", refine))
                 if value is not None]
    if study is None and loop_only:
        raise InputError(f"{loop_only[0]}: applies to the closed loop only; add --closed-loop "
                         "DIR (the model's study folder)")
    noise = 0.0 if noise is None else noise
    _check_noise_fraction(noise, "--noise")
    _at_least(runs, "--runs", 1, "closed-loop runs")
    if filter_name is not None:
        check_filter_name(filter_name, "--filter")
    started = time.perf_counter()
    loaded, out = held_out(model, study)  # a wrong study is said before anything is shown
    if shown is not None:
        shown(out)
    if study is not None:
        out["closed_loop"] = closed_loop(loaded, study, runs=runs or 60, noise=noise,
                                         refine=refine or "none", filter=filter_name or "none")
    if plot_path is not None:
        from .plots import plot_held_out

        plot_held_out(loaded, plot_path)
        out["plot"] = str(plot_path)
    out["wall_time_s"] = time.perf_counter() - started
    return out


def _at_least(value: int | None, flag: str, low: int, what: str) -> None:
    """An optional count (None: its default) checked by `check_integer`, `what` as the note."""
    if value is not None:
        check_integer(flag, value, low, note=what)


def _check_noise_fraction(value: float, flag: str) -> None:
    """A noise level: a fraction of the peak force in [0, 0.5) (`checks.check_fraction`); a
    percentage typed for it (2 for 0.02) is named."""
    check_fraction(flag, value, 0.5, high_open=True, allow_zero=True,
                   note="white noise as a fraction of the peak force, e.g. 0.01")
