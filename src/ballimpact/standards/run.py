"""A method run as `ballimpact standard METHOD` runs it (`run_method`): on a lab's records or on a
ball model, the inputs checked, with its CSV table."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..checks import check_allow
from ..errors import InputError
from ..fileio import check_output_file
from ..records.options import RecordOptions
from .lab import from_records
from .methods import Method, get_method
from .model import on_model
from .results import write_result_table


def run_method(method: str | Method, *, paths: Sequence[Path] = (), ball: str | None = None,
               mass_kg: float | None = None, ball_id_pattern: str | None = None,
               impact_speed_m_s: float | None = None, element_size_m: float | None = None,
               record_options: RecordOptions = RecordOptions(), allow=(),
               table: Path | None = None) -> dict[str, Any]:
    """`method` on a lab's records, `paths` (files or folders; `from_records` with `mass_kg`
    (kg), the ball ids by `ball_id_pattern` and `record_options`, how a record is loaded and
    processed, `records.RecordOptions`, `allow` joined to its own: `RecordOptions.allowing`),
    or on a ball model, `ball` (a preset or ball file;
    `on_model`, its mesh's element size `element_size_m`, m): one of the two.
    `impact_speed_m_s`: the impact methods run or judged at this speed (m/s) instead of the
    method's. `table`: the result's CSV (`write_result_table`) written there (a .csv file in an
    existing folder).

    Returns the result of `from_records` or `on_model`, with "table" (the path) when written.
    Raises `InputError` (naming the command's flags) for both or neither of `paths` and `ball`,
    a bad `table` path, `mass_kg` or `ball_id_pattern` with a ball, an unknown `allow` check,
    and what `from_records` and `on_model` raise."""
    method = get_method(method)
    if paths and ball is not None:
        raise InputError("give either FILES_OR_DIRS (a lab's records) or --ball (a model), not "
                         "both")
    if not paths and ball is None:
        raise InputError(f"{method.name}: give FILES_OR_DIRS (a lab's records) or --ball (a "
                         "ball model)")
    check_output_file(table, "--table", ".csv")
    allow = check_allow(allow)
    if ball is not None:
        if mass_kg is not None:
            raise InputError("--mass-kg: a ball model has its own mass; leave it out with --ball")
        if ball_id_pattern is not None:
            raise InputError("--ball-id-pattern: names the balls of records; leave it out with "
                             "--ball")
        result = on_model(method, ball, nominal=impact_speed_m_s, allow=allow,
                          element_size_m=element_size_m)
    else:
        result = from_records(method, paths, mass_kg=mass_kg, ball_of=ball_id_pattern,
                              nominal=impact_speed_m_s,
                              options=record_options.allowing(allow))
    if table is not None:
        result["table"] = write_result_table(table, result)
    return result
