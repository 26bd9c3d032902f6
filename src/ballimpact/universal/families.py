"""The size-free model's closed loop on balls of other sports: synthetic tests of homogeneous
balls of a family's size and mass, measured at 100 kHz with noise, identified with a universal
model and re-simulated.

Two kinds of family: a ball's size with constants inside the model's own ranges mapped onto it
(`family_tests`, below), or a material family of `data/ball_families.json` (`material_family`:
its size and typical boxes of the constants and speeds, `family_box_tests`), which is what a
model of the groups is checked on.

The test balls' constants are drawn (seeded Sobol) inside the model's ranges as they map onto the
family's ball (`similarity.map_params`), over the inner `INNER` fraction of each range on the
parameter's own axis (tau1: log), at speeds across the model's training speeds: every test lies
inside the model's dimensionless ranges by construction, as a real ball of that family would be
only if its material is (docs/universal.md, "Any solid ball").
"""

from __future__ import annotations

import json
import warnings
from importlib import resources
from typing import Any

import numpy as np

from ..errors import InputError, InputWarning
from . import space
from ..comparison import compare, pulse_nrmse
from ..progress import end_line, redraw_line
from .evaluate import PERCENTILE
from .identify import identify, reference_size, scaled_options
from .model import UniversalModel
from .similarity import BallSize, map_params

#: the centre fraction of each range the test balls are drawn from (unit scale)
INNER = 0.8
#: the families of the issue's check (sizes: `data/sports_balls.json`, the rules' middles)
FAMILIES = ("baseball", "softball-12in", "lacrosse", "golf-core")


def sports_balls() -> dict[str, Any]:
    """The sports balls' sizes and masses from their rules (`data/sports_balls.json`)."""
    text = resources.files("ballimpact").joinpath("data/sports_balls.json").read_text()
    return json.loads(text)["balls"]


def nominal_size(name: str) -> BallSize:
    """The middle of a sports ball's diameter and mass limits."""
    ball = sports_balls()[name]
    return BallSize(0.25 * sum(ball["diameter_m"]), 0.5 * sum(ball["mass_kg"]))


def family_tests(model: UniversalModel, size: BallSize, runs: int, seed: int
                 ) -> tuple[list[dict], np.ndarray]:
    """`runs` constants (c10_pa, c01_pa, g1, tau1_s) of balls of `size` inside the model's ranges
    (mapped), and their impact speeds (m/s): the study's seeded Sobol design (`space.sample`)
    over the inner `INNER` of each range."""
    names = list(space.PARAMETERS)
    ends = space.from_unit(np.outer([0.5 - INNER / 2, 0.5 + INNER / 2], np.ones(len(names))),
                           model.ranges)
    inner = {name: (ends[0, j], ends[1, j]) for j, name in enumerate(names)}
    points = space.sample(runs, seed, "sobol", inner)
    reference = reference_size(model)
    params = [map_params(dict(zip(space.MATERIAL_PARAMETERS, p[:4])), reference, size)
              for p in points]
    return params, points[:, -1]


#: the material families of issue 42's check, in `data/ball_families.json`
MATERIAL_FAMILIES = ("lacrosse-soft", "softball", "baseball", "cricket", "hockey-hard",
                     "golf-core-stiff")
_BOX = ("mu0_pa", "c01_over_c10", "g1", "tau1_s", "impact_speed_m_s")


def material_family(name: str) -> dict[str, Any]:
    """A material family (`data/ball_families.json`): its ball, boxes and basis."""
    text = resources.files("ballimpact").joinpath("data/ball_families.json").read_text()
    families = json.loads(text)["families"]
    if name not in families:
        raise InputError(f"family {name!r}: unknown; allowed {', '.join(families)}")
    return families[name]


def family_box_tests(name: str, runs: int, seed: int) -> tuple[BallSize, list[dict], np.ndarray]:
    """The ball of material family `name`, `runs` constants (c10_pa, c01_pa, g1, tau1_s) from
    a seeded Sobol design over its boxes (mu0 and tau1 on log axes) and their impact speeds."""
    family = material_family(name)
    size = nominal_size(family["ball"])
    log = ("mu0_pa", "tau1_s")
    unit = space.unit_sample(runs, seed, "sobol", len(_BOX))
    values = {}
    for j, key in enumerate(_BOX):
        low, high = family[key]
        u = unit[:, j]
        values[key] = low * (high / low) ** u if key in log else low + u * (high - low)
    c10 = values["mu0_pa"] / (2.0 * (1.0 + values["c01_over_c10"]))
    params = [{"c10_pa": float(a), "c01_pa": float(a * r), "g1": float(g), "tau1_s": float(t)}
              for a, r, g, t in zip(c10, values["c01_over_c10"], values["g1"], values["tau1_s"])]
    return size, params, values["impact_speed_m_s"]


def family_closed_loop(model: UniversalModel, size: BallSize, *, runs: int = 12,
                       noise: float = 0.01, seed: int = 0, label: str = "",
                       tests: tuple[list[dict], np.ndarray] | None = None) -> dict[str, Any]:
    """Synthetic tests of balls of `size` (FE runs of the model's mesh scaled to the ball, pulses
    at 100 kHz with white noise of `noise` times the peak force, processed as measured tests),
    each identified with `model` (`identify(..., size=size)`) and its identified ball compared
    with the clean test: force NRMSE, COR error, contact time and peak force errors per run, and
    their median, 90th percentile and maximum. `tests`: the balls' constants and speeds
    (`family_box_tests`), default `family_tests` inside the model's ranges."""
    from ..fe import FailedRun, load_ball, simulate_batch
    from ..records.features import extract_features
    from ..records.pipeline import process
    from ..comparison import PULSE_RATE_HZ, noisy_record
    from .study import pulse_100khz

    params, speeds = tests if tests is not None else family_tests(model, size, runs, seed)
    runs = len(params)
    options = scaled_options(model, size)
    spec = [_spec(p, size, model, f"{label}-test-{i}") for i, p in enumerate(params)]
    truths = simulate_batch([load_ball(s, allow={"ball-units"}) for s in spec], speeds, options)
    rng = np.random.default_rng(seed)
    found = []
    for i, (truth, speed) in enumerate(zip(truths, speeds)):
        record = noisy_record(pulse_100khz(truth), float(speed), truth.cor, size.mass_kg, noise,
                              rng)
        with warnings.catch_warnings():  # the estimate's own notes are in the rows
            warnings.simplefilter("ignore", InputWarning)
            found.append(identify(process(record, warn_noisy=False), model, verify=False,
                                  size=size, allow={"ball-units"}))
        redraw_line(f"{label}: identified {i + 1}/{runs}")
    end_line()
    results = simulate_batch([load_ball(f.ball, allow={"ball-units"}) for f in found], speeds,
                             options, on_failure="return")
    t = np.arange(pulse_100khz(truths[0]).size) / PULSE_RATE_HZ
    rows = []
    for p, speed, truth, f, result in zip(params, speeds, truths, found, results):
        row = {"impact_speed_m_s": float(speed), "true": p, "identified": f.params,
               "groups": f.groups, "at_training_bound": f.at_training_bound}
        if isinstance(result, FailedRun):
            rows.append({**row, "failed": result.reason})
            continue
        h = result.history
        nrmse = pulse_nrmse(t, pulse_100khz(truth), h["time_s"], h["contact_force_n"])
        try:
            simulated = extract_features(result.record()).values
        except InputError as error:  # e.g. a pulse split in two: counted as failed, not lost
            rows.append({**row, "failed": f"features: {error}"})
            continue
        rows.append({**row, **compare(extract_features(truth.record()).values, simulated,
                                      nrmse)})
    ok = [r for r in rows if "failed" not in r]
    summary: dict[str, Any] = {"family": label, "diameter_m": 2 * size.radius_m,
                               "mass_kg": size.mass_kg, "runs": len(rows),
                               "failed": len(rows) - len(ok), "noise_of_peak": noise,
                               "speeds_m_s": [float(min(speeds)), float(max(speeds))]}
    for key in ("force_nrmse", "cor_error", "contact_time_relative_error",
                "peak_force_relative_error"):
        v = np.abs([r[key] for r in ok])
        summary[key] = {"median": float(np.median(v)),
                        f"p{PERCENTILE}": float(np.percentile(v, PERCENTILE)),
                        "max": float(v.max())}
    return {"summary": summary, "rows": rows}


def _spec(params: dict, size: BallSize, model: UniversalModel, name: str) -> dict:
    """The universal ball of `params`; a `prony` list of terms ({"g", "tau_s"}) in them stands
    for the one term g1, tau1_s (a test ball the model cannot be: benchmarks/
    bench_second_prony.py)."""
    from ..balls.ball import universal_spec

    spec = universal_spec(params, size.radius_m, size.density_kg_m3,
                          model.metadata["template"]["moduli"], name)
    if "prony" in params:
        spec["layers"][0]["material"]["prony"] = [dict(term) for term in params["prony"]]
    return spec
