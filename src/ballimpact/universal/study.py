"""A design of experiments of the universal ball: sampled points run through the batched FE
engine, batch by batch, locally or on Dask distributed, checkpointed per batch."""

from __future__ import annotations

import json
import math
import time
import warnings
from collections.abc import Collection
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .. import __version__
from ..errors import InputError
from ..fileio import write_atomic
from ..checks import check_allow, check_integer
from ..comparison import PULSE_RATE_HZ
from . import space
from .dataset import (
    COLUMNS,
    CURVES,
    PULSE_SAMPLES,
    SHAPE_GRID,
    done_batches,
    read_batch,
    remove_batch,
    remove_temporaries,
    write_batch,
)

CONFIG_FILE = "study.json"
#: configuration keys and defaults (SI); `ranges` and `template` are filled in by `make_config`
DEFAULTS: dict[str, Any] = {"runs": 600, "seed": 0, "method": "sobol", "batch_size": 32,
                            "group_size": 4, "element_size_m": 1.5e-3, "precision": "float32",
                            "integration": "reduced"}


def _positive(v) -> bool:
    return space.is_number(v) and v > 0


def _range(v) -> bool:
    return space.is_pair(v) and v[0] < v[1]


#: what a study's configuration holds (`study.json`), checked by `check_config`
CONFIG_SCHEMA: dict[str, Any] = {
    "runs": space.count(1), "seed": space.count(0),
    "method": (lambda v: v in space.METHODS, " or ".join(space.METHODS)),
    "batch_size": space.count(1), "group_size": space.count(1),
    "element_size_m": (_positive, "a size in m > 0"),
    "precision": (lambda v: v in ("float32", "float64"), "float32 or float64"),
    "integration": (lambda v: v in ("reduced", "full"), "reduced or full"),
    "ranges": {name: (_range, "[low, high] in SI with low < high") for name in space.PARAMETERS},
    "template": {"radius_m": (_positive, "a radius in m > 0"),
                 "mass_kg": (_positive, "a mass in kg > 0"),
                 "density_kg_m3": (_positive, "a density in kg/m^3 > 0"),
                 "moduli": (lambda v: isinstance(v, str), "a moduli convention (text)")},
}


#: the ranges of a study of the groups (`design_space` "groups")
GROUP_RANGES_SCHEMA = {name: (_range, "[low, high] with low < high")
                       for name in space.GROUP_PARAMETERS}


def design_space(config: dict[str, Any]) -> str:
    """A study's design space (`space.DESIGN_SPACES`): "material" for studies written before
    the groups' design."""
    value = config.get("design_space", "material")
    if value not in space.DESIGN_SPACES:
        raise InputError(f"design_space = {json.dumps(value)[:40]}: allowed "
                         f"{', '.join(space.DESIGN_SPACES)}")
    return value


def check_config(config: Any, where: str) -> dict[str, Any]:
    """A study configuration checked against `CONFIG_SCHEMA` (its ranges: those of its design
    space) and the range limits; `where` names its source in the messages."""
    groups = isinstance(config, dict) and design_space(config) == "groups"
    schema = {**CONFIG_SCHEMA, "ranges": GROUP_RANGES_SCHEMA} if groups else CONFIG_SCHEMA
    space.check_fields(config, schema, where)
    try:
        if groups:
            space.check_group_ranges(config["ranges"])
        else:
            space.check_ranges(config["ranges"], study_allow(config))
    except InputError as error:
        raise InputError(f"{where}: {error}") from None
    radius, size = config["template"]["radius_m"], config["element_size_m"]
    if size >= radius / 2:  # the mesher's own limit, checked before anything runs
        raise InputError(f"{where}: element_size_m = {size:g} m: must be below the ball's "
                         f"radius / 2 = {radius / 2:g} m")
    return config


def study_allow(config: dict[str, Any]) -> frozenset[str]:
    """The plausibility checks the study's balls may fail with a warning (`allow`: kept in the
    configuration, so that a resumed study and each Dask worker load its balls alike; studies
    written before it have none)."""
    allow = config.get("allow", [])
    if not isinstance(allow, list):
        raise InputError(f"'allow' = {json.dumps(allow)[:40]}: expected a list of check names")
    return check_allow(allow)


def load_config(folder: Path, flag: str = "DIR") -> dict[str, Any]:
    """The configuration of the study in `folder`, checked; `InputError` naming `flag`, the
    folder or `study.json` and what is wrong (not a folder, no study, damaged file)."""
    folder = Path(folder)
    stored = folder / CONFIG_FILE
    if not folder.exists():
        raise InputError(f"{flag}: {folder} does not exist (run `ballimpact universal run "
                         f"{folder}` first)")
    if not folder.is_dir():
        raise InputError(f"{flag}: {folder} is a file, not a study folder")
    if not stored.is_file():
        raise InputError(f"{flag}: {folder} holds no study ({CONFIG_FILE} missing)")
    try:
        config = json.loads(stored.read_text())
    except (OSError, ValueError) as error:
        raise InputError(f"{flag}: {stored}: not readable JSON ({error})") from None
    if isinstance(config, dict):  # studies written before the groups' design
        config.setdefault("design_space", "material")
    return check_config(config, f"{flag}: {stored}")


def _write_config(folder: Path, config: dict[str, Any]) -> None:
    write_atomic(Path(folder) / CONFIG_FILE, json.dumps(config, indent=2))


def make_config(*, template: str | Path = "cricket-universal", ranges: dict | None = None,
                allow: Collection[str] = (), design: str = "material",
                **settings: Any) -> dict[str, Any]:
    """A checked study configuration. `template`: a preset or ball file giving the radius, mass
    and moduli convention; `design`: "material" (the constants and the speed on the template,
    `space.PARAMETERS`) or "groups" (the dimensionless groups, `space.GROUP_PARAMETERS`, each
    run at its `space.run_speed`; its balls may be outside sports balls' moduli, as the groups
    are what counts); `ranges`: name -> (low, high) overriding the design space's defaults;
    `allow`: plausibility checks the template and the design's balls may fail with a warning
    ("ball-units": e.g. a foam ball softer than sports balls); `settings`: any of `DEFAULTS`'
    keys."""
    from ..fe import load_ball

    unknown = set(settings) - set(DEFAULTS)
    if unknown:
        raise InputError(f"study settings {sorted(unknown)}: unknown; allowed {sorted(DEFAULTS)}")
    config = {**DEFAULTS, **{k: v for k, v in settings.items() if v is not None}}
    if design not in space.DESIGN_SPACES:
        raise InputError(f"design = {design!r}: allowed {', '.join(space.DESIGN_SPACES)}")
    # a study of the groups runs each point at the speed that keeps its pulse well sampled, so
    # its balls' moduli are those of the groups at that speed, not a sports ball's
    config["allow"] = sorted(check_allow({*allow, "ball-units"} if design == "groups" else allow))
    ball = load_ball(str(template), impact_speed_m_s=25.0, allow=config["allow"])
    config["design_space"] = design
    if design == "groups":
        config["ranges"] = space.check_group_ranges(ranges or {})
    else:
        config["ranges"] = space.check_ranges(ranges or {}, config["allow"])
    config["template"] = space.template_geometry(ball)
    config["version"] = __version__
    config = json.loads(json.dumps(config))  # as stored: tuples become lists
    return check_config(config, "study settings")


def batch_ids(config: dict[str, Any], batch: int) -> range:
    """The run ids of batch `batch` of a study."""
    first = batch * config["batch_size"]
    return range(first, min(first + config["batch_size"], config["runs"]))


def load_dataset(folder: Path, config: dict[str, Any] | None = None
                 ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """All finished batches of a study: (columns, curves), rows sorted by run_id.

    `columns` maps each Parquet column to a NumPy array; `curves` holds `force_shape` and
    `force_n_100khz` aligned with the rows, plus `shape_grid` and `pulse_time_s`. `config`: the
    study's configuration (read from `folder` if not given). Every batch is checked against it
    (`InputError` naming the damaged file)."""
    folder = Path(folder)
    if config is None:
        config = load_config(folder)
    batches = sorted(done_batches(folder))
    if not batches:
        raise InputError(f"{folder}: no finished runs (expected runs/batch-*.parquet; "
                         "run `ballimpact universal run` first)")
    parts = [read_batch(folder, b, batch_ids(config, b)) for b in batches]
    names = [n for n in COLUMNS if all(n in p[0] for p in parts)]  # one column order
    columns = {n: np.concatenate([p[0][n] for p in parts]) for n in names}
    curves = {key: np.concatenate([p[1][key] for p in parts]) for key in ("run_id", *CURVES)}
    # batches are read in order and hold consecutive run ids: rows are sorted by run id
    curves["shape_grid"] = SHAPE_GRID
    curves["pulse_time_s"] = np.arange(PULSE_SAMPLES) / PULSE_RATE_HZ
    return columns, curves


def samples(config: dict[str, Any]) -> np.ndarray:
    """The study's points: rows (c10_pa, c01_pa, g1, tau1_s, impact_speed_m_s) in SI (a study of
    the groups: its design's groups as the template's constants, each at its run speed)."""
    ranges = {k: tuple(v) for k, v in config["ranges"].items()}
    if design_space(config) == "groups":
        groups = space.sample(config["runs"], config["seed"], config["method"], ranges,
                              tuple(space.GROUP_PARAMETERS))
        template = config["template"]
        return space.params_from_groups(groups, template["radius_m"], template["density_kg_m3"])
    return space.sample(config["runs"], config["seed"], config["method"], ranges)


def batch_count(config: dict[str, Any]) -> int:
    return math.ceil(config["runs"] / config["batch_size"])


def run_batch(config: dict[str, Any], batch: int) -> tuple[list[dict], dict[str, np.ndarray]]:
    """Run one batch of a study: its rows and curves (see `dataset`). A pure function of the
    configuration and the batch index, so a Dask worker computes exactly what a local run does."""
    from ..fe import FailedRun, SolverOptions, load_ball, simulate_batch

    points = samples(config)
    ids = list(batch_ids(config, batch))
    geometry = config["template"]
    names = list(space.PARAMETERS)
    allow = study_allow(config)
    balls = []
    for i in ids:
        params = dict(zip(names, points[i]))
        balls.append(load_ball(space.universal_ball_spec(params, geometry, f"run-{i}"),
                               allow=allow))
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
            # what feature extraction says about an FE pulse belongs to the run's row, not to
            # the user's terminal
            with warnings.catch_warnings(record=True) as said:
                warnings.simplefilter("always")
                try:
                    values, shape, pulse = _outputs(result)
                    row.update(status="ok", reason="", **values)
                except Exception as error:  # noqa: BLE001 - recorded with the run, not dropped
                    row.update(status="failed",
                               reason=f"features: {type(error).__name__}: {error}")
            mine += [str(w.message) for w in said]
        row["warnings"] = "; ".join(dict.fromkeys(mine))
        rows.append(row)
        shapes.append(shape)
        pulses.append(pulse)
    # every row has every column, in one order (failed runs: NaN)
    rows = [{key: row.get(key, math.nan) for key in COLUMNS} for row in rows]
    return rows, {"run_id": np.array(ids), "force_shape": np.array(shapes),
                  "force_n_100khz": np.array(pulses)}


def _outputs(result) -> tuple[dict[str, float], np.ndarray, np.ndarray]:
    from ..records.features import extract_features

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
              extend: int | None = None, workers: int | None = None,
              scheduler: str | None = None,
              progress: Callable[[int, int, float, int], None] | None = None,
              max_batches: int | None = None) -> dict[str, Any]:
    """Run (or resume, or extend) the study in `folder`; returns a summary.

    A new study needs `config` (from `make_config`) and an empty or missing `folder`; `resume`
    continues the study stored in `folder` (a `config` given too must equal the stored one);
    `extend` = N adds N runs to it (Sobol designs: the same sequence continued, so the study
    then equals one run with the total from the start; see `_extend`).
    `workers` starts a local Dask cluster of that many processes; `scheduler` connects to a
    running one; neither: runs here. `max_batches` stops after that many batches (the rest are
    left for `resume`). `progress(done_runs, total_runs, elapsed_s, new_runs)` is called after
    each batch. On a Dask scheduler the workers need ballimpact installed. Everything is
    checked before anything is written.
    """
    folder = Path(folder)
    config = _prepare(folder, config, resume, extend, workers, scheduler)
    remove_temporaries(folder)
    total = batch_count(config)
    done = {b for b in done_batches(folder) if b < total}
    todo = [b for b in range(total) if b not in done]
    if max_batches is not None:
        todo = todo[:max_batches]
    started = time.perf_counter()
    done_runs = sum(len(batch_ids(config, b)) for b in done)
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
            "new_runs": new_runs, "batches": total,
            "wall_time_s": time.perf_counter() - started}


def _prepare(folder: Path, config: dict[str, Any] | None, resume: bool, extend: int | None,
             workers: int | None, scheduler: str | None) -> dict[str, Any]:
    """`run_study`'s arguments checked and its study opened: the configuration to run (a new
    study's written to `folder`, an extended one's rewritten)."""
    if workers is not None:
        check_integer("--workers", workers, 1, note="Dask processes")
    if workers is not None and scheduler is not None:
        raise InputError("--workers and --scheduler: give one (a local cluster of N processes, "
                         "or a running scheduler's address)")
    if workers is not None or scheduler is not None:
        _dask()  # missing: said before the study is written
    if extend is not None:
        return _extend(folder, config, extend)
    if resume:
        saved = load_config(folder, "--resume")
        _check_unchanged(config, saved, "--resume")
        return saved
    return _new_study(folder, config)


def _new_study(folder: Path, config: dict[str, Any] | None) -> dict[str, Any]:
    """A new study's configuration, checked, written to `folder` (missing or empty)."""
    if config is None:
        raise InputError("a new study needs its configuration")
    config = check_config(config, "study settings")
    if folder.exists() and not folder.is_dir():
        raise InputError(f"DIR: {folder} is a file, not a study folder")
    if (folder / CONFIG_FILE).exists() or done_batches(folder):
        raise InputError(f"DIR: {folder} already holds a study: add --resume to continue "
                         "it, --extend N to add N runs, or choose another folder")
    if folder.is_dir() and any(folder.iterdir()):
        raise InputError(f"DIR: {folder} is not empty and holds no study: choose a new or "
                         "empty folder")
    folder.mkdir(parents=True, exist_ok=True)
    _write_config(folder, config)
    return config


def _check_unchanged(config: dict[str, Any] | None, saved: dict[str, Any], flag: str,
                     free: tuple[str, ...] = ("version",)) -> None:
    """A configuration given with --resume/--extend must agree with the stored one."""
    if config is None:
        return
    differ = [k for k in config if k not in free and config[k] != saved.get(k)]
    if differ:
        more = " (to add runs: --extend N)" if "runs" in differ else ""
        raise InputError(f"{flag}: the stored study differs in {', '.join(differ)}; "
                         f"{flag} without changing them{more}, or start a new folder")


def _extend(folder: Path, config: dict[str, Any] | None, extra: int) -> dict[str, Any]:
    """The stored study grown by `extra` runs, written back.

    A scrambled Sobol sequence is a sequence: its first n points do not depend on how many
    follow, so the grown design holds the old runs unchanged and continues with the next points
    (the study equals one run with the total from the start). A Latin hypercube's strata depend
    on the number of points: it cannot grow. A partial last batch is run again whole (the same
    runs, recomputed, plus the new ones), so the batches are those of a study of the total."""
    extra = check_integer("--extend", extra, 1, note="the number of runs to add")
    saved = load_config(folder, "--extend")
    _check_unchanged(config, saved, "--extend", free=("version", "runs"))
    if saved["method"] != "sobol":
        raise InputError(f"--extend: the study in {folder} is an {saved['method']} design, whose "
                         "points depend on the number of runs, so it cannot grow; start a new "
                         "study with more --runs (a Sobol design, the default, can be extended)")
    last = batch_count(saved) - 1
    if len(batch_ids(saved, last)) < saved["batch_size"]:
        remove_batch(folder, last)
    grown = {**saved, "runs": saved["runs"] + extra}
    _write_config(folder, grown)
    return grown


def _dask():
    try:
        import dask.distributed
    except ImportError:
        raise InputError("--workers/--scheduler need Dask distributed: pip install "
                         "'ballimpact[distributed]'") from None
    return dask.distributed


def _run_distributed(config, todo, finished, workers, scheduler) -> None:
    distributed = _dask()
    Client, LocalCluster = distributed.Client, distributed.LocalCluster
    as_completed = distributed.as_completed
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
