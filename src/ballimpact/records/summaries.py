"""The `features` command's work on record files: each record loaded and processed, their
features summarised (one record, or many grouped by speed: `repeats`), the table and the plot
written."""

from __future__ import annotations

import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..fileio import check_output_file, check_plot_path
from . import repeats
from .options import RecordOptions
from .pipeline import ProcessedImpact


def features_of_files(
    paths: Sequence[Path],
    *,
    options: RecordOptions = RecordOptions(),
    nominal_m_s: Sequence[float] | None = None,
    tolerance: float = repeats.DEFAULT_SPEED_TOLERANCE,
    table_path: Path | None = None,
    plot_path: Path | None = None,
) -> tuple[dict[str, Any], list[ProcessedImpact]]:
    """The `features` command on the records of `paths` (`repeats.record_files`: folders too,
    less the table output), each loaded and processed as `options` say: with several,
    `repeats.summarise_repeats` (grouped to `nominal_m_s`, m/s, or clustered within the
    relative `tolerance`), with one, `repeats.record_summary` (the record must lie within
    `tolerance` of a nominal speed). Writes the table, a row per record
    (`repeats.write_speed_table`, CSV, `table_path`), and the record's pulse, or the groups'
    mean pulses with their bands (PNG, `plot_path`). Returns the result, with `wall_time_s`,
    `table_csv` and `plot` where written, and the processed records. `InputError`, before
    anything is loaded, for a bad output path, tolerance or nominal speed."""
    check_plot_path(plot_path)
    check_output_file(table_path, "--table", ".csv")
    repeats.check_tolerance(tolerance)
    if nominal_m_s is not None:
        repeats.check_nominal(nominal_m_s)
    files = repeats.record_files(paths, table_path)
    started = time.perf_counter()
    processed = [options.process(options.load(path)) for path in files]
    if len(files) > 1:  # a row each, grouped by speed, with per-group means and SDs
        result = repeats.summarise_repeats(processed, files, nominal_m_s, tolerance)
        rows = result["records"]
    else:  # a single record must still lie near a nominal speed
        group = repeats.record_group(processed[0], files[0], nominal_m_s, tolerance)
        result = repeats.record_summary(processed[0])
        rows = [repeats.record_row(processed[0], files[0], group)]
    result["wall_time_s"] = time.perf_counter() - started
    if table_path is not None:
        result["table_csv"] = repeats.write_speed_table(table_path, rows)
    if plot_path is not None:
        from .. import plotting  # matplotlib only when a plot is asked for

        if len(files) > 1:
            plotting.plot_repeats(processed, [row["group_speed_m_s"] for row in rows], plot_path)
        else:
            plotting.plot_impact(processed[0].raw, processed[0].filtered, processed[0].features,
                                 plot_path, title=str(files[0].name))
        result["plot"] = str(plot_path)
    return result, processed
