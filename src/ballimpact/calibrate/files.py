"""The files of `ballimpact calibrate`: its tests named by file (impact tests already processed,
compression curves read from their CSVs), and its results written to the output folder
(docs/calibrate.md)."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..fileio import json_safe, write_atomic
from .compression import DEFAULT_STEPS, CompressionTest, read_compression_csv
from .problem import CalibrationTest

#: the files `write_results` puts in the output folder
BALL_FILE = "calibrated-ball.json"
RESULT_FILE = "calibration.json"


def calibration_tests(impacts: Sequence[tuple[Path, Any, str | None]],
                      compressions: Sequence[tuple[Path, str | None]] = (), *,
                      compression_rate_m_s: float | None = None,
                      compression_steps: int = DEFAULT_STEPS) -> list:
    """The tests of a calibration: a `CalibrationTest` per (file, `ImpactFeatures`, layer) of
    `impacts`, then a `CompressionTest` per (CSV file, layer) of `compressions` (read by
    `read_compression_csv`; `compression_rate_m_s` the platen speed, None for the fully relaxed
    curve; `compression_steps` increments of the FE curve), each named by its file's stem (a
    stem already taken gets -N)."""
    tests: list = []
    names: set[str] = set()
    for path, features, layer in impacts:
        stem = Path(path).stem
        name = stem if stem not in names else f"{stem}-{len(tests)}"
        names.add(name)
        tests.append(CalibrationTest(name, features, layer))
    rate = compression_rate_m_s
    if rate is not None and not (math.isfinite(rate) and rate > 0):
        raise InputError(f"--compression-rate-m-s {rate:g}: must be > 0 (m/s), the platen "
                         "speed; leave it out for the long-term (fully relaxed) curve")
    if compression_steps < 1:
        raise InputError(f"--compression-steps {compression_steps}: must be an integer >= 1")
    for path, layer in compressions:
        path = Path(path)
        deflection, force = read_compression_csv(path)
        name = path.stem if path.stem not in names else f"{path.stem}-{len(names)}"
        names.add(name)
        tests.append(CompressionTest(name, deflection, force, layer, rate, compression_steps,
                                     str(path)))
    return tests


def write_results(out: Path, result: dict[str, Any]) -> None:
    """The calibrated ball (`BALL_FILE`, its path put in `result["ball_file"]`) and the result
    of `calibration.calibrate` without its stage results (`RESULT_FILE`) into the folder
    `out`."""
    ball_file = Path(out) / BALL_FILE
    write_atomic(ball_file, json.dumps(result["ball"], indent=2))
    result["ball_file"] = str(ball_file)
    write_atomic(Path(out) / RESULT_FILE, json.dumps(json_safe(result), indent=2))


__all__ = ["BALL_FILE", "RESULT_FILE", "calibration_tests", "write_results"]
