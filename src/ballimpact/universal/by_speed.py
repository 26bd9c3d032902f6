"""Identifications of several tests of one ball grouped by impact speed (`identify` with more
than one test): the scatter of repeats at one speed with the identification of their mean pulse,
and a speed-table ball file of the identified parameters against speed. `identify_tests` is the
whole of the `identify` command's work on processed tests."""

from __future__ import annotations

import warnings
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputWarning
from ..records.pipeline import process
from ..records.repeats import (DEFAULT_SPEED_TOLERANCE, check_masses, check_nominal, check_tolerance,
                       group_by_speed, mean_sd, pulse_band)
from .identify import Identification, identify
from .similarity import check_size


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
                   diameter_m: float | None = None, tolerances=None,
                   each: Callable[[Any, Identification], None] | None = None
                   ) -> IdentifiedTests:
    """The universal ball of each processed test (`identify`, with the FE check when `verify`),
    the tests grouped by speed first (`speed_groups`: errors before anything runs), the repeats
    at one speed summarised (`identify_repeats`) and the ball of them all; `diameter_m` (m):
    the tested ball's diameter (`similarity.check_size`), else the model's; `each(file,
    identification)` is called as each test is done."""
    groups = speed_groups(processed, files, nominal_m_s, tolerance)
    results = []
    for path, pr in zip(files, processed):
        size = None if diameter_m is None else check_size(diameter_m, pr.features.mass_kg,
                                                           allow)
        found = identify(pr, model, verify=verify, refine=refine, allow=allow, size=size,
                         tolerances=tolerances)
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
