"""The three steps of `ballimpact universal` as library calls: a design of experiments run into a
study folder (`design_config`, `run_design`), a model trained on it and saved (`train_model`),
and a model's held-out figures (`held_out`; the closed loop is `evaluate.closed_loop`). Each
returns the data the command prints."""

from __future__ import annotations

from collections.abc import Callable, Collection
from pathlib import Path
from typing import Any

from .dataset import load_dataset
from .evaluate import check_study_matches
from .identify import warn_failed_model
from .model import UniversalModel, load_model
from .study import load_config, make_config, run_study
from .training import train

#: failed runs a run's summary lists (`run_design`'s `failures`)
LISTED_FAILURES = 20


def design_config(*, template: str | Path | None = None, ranges: dict | None = None,
                  allow: Collection[str] = (), stored: bool = False,
                  **settings: Any) -> dict[str, Any] | None:
    """The configuration `run_design` gets. A new study (`stored` False): `make_config` with
    `template` (default cricket-universal), `ranges`, `allow` and `settings` (None values left
    out). A stored study (resumed or extended): only what is given, to be compared with what the
    study holds (`make_config`'s values of the given keys), or None when nothing is given."""
    given = [k for k, v in settings.items() if v is not None]
    if stored and not (given or ranges or template or allow):
        return None
    config = make_config(template=template or "cricket-universal", ranges=ranges, allow=allow,
                         **settings)
    if not stored:
        return config
    return {k: config[k] for k in (*given, *(["ranges"] if ranges else []),
                                   *(["template"] if template else []),
                                   *(["allow"] if allow else []))}


def run_design(folder: Path, config: dict[str, Any] | None = None, *,
               progress: Callable[[int, int, float, int], None] | None = None,
               **options: Any) -> dict[str, Any]:
    """`study.run_study` (`options`: resume, extend, workers, scheduler), its summary with the
    study's failed runs: `failed_runs` (their number), `failures` (the first
    `LISTED_FAILURES`, each `run_id` and `reason`) and `runs_per_s` of this run (None when
    nothing ran)."""
    summary = run_study(folder, config, progress=progress, **options)
    columns, _ = load_dataset(folder)
    failed = [(int(i), r) for i, s, r in zip(columns["run_id"], columns["status"],
                                               columns["reason"]) if s != "ok"]
    summary["failed_runs"] = len(failed)
    summary["failures"] = [{"run_id": i, "reason": r} for i, r in failed[:LISTED_FAILURES]]
    summary["runs_per_s"] = (summary["new_runs"] / summary["wall_time_s"]
                             if summary["wall_time_s"] > 0 else None)
    return summary


def train_model(study: Path, out: Path, **settings: Any) -> dict[str, Any]:
    """`training.train` on the study in `study` (`settings`: seed, steps, width, members,
    noise_augment, force), the model saved to OUT.json and OUT.npz: their paths
    (`model_json`, `model_npz`), the `held_out` report and `held_out_check`, the `runs` used
    and the training's `wall_time_s`."""
    model, report = train(study, **settings)
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
