"""A design of experiments of the universal ball: sampled points run through the batched FE
engine, batch by batch, locally or on Dask distributed, checkpointed per batch."""

from __future__ import annotations

import json
import math
import time
import warnings
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .. import __version__
from ..errors import InputError
from ..features import FEATURE_NAMES
from . import space
from .dataset import (
    PULSE_RATE_HZ,
    PULSE_SAMPLES,
    SHAPE_GRID,
    done_batches,
    write_batch,
)

CONFIG_FILE = "study.json"
#: the dataset's columns, in order
COLUMNS = ("run_id", "batch", *space.PARAMETERS, "mu0_pa", "status", "reason", "warnings",
           *FEATURE_NAMES, "cor", "peak_force_n", "contact_time_s", "energy_balance_error",
           "steps", "wall_time_s")
#: configuration keys and defaults (SI); `ranges` and `template` are filled in by `make_config`
DEFAULTS: dict[str, Any] = {"runs": 600, "seed": 0, "method": "sobol", "batch_size": 32,
                            "group_size": 4, "element_size_m": 1.5e-3, "precision": "float32",
                            "integration": "reduced"}


def make_config(*, template: str | Path = "cricket-universal", ranges: dict | None = None,
                **settings: Any) -> dict[str, Any]:
    """A checked study configuration. `template`: a preset or ball file giving the radius, mass
    and moduli convention; `ranges`: name -> (low, high) overriding `space.PARAMETERS`'s;
    `settings`: any of `DEFAULTS`' keys."""
    from ..fe import load_ball

    unknown = set(settings) - set(DEFAULTS)
    if unknown:
        raise InputError(f"study settings {sorted(unknown)}: unknown; allowed {sorted(DEFAULTS)}")
    config = {**DEFAULTS, **{k: v for k, v in settings.items() if v is not None}}
    for key in ("runs", "batch_size", "group_size"):
        if not (isinstance(config[key], int) and config[key] >= 1):
            raise InputError(f"{key} = {config[key]}: need an integer >= 1")
    if config["method"] not in space.METHODS:
        raise InputError(f"method = {config['method']!r}: allowed {', '.join(space.METHODS)}")
    ball = load_ball(str(template), impact_speed_m_s=25.0)
    config["ranges"] = space.check_ranges(ranges or {})
    config["template"] = space.template_geometry(ball)
    config["version"] = __version__
    return json.loads(json.dumps(config))  # as stored: tuples become lists


def samples(config: dict[str, Any]) -> np.ndarray:
    ranges = {k: tuple(v) for k, v in config["ranges"].items()}
    return space.sample(config["runs"], config["seed"], config["method"], ranges)


def batch_count(config: dict[str, Any]) -> int:
    return math.ceil(config["runs"] / config["batch_size"])


def run_batch(config: dict[str, Any], batch: int) -> tuple[list[dict], dict[str, np.ndarray]]:
    """Run one batch of a study: its rows and curves (see `dataset`). A pure function of the
    configuration and the batch index, so a Dask worker computes exactly what a local run does."""
    from ..fe import FailedRun, SolverOptions, load_ball, simulate_batch

    points = samples(config)
    first = batch * config["batch_size"]
    ids = list(range(first, min(first + config["batch_size"], config["runs"])))
    geometry = config["template"]
    names = list(space.PARAMETERS)
    balls = []
    for i in ids:
        params = dict(zip(names, points[i]))
        balls.append(load_ball(space.universal_ball_spec(params, geometry, f"run-{i}")))
    options = SolverOptions(element_size_m=config["element_size_m"],
                            precision=config["precision"], integration=config["integration"])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        results = simulate_batch(balls, points[ids, -1], options,
                                 group_size=config["group_size"], on_failure="return")
    notes = [str(w.message) for w in caught]
    rows, shapes, pulses = [], [], []
    for i, result in zip(ids, results):
        row = {"run_id": i, "batch": batch, **dict(zip(names, map(float, points[i])))}
        row["mu0_pa"] = 2.0 * (row["c10_pa"] + row["c01_pa"])
        mine = [n for n in notes if f"run-{i}:" in n or f"run-{i} " in n]
        shape = np.full(SHAPE_GRID.size, np.nan)
        pulse = np.full(PULSE_SAMPLES, np.nan)
        if isinstance(result, FailedRun):
            row.update(status="failed", reason=result.reason)
        else:
            try:
                values, shape, pulse = _outputs(result)
                row.update(status="ok", reason="", **values)
            except Exception as error:  # noqa: BLE001 - recorded with the run, not dropped
                row.update(status="failed", reason=f"features: {type(error).__name__}: {error}")
        row["warnings"] = "; ".join(dict.fromkeys(mine))
        rows.append(row)
        shapes.append(shape)
        pulses.append(pulse)
    # every row has every column, in one order (failed runs: NaN)
    rows = [{key: row.get(key, math.nan) for key in COLUMNS} for row in rows]
    return rows, {"run_id": np.array(ids), "force_shape": np.array(shapes),
                  "force_n_100khz": np.array(pulses)}


def _outputs(result) -> tuple[dict[str, float], np.ndarray, np.ndarray]:
    from ..features import extract_features

    features = extract_features(result.record())
    values = {key: float(v) for key, v in features.values.items()}
    values.update(cor=result.cor, peak_force_n=result.peak_force_n,
                  contact_time_s=result.contact_time_s,
                  energy_balance_error=result.energy_balance_error, steps=float(result.steps),
                  wall_time_s=result.wall_time_s)
    return values, force_shape(features), pulse_100khz(result)


def force_shape(features) -> np.ndarray:
    """The pulse as F / F_peak on `SHAPE_GRID` (t / contact time from the contact start)."""
    tc = features.values["P1"]  # the features' times count from the contact start
    return np.interp(SHAPE_GRID * tc, features.time_s, features.force_n,
                     left=0.0, right=0.0) / features.values["P6"]


def pulse_100khz(result) -> np.ndarray:
    """The contact force (N) at 100 kHz from first contact (t = 0), `PULSE_SAMPLES` long."""
    t = np.arange(PULSE_SAMPLES) / PULSE_RATE_HZ
    h = result.history
    return np.interp(t, h["time_s"], h["contact_force_n"], left=0.0, right=0.0)


def run_study(folder: Path, config: dict[str, Any] | None = None, *, resume: bool = False,
              workers: int | None = None, scheduler: str | None = None,
              progress: Callable[[int, int, float, int], None] | None = None,
              max_batches: int | None = None) -> dict[str, Any]:
    """Run (or resume) the study in `folder`; returns a summary.

    A new study needs `config` (from `make_config`) and an empty or missing `folder`; `resume`
    continues the study stored in `folder` (a `config` given too must equal the stored one).
    `workers` starts a local Dask cluster of that many processes; `scheduler` connects to a
    running one; neither: runs here. `max_batches` stops after that many batches (the rest are
    left for `resume`). `progress(done_runs, total_runs, elapsed_s, new_runs)` is called after
    each batch. On a Dask scheduler the workers need ballimpact installed.
    """
    folder = Path(folder)
    stored = folder / CONFIG_FILE
    if resume:
        if not stored.exists():
            raise InputError(f"--resume: {folder} holds no study ({CONFIG_FILE} missing)")
        saved = json.loads(stored.read_text())
        if config is not None:
            differ = [k for k in config if k != "version" and config[k] != saved.get(k)]
            if differ:
                raise InputError(f"--resume: the stored study differs in {', '.join(differ)}; "
                                 "resume without changing them or start a new folder")
        config = saved
    else:
        if config is None:
            raise InputError("a new study needs its configuration")
        if stored.exists() or done_batches(folder):
            raise InputError(f"{folder} already holds a study: add --resume to continue it, "
                             "or choose another folder")
        folder.mkdir(parents=True, exist_ok=True)
        stored.write_text(json.dumps(config, indent=2))
    done = done_batches(folder)
    todo = [b for b in range(batch_count(config)) if b not in done]
    if max_batches is not None:
        todo = todo[:max_batches]
    started = time.perf_counter()
    done_runs = sum(_batch_size(config, b) for b in done)
    new_runs = 0

    def finished(batch: int, rows, arrays) -> None:
        nonlocal done_runs, new_runs
        write_batch(folder, batch, rows, arrays)
        done_runs += len(rows)
        new_runs += len(rows)
        if progress is not None:
            progress(done_runs, config["runs"], time.perf_counter() - started, new_runs)

    if workers is None and scheduler is None:
        for batch in todo:
            finished(batch, *run_batch(config, batch))
    else:
        _run_distributed(config, todo, finished, workers, scheduler)
    return {"folder": str(folder), "runs": config["runs"], "finished_runs": done_runs,
            "new_runs": new_runs, "batches": batch_count(config),
            "wall_time_s": time.perf_counter() - started}


def _batch_size(config: dict[str, Any], batch: int) -> int:
    return min(config["batch_size"], config["runs"] - batch * config["batch_size"])


def _run_distributed(config, todo, finished, workers, scheduler) -> None:
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise InputError("--workers/--scheduler need Dask distributed: pip install "
                         "'ballimpact[distributed]'") from None
    if workers is not None and not (isinstance(workers, int) and workers >= 1):
        raise InputError(f"--workers = {workers}: need an integer >= 1")
    cluster = None
    if scheduler is None:
        # one process per worker, one thread each: the engine vmaps within a batch
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
    client = Client(cluster if cluster is not None else scheduler)
    try:
        futures = {client.submit(run_batch, config, batch, pure=False): batch for batch in todo}
        for future in as_completed(futures):
            finished(futures[future], *future.result())
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
