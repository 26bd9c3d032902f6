"""Identifications of several tests of one ball grouped by impact speed (`identify` with more
than one test): the scatter of repeats at one speed with the identification of their mean pulse,
and a speed-table ball file of the identified parameters against speed."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ..errors import InputWarning
from ..pipeline import process
from ..repeats import mean_sd, pulse_band
from .identify import identify
from .similarity import check_size


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
