"""The study dataset: one Parquet row per run and a companion NPZ of curves, written per batch.

Layout of a study folder::

    study.json                 the study's configuration (design, ranges, template, solver)
    runs/batch-00012.parquet   one row per run of batch 12: inputs, status, reason, P1..P19,
                               cor, peak_force_n, contact_time_s, energy_balance_error, ...
    runs/batch-00012.npz       run_id, force_shape (F/F_peak on GRID, t/t_contact from 0 to 1),
                               force_n_100khz (the pulse sampled at 100 kHz from first contact)

Each batch's files are written under a temporary name and renamed into place
(`fileio.replacing`), the Parquet file last: a batch counts as done when its Parquet file exists,
so an interrupted study resumes with no lost and no duplicated runs.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..records.features import FEATURE_NAMES
from ..fileio import first_line, read_arrays, replacing
from . import space

#: normalised time grid of the stored force shapes (t / contact time)
SHAPE_POINTS = 64
SHAPE_GRID = np.linspace(0.0, 1.0, SHAPE_POINTS)
#: the stored pulses: `comparison.PULSE_RATE_HZ` (100 kHz) from first contact, 6 ms
PULSE_SAMPLES = 600
#: the dataset's columns, in order
COLUMNS = ("run_id", "batch", *space.PARAMETERS, "mu0_pa", "status", "reason", "warnings",
           *FEATURE_NAMES, "cor", "peak_force_n", "contact_time_s", "energy_balance_error",
           "steps", "wall_time_s")
#: the columns training and the closed loop read (numeric ones must be numbers)
NUMERIC_COLUMNS = (*space.PARAMETERS, "mu0_pa", *FEATURE_NAMES, "cor")
#: a finished batch's files; temporary files (batch-00012.tmp.parquet) never match
BATCH_FILE = re.compile(r"batch-(\d{5})\.parquet")
#: each curve of a batch's NPZ: its length per run
CURVES = {"force_shape": SHAPE_POINTS, "force_n_100khz": PULSE_SAMPLES}


def batch_paths(folder: Path, batch: int) -> tuple[Path, Path]:
    stem = Path(folder) / "runs" / f"batch-{batch:05d}"
    return stem.with_suffix(".parquet"), stem.with_suffix(".npz")


def done_batches(folder: Path) -> set[int]:
    runs = Path(folder) / "runs"
    if not runs.is_dir():
        return set()
    return {int(m.group(1)) for p in runs.iterdir() if (m := BATCH_FILE.fullmatch(p.name))}


def remove_temporaries(folder: Path) -> None:
    """Delete what a killed write left (`*.tmp.*`; an interrupt with an exception deletes its
    own): never a finished batch."""
    runs = Path(folder) / "runs"
    if runs.is_dir():
        for p in runs.glob("batch-*.tmp.*"):
            p.unlink(missing_ok=True)


def remove_batch(folder: Path, batch: int) -> None:
    """Undo a finished batch: its Parquet file first (it marks the batch done), then its NPZ."""
    for p in batch_paths(Path(folder), batch):
        p.unlink(missing_ok=True)


def write_batch(folder: Path, batch: int, rows: list[dict[str, Any]],
                arrays: dict[str, np.ndarray]) -> None:
    """Write one batch atomically (NPZ first, Parquet last: the Parquet file marks it done)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    parquet, npz = batch_paths(Path(folder), batch)
    parquet.parent.mkdir(parents=True, exist_ok=True)
    with replacing(npz) as tmp:
        np.savez(tmp, **arrays)
    with replacing(parquet) as tmp:
        pq.write_table(pa.Table.from_pylist(rows), tmp)


def read_batch(folder: Path, batch: int, expected_ids: range) -> tuple[dict, dict]:
    """One finished batch, checked: the columns training reads, the run ids the study's
    configuration gives this batch, and its curves (keys, shapes, no pickles)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    parquet, npz = batch_paths(folder, batch)
    try:
        table = pq.read_table(parquet)
    except (OSError, ValueError, pa.ArrowException) as error:
        raise InputError(f"{parquet}: not a readable Parquet file ({first_line(error)}); "
                         "delete it and resume the study to rerun that batch") from None
    missing = [c for c in ("run_id", "status", *NUMERIC_COLUMNS) if c not in table.column_names]
    if missing:
        raise InputError(f"{parquet}: column {missing[0]} missing ({len(missing)} missing in "
                         "all); not a batch of a universal study")
    columns = {name: table.column(name).to_numpy(zero_copy_only=False)
               for name in table.column_names}
    for name in ("run_id", *NUMERIC_COLUMNS):
        if columns[name].dtype.kind not in "iuf":
            raise InputError(f"{parquet}: column {name} holds {columns[name].dtype} values, "
                             "expected numbers")
    if list(columns["run_id"]) != list(expected_ids):
        raise InputError(f"{parquet}: run ids {_span(columns['run_id'])}, expected "
                         f"{_span(expected_ids)} for batch {batch} of this study's design")
    ok = columns["status"] == "ok"
    bad = ~np.all(np.isfinite(np.column_stack([columns[c][ok].astype(float)
                                               for c in NUMERIC_COLUMNS])), axis=1)
    if bad.any():
        raise InputError(f"{parquet}: run {int(columns['run_id'][ok][bad][0])} is marked ok "
                         "but holds non-finite inputs or features")
    rerun = f"delete {parquet.name} and resume the study to rerun that batch"
    try:
        curves = read_arrays(npz, str(npz), "this batch's curves")
    except InputError as error:
        raise InputError(f"{error}; {rerun}") from None
    missing = [key for key in ("run_id", *CURVES) if key not in curves]
    if missing:
        raise InputError(f"{npz}: not this batch's curves (array {missing[0]} missing); {rerun}")
    if list(curves["run_id"]) != list(expected_ids):
        raise InputError(f"{npz}: run ids {_span(curves['run_id'])}, expected "
                         f"{_span(expected_ids)} (as in {parquet.name})")
    for key, points in CURVES.items():
        if curves[key].shape != (len(expected_ids), points) or curves[key].dtype.kind != "f":
            raise InputError(f"{npz}: {key} has shape {curves[key].shape} ({curves[key].dtype}), "
                             f"expected ({len(expected_ids)}, {points}) floats")
    return columns, curves


def _span(ids) -> str:
    ids = list(ids)
    return f"{ids[0]}..{ids[-1]}" if ids else "none"
