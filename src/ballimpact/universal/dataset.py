"""The study dataset: one Parquet row per run and a companion NPZ of curves, written per batch.

Layout of a study folder::

    study.json                 the study's configuration (design, ranges, template, solver)
    runs/batch-00012.parquet   one row per run of batch 12: inputs, status, reason, P1..P19,
                               cor, peak_force_n, contact_time_s, energy_balance_error, ...
    runs/batch-00012.npz       run_id, force_shape (F/F_peak on GRID, t/t_contact from 0 to 1),
                               force_n_100khz (the pulse sampled at 100 kHz from first contact)

Each batch's files are written under a temporary name and renamed into place (atomic on POSIX),
the Parquet file last: a batch counts as done when its Parquet file exists, so an interrupted
study resumes with no lost and no duplicated runs.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError

#: normalised time grid of the stored force shapes (t / contact time)
SHAPE_POINTS = 64
SHAPE_GRID = np.linspace(0.0, 1.0, SHAPE_POINTS)
#: the stored pulses: 100 kHz from first contact, 6 ms
PULSE_RATE_HZ = 100e3
PULSE_SAMPLES = 600


def batch_paths(folder: Path, batch: int) -> tuple[Path, Path]:
    stem = folder / "runs" / f"batch-{batch:05d}"
    return stem.with_suffix(".parquet"), stem.with_suffix(".npz")


def done_batches(folder: Path) -> set[int]:
    runs = Path(folder) / "runs"
    if not runs.is_dir():
        return set()
    return {int(p.stem.split("-")[1]) for p in runs.glob("batch-*.parquet")}


def write_batch(folder: Path, batch: int, rows: list[dict[str, Any]],
                arrays: dict[str, np.ndarray]) -> None:
    """Write one batch atomically (NPZ first, Parquet last: the Parquet file marks it done)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    parquet, npz = batch_paths(Path(folder), batch)
    parquet.parent.mkdir(parents=True, exist_ok=True)
    tmp = npz.with_name(npz.stem + ".tmp.npz")
    np.savez(tmp, **arrays)
    os.replace(tmp, npz)
    tmp = parquet.with_name(parquet.stem + ".tmp.parquet")
    pq.write_table(pa.Table.from_pylist(rows), tmp)
    os.replace(tmp, parquet)


def load_dataset(folder: Path) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """All finished batches of a study: (columns, curves), rows sorted by run_id.

    `columns` maps each Parquet column to a NumPy array; `curves` holds `force_shape` and
    `force_n_100khz` aligned with the rows, plus `shape_grid` and `pulse_time_s`."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    folder = Path(folder)
    batches = sorted(done_batches(folder))
    if not batches:
        raise InputError(f"{folder}: no finished runs (expected runs/batch-*.parquet; "
                         "run `ballimpact universal run` first)")
    tables = [pq.read_table(batch_paths(folder, b)[0]) for b in batches]
    names = tables[0].column_names  # one column order, whatever order a batch was written in
    table = pa.concat_tables([t.select(names) for t in tables])
    columns = {name: table.column(name).to_numpy(zero_copy_only=False)
               for name in table.column_names}
    parts = [np.load(batch_paths(folder, b)[1], allow_pickle=False) for b in batches]
    curves = {key: np.concatenate([p[key] for p in parts]) for key in
              ("run_id", "force_shape", "force_n_100khz")}
    order = np.argsort(columns["run_id"], kind="stable")
    columns = {k: v[order] for k, v in columns.items()}
    curves_order = np.argsort(curves["run_id"], kind="stable")
    curves = {k: v[curves_order] for k, v in curves.items()}
    if not np.array_equal(curves["run_id"], columns["run_id"]):
        raise InputError(f"{folder}: the Parquet rows and NPZ curves disagree on run ids")
    curves["shape_grid"] = SHAPE_GRID
    curves["pulse_time_s"] = np.arange(PULSE_SAMPLES) / PULSE_RATE_HZ
    return columns, curves
