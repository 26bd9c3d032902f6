"""The files of `ballimpact calibrate`: its tests named by file (impact tests already processed,
compression curves read from their CSVs), its results written to the output folder
(docs/calibrate.md), and the calibration from those files to those results
(`calibrate_from_files`)."""

from __future__ import annotations

import json
import warnings
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

from ..checks import check_allow, check_integer, check_range
from ..errors import InputError, InputWarning
from ..fileio import check_output_folder, check_plot_path, json_safe, write_atomic
from ..records.datasets import PREFIX, is_builtin
from ..records.options import RecordOptions
from .compression import DEFAULT_STEPS, CompressionTest, read_compression_csv
from .problem import CalibrationTest

#: the files `write_results` puts in the output folder
BALL_FILE = "calibrated-ball.json"
RESULT_FILE = "calibration.json"


def parse_test(text: str) -> tuple[Path, float | None, str | None]:
    """FILE[:SPEED[:LAYER]] of --test (FILE may be `builtin:NAME`) -> (path, speed (m/s) or
    None, layer or None); `InputError` naming --test for a speed that is not a number > 0."""
    prefix = text[:len(PREFIX)] if is_builtin(text) else ""  # builtin:NAME[:SPEED]
    path, _, rest = text[len(prefix):].partition(":")
    path = prefix + path
    speed_text, _, layer = rest.partition(":")
    speed = None
    if speed_text:
        try:
            speed = float(speed_text)
        except ValueError:
            raise InputError(f"--test {text}: the speed {speed_text!r} is not a number "
                             "(FILE[:SPEED[:LAYER]])") from None
        check_range(f"--test {text}: speed", speed, 0.0, low_open=True, unit="m/s",
                    note="FILE[:SPEED[:LAYER]]")
    return Path(path), speed, layer or None


def parse_compression(text: str) -> tuple[Path, str | None]:
    """FILE.csv[:LAYER] of --compression -> (path, layer or None)."""
    path, _, layer = text.partition(":")
    if not path:
        raise InputError(f"--compression {text!r}: expected FILE.csv[:LAYER]")
    return Path(path), layer or None


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
    if rate is not None:
        check_range("--compression-rate-m-s", rate, 0.0, low_open=True, unit="m/s",
                    note="the platen speed; leave it out for the long-term (fully relaxed) "
                         "curve")
    compression_steps = check_integer("--compression-steps", compression_steps, 1)
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


def calibrate_from_files(ball: str | Path, bounds: dict[str, tuple[float, float]], options, *,
                         tests: Sequence[str] = (), compressions: Sequence[str] = (),
                         record_options: RecordOptions = RecordOptions(),
                         impact_speed_m_s: float | None = None,
                         compression_rate_m_s: float | None = None,
                         compression_steps: int = DEFAULT_STEPS, objectives=None,
                         method: str = "nsga2", stages=None, population: int = 24,
                         generations: int = 8, seed: int = 0, decision: str = "knee",
                         weights=None, out: Path | None = None, resume: bool = False,
                         max_evaluations: int = 30, allow=(),
                         plot_path: Path | None = None) -> tuple[dict[str, Any], list]:
    """`ballimpact calibrate`: the ball `ball` (preset or specification file, its constants at
    the first impact test's speed, else at `impact_speed_m_s` (m/s)) calibrated by
    `calibration.calibrate` (the free parameters' `bounds` (SI), the solver `options` and the
    search's arguments as there; checkpoints, and with `resume` the search continued, in the
    folder `out`) against the impact tests `tests` (FILE[:SPEED[:LAYER]], `parse_test`: each
    loaded and processed as `record_options` say, SPEED (m/s) over its impact speed) and the
    compression curves `compressions` (FILE.csv[:LAYER]; `calibration_tests` with
    `compression_rate_m_s` (m/s) and `compression_steps`). With `out` the results are written
    there (`write_results`), with `plot_path` a PNG of the last stage's pulses. Returns (the
    result of `calibrate` without its stage results, with `ball_file` and `plot` where
    written; the `StageResult`s). Raises `InputError` (naming the flag) on bad paths, no test,
    a test without an impact speed, and what `calibrate` raises."""
    from ..fe import load_ball
    from .calibration import calibrate

    check_plot_path(plot_path)
    if out is not None:
        if out.exists() and not out.is_dir():
            raise InputError(f"--out {out}: is a file; give a folder (it holds the "
                             "evaluations, plots and the calibrated ball)")
        check_output_folder(out, "--out")
    if not tests and not compressions:
        raise InputError("--test or --compression: give at least one test (an impact record, "
                         "or a compression curve)")
    impacts = []
    record_options = record_options.allowing(check_allow(allow))
    for text, (path, speed, layer) in zip(tests, [parse_test(text) for text in tests]):
        # the test's own SPEED wins over the side file's and the options' impact speed
        given = record_options if speed is None else replace(record_options,
                                                               impact_speed_m_s=speed)
        record = given.load(path)
        if record.impact_speed_m_s is None:
            raise InputError(f"--test {text}: no impact speed; give it as {path}:SPEED (m/s) "
                             "or in the side file (impact_speed_m_s)")
        impacts.append((path, record_options.process(record).features, layer))
    found = calibration_tests(impacts, [parse_compression(text) for text in compressions],
                              compression_rate_m_s=compression_rate_m_s,
                              compression_steps=compression_steps)
    speed = found[0].impact_speed_m_s if impacts else impact_speed_m_s  # impacts come first
    template = load_ball(ball, speed, allow=allow).to_dict()
    result = calibrate(template, found, bounds, options, objectives=objectives, method=method,
                       stages=stages, population=population, generations=generations,
                       seed=seed, decision=decision, weights=weights, out=out, resume=resume,
                       max_evaluations=max_evaluations, allow=allow)
    stage_results = result.pop("stage_results")
    warn_one_layer(template, found, result)
    if out is not None:
        write_results(out, result)
    if plot_path is not None:
        from .plots import plot_pulses

        last = stage_results[-1]
        plot_pulses(last.problem.tests, last.runs, plot_path, "calibrated ball")
        result["plot"] = str(plot_path)
    return result, stage_results


def warn_one_layer(template: dict[str, Any], tests: Sequence, result: dict[str, Any]) -> None:
    """An `InputWarning` when a one-layer ball calibrated against impact and compression tests
    together misses either: each objective's value as the last stage that fitted it left it (a
    later stage may have moved it a little), against the
    model checks' tolerances (`verdict.Tolerances`: force NRMSE, COR, contact time, peak force;
    `verdict.COMPRESSION_TOLERANCE`). One homogeneous layer ties the impact's instantaneous
    moduli to the compression's relaxed ones through its g1, and a layered ball (core and cover)
    is the way on (docs/calibrate.md, "Layered balls from tests")."""
    from ..verdict import COMPRESSION_TOLERANCE, Tolerances

    if len(template["layers"]) != 1 or {t.kind for t in tests} != {"impact", "compression"}:
        return
    last: dict[str, float] = {}
    for stage in result["stages"]:
        last.update(stage["chosen"]["objectives"])
    tolerances = Tolerances()
    allowed = {"nrmse": tolerances.force_nrmse, "cor": tolerances.cor,
               "contact_time": tolerances.contact_time, "peak_force": tolerances.peak_force,
               "compression": COMPRESSION_TOLERANCE}
    missed = [f"{name} {value:.3g} > {allowed[name]:g}" for name, value in last.items()
              if name in allowed and not abs(value) <= allowed[name]]
    if missed:
        warnings.warn(f"one homogeneous layer may not give the impact and the compression tests "
                      f"together ({', '.join(missed)}, each as the last stage that fitted it left "
                      "it; a parameter on its bound or a search that stopped early can also do "
                      "this); calibrate a layered ball (core and cover) against both: "
                      "docs/calibrate.md, 'Layered balls from tests'", InputWarning, stacklevel=2)


__all__ = ["BALL_FILE", "RESULT_FILE", "calibrate_from_files", "calibration_tests",
           "parse_compression", "parse_test", "warn_one_layer", "write_results"]
