"""Identifications of several tests of one ball grouped by impact speed (`identify` with more
than one test): the scatter of repeats at one speed with the identification of their mean pulse,
and a speed-table ball file of the identified parameters against speed. `identify_tests` is the
`identify` command's work on processed tests, `identify_files` the whole of it on record files."""

from __future__ import annotations

import json
import time
import warnings
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np

from ..checks import check_allow
from ..errors import InputError, InputWarning
from ..fileio import (check_distinct_files, check_output_file, check_plot_path, write_atomic,
                      write_table)
from ..records.options import RecordOptions
from ..records.pipeline import process
from ..records.repeats import (DEFAULT_SPEED_TOLERANCE, check_masses, check_nominal, check_tolerance,
                       group_by_speed, mean_sd, pulse_band)
from .compression_check import (COMPRESSION_TOLERANCE, check_compression_tolerance,
                                load_compression_test)
from .identify import Identification, check_speed, identify, reference_size
from .model import load_model
from .similarity import check_diameter, check_size


def speed_groups(processed: Sequence, files: Sequence[str | Path],
                 nominal_m_s: Sequence[float] | None = None,
                 tolerance: float = DEFAULT_SPEED_TOLERANCE) -> list[float]:
    """The speed group (m/s) of each processed test (`repeats.group_by_speed`, to `nominal_m_s`
    or clustered within `tolerance`): tests of one group are repeats at one speed. The tests
    are of one ball: masses within 1% (`repeats.check_masses`; one speed table, one ball);
    `files` name the tests in errors."""
    tolerance = check_tolerance(tolerance)
    nominal = None if nominal_m_s is None else check_nominal(nominal_m_s)
    speeds = [p.features.values["P15"] for p in processed]
    groups = [float(g) for g in group_by_speed(speeds, nominal, tolerance, files=files)]
    check_masses([p.features.mass_kg for p in processed], files, [0.0] * len(processed),
                 what="the tests of one command (one ball)")
    return groups


@dataclass
class IdentifiedTests:
    """`identify_tests`' result: `results` (file, processed test, `Identification`) per test,
    each test's speed group (m/s), the `repeats` (`identify_repeats`) and the identified `ball`
    (the test's ball, or with several tests the speed-table ball of `speed_table_ball`)."""

    results: list[tuple[Any, Any, Identification]]
    groups: list[float]
    repeats: list[dict[str, Any]]
    ball: dict[str, Any]

    def to_dict(self) -> dict[str, Any]:
        """One test: its identification and `file`; several: `identifications` (each with its
        `file`) and the speed `table`'s rows; `repeats` where a speed has several tests."""
        found = [{**f.to_dict(), "file": str(p)} for p, _, f in self.results]
        out: dict[str, Any] = found[0] if len(found) == 1 else {"identifications": found}
        if self.repeats:
            out["repeats"] = self.repeats
        if len(found) > 1:
            out["table"] = self.ball["speed_table"]["rows"]
        return out


def identify_tests(processed: Sequence, files: Sequence[str | Path], model, *,
                   nominal_m_s: Sequence[float] | None = None,
                   tolerance: float = DEFAULT_SPEED_TOLERANCE, verify: bool = True,
                   refine: str = "none", allow: Collection[str] = (),
                   diameter_m: float | None = None, tolerances=None, compression=None,
                   compression_tolerance: float = COMPRESSION_TOLERANCE,
                   each: Callable[[Any, Identification], None] | None = None
                   ) -> IdentifiedTests:
    """The universal ball of each processed test (`identify`, with the FE check when `verify`),
    the tests grouped by speed first (`speed_groups`: errors before anything runs), the repeats
    at one speed summarised (`identify_repeats`) and the ball of them all; `diameter_m` (m):
    the tested ball's diameter (`similarity.check_size`), else the model's; `compression`: a
    compression test of the ball, judged on each identified ball (`identify`); `each(file,
    identification)` is called as each test is done."""
    groups = speed_groups(processed, files, nominal_m_s, tolerance)
    results = []
    for path, pr in zip(files, processed):
        size = None if diameter_m is None else check_size(diameter_m, pr.features.mass_kg,
                                                           allow)
        found = identify(pr, model, verify=verify, refine=refine, allow=allow, size=size,
                         tolerances=tolerances, compression=compression,
                         compression_tolerance=compression_tolerance)
        results.append((path, pr, found))
        if each is not None:
            each(path, found)
    repeated = identify_repeats(results, groups, model, allow, diameter_m)
    ball = (results[0][2].ball if len(results) == 1
            else speed_table_ball([f for _, _, f in results], model, groups))
    return IdentifiedTests(results, groups, repeated, ball)


def identify_repeats(results: list, groups: list[float], model, allow,
                     diameter_m: float | None) -> list[dict[str, Any]]:
    """`results`: (file, processed test, `Identification`) per test; `groups`: each test's speed
    group (m/s). Per speed group of two or more tests: the mean and standard deviation (ddof =
    1) of the identified parameters and groups over the repeats (their scatter), and the
    identification of the group's mean pulse (aligned at contact start, `repeats.pulse_band`)
    with its 90% intervals; the ball's diameter `diameter_m` (m) maps another ball's tests."""
    out = []
    for label in sorted(set(groups)):
        members = [r for r, g in zip(results, groups) if g == label]
        if len(members) < 2:
            continue
        params_mean, params_sd = mean_sd([f.params for _, _, f in members])
        groups_mean, groups_sd = mean_sd([f.groups for _, _, f in members])
        mean_pulse = _identify_mean_pulse([pr for _, pr, _ in members], model, allow,
                                          diameter_m)
        out.append({"speed_m_s": label, "count": len(members),
                    "files": [str(p) for p, _, _ in members],
                    "params_mean": params_mean, "params_sd": params_sd,
                    "groups_mean": groups_mean, "groups_sd": groups_sd,
                    "mean_pulse": {"params": mean_pulse.params,
                                   "params_interval_90": mean_pulse.interval_90}})
    return out


def _identify_mean_pulse(processed: list, model, allow, diameter_m: float | None):
    """The universal ball of the mean pulse of repeats (`repeats.PulseBand.record`, at the
    repeats' mean mass and speeds), processed unfiltered (averaging has smoothed it) and
    identified without an FE check."""
    features = [p.features for p in processed]
    mean = {key: float(np.mean([f.values[key] for f in features])) for key in ("P15", "P16")}
    mass = float(np.mean([f.mass_kg for f in features]))
    record = pulse_band(features).record(mass, mean["P15"], mean["P16"])
    size = None if diameter_m is None else check_size(diameter_m, mass, allow)
    with warnings.catch_warnings():  # the repeats' own identifications said what applies
        warnings.simplefilter("ignore", InputWarning)
        return identify(process(record, filter="none", warn_noisy=False), model, verify=False,
                        allow=allow, size=size)


def speed_table_ball(found: list, model, groups: list[float]) -> dict[str, Any]:
    """A ball file holding the identified parameters against impact speed (the tests' ball:
    its size and mass are those of the first identification): a row per speed group, the mean
    of its repeats (speed and parameters)."""
    template = model.metadata["template"]
    layer = found[0].ball["layers"][0]
    keys = ("c10_pa", "c01_pa", "g1", "tau1_s")
    rows = []
    for label in sorted(set(groups)):
        members = [f for f, g in zip(found, groups) if g == label]
        rows.append({"speed_m_s": float(np.mean([f.impact_speed_m_s for f in members])),
                     **{k: float(np.mean([f.params[k] for f in members])) for k in keys}})
    return {"name": "identified-universal", "speed_table": {
        "outer_radius_m": layer["outer_radius_m"], "density_kg_m3": layer["density_kg_m3"],
        "moduli": template["moduli"], "rows": rows}}


def identify_files(files: Sequence[Path], *, options: RecordOptions = RecordOptions(),
                   model: str | Path | None = None,
                   verify: bool = True, refine: str = "none", allow: Collection[str] = (),
                   diameter_m: float | None = None,
                   nominal_m_s: Sequence[float] | None = None,
                   tolerance: float = DEFAULT_SPEED_TOLERANCE, tolerances=None,
                   compression: Path | None = None,
                   compression_tolerance: float = COMPRESSION_TOLERANCE,
                   table_path: Path | None = None, ball_path: Path | None = None,
                   plot_path: Path | None = None,
                   each: Callable[[Any, Identification], None] | None = None
                   ) -> tuple[IdentifiedTests, dict[str, Any]]:
    """`identify_tests` on the test record `files`, each loaded and processed as `options`
    say, with the universal `model` (a path, None: the
    built-in one); each impact speed (m/s) is checked against the model's training speeds
    before anything is processed. Writes the speed table (CSV, `table_path`, several files
    only), the identified ball (JSON, `ball_path`) and the tests with the identified balls'
    pulses (PNG, `plot_path`). `compression`: a compression test's CSV (the ball squeezed
    slowly between platens), a criterion of each FE check (`identify`). Returns the
    identifications and the command's result: `IdentifiedTests.to_dict` with `table_csv`,
    `ball_file`, `plot` where written and `wall_time_s`. `InputError`, before anything is
    loaded, for a bad output path (an output over an input included), `table_path` with one
    file, a diameter outside sports balls', an unknown `allow` name and a bad compression
    test."""
    started = time.perf_counter()
    check_plot_path(plot_path)
    if diameter_m is not None:  # before anything is loaded (the mass comes later)
        check_diameter(diameter_m)
    records = check_distinct_files(list(files), "FILE")
    inputs = set(records) | {p.with_suffix(".json") for p in records}  # and their side files
    if compression is not None:
        inputs.add(Path(compression).resolve())
    for path, flag, suffix in ((table_path, "--table", ".csv"),
                               (ball_path, "--ball-out", ".json")):
        if path is None:
            continue
        check_output_file(path, flag, suffix)
        if path.is_dir():
            raise InputError(f"{flag}: {path} is a folder; give a {suffix} file")
        if path.resolve() in inputs:
            raise InputError(f"{flag}: {path} is one of the inputs (test records, side files, "
                             "compression test); "
                             "writing it would overwrite the test: choose another name")
    if table_path is not None and len(files) < 2:
        raise InputError("--table: needs several test files (one per speed), got one; the "
                         "parameters of one test are in the output (--json) and its ball in "
                         "--ball-out")
    allow = check_allow(allow)
    options = options.allowing(allow)
    compression_tolerance = check_compression_tolerance(compression_tolerance)
    if compression is not None:
        if not verify:
            raise InputError("--compression: a criterion of the FE check, which --no-verify "
                             "turns off")
        compression = load_compression_test(compression)
    loaded = load_model(model)
    if compression is not None:  # a curve deeper than the ball can be squeezed: before any run
        radius = 0.5 * diameter_m if diameter_m is not None else reference_size(loaded).radius_m
        compression.check_against(SimpleNamespace(outer_radius_m=radius))
    tests = [options.load(path) for path in files]
    for path, record in zip(files, tests):  # before any processing or FE run
        if record.impact_speed_m_s is not None:
            check_speed(loaded, record.impact_speed_m_s, allow, f"{path}: ")
    found = identify_tests([options.process(record) for record in tests], files, loaded,
                           nominal_m_s=nominal_m_s, tolerance=tolerance, verify=verify,
                           refine=refine, allow=allow, diameter_m=diameter_m,
                           tolerances=tolerances, compression=compression,
                           compression_tolerance=compression_tolerance, each=each)
    out = found.to_dict()
    if "table" in out and table_path is not None:
        out["table_csv"] = write_table(table_path, list(out["table"][0]), out["table"], ".6g")
    if ball_path is not None:
        write_atomic(ball_path, json.dumps(found.ball, indent=2))
        out["ball_file"] = str(ball_path)
    if plot_path is not None:
        from .plots import plot_identification

        plot_identification([(Path(p).name, pr, f) for p, pr, f in found.results], plot_path)
        out["plot"] = str(plot_path)
    out["wall_time_s"] = time.perf_counter() - started
    return found, out
