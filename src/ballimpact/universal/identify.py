"""Identify a universal ball from one measured impact: features -> parameters with intervals
(inverse ensemble) -> optional refinement on the forward surrogate -> an FE run to verify."""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError, InputWarning
from . import space
from .compare import compare, features_pulse, pulse_nrmse
from .model import FEATURES, TARGETS, UniversalModel

REFINE = ("none", "surrogate")


@dataclass
class Identification:
    params: dict[str, float]                  # c10_pa, c01_pa, g1, tau1_s and mu0_pa (SI)
    interval_90: dict[str, list[float]]
    ball: dict[str, Any]                      # ball specification for `simulate --ball`
    impact_speed_m_s: float
    refine: str
    verification: dict[str, Any] | None = None
    simulated: Any = field(default=None, repr=False)   # FEResult of the verification
    wall_time_s: float = 0.0

    def to_dict(self) -> dict[str, Any]:
        return {"params": self.params, "params_interval_90": self.interval_90,
                "ball": self.ball, "impact_speed_m_s": self.impact_speed_m_s,
                "refine": self.refine, "verification": self.verification,
                "wall_time_s": self.wall_time_s}


def check_range(model: UniversalModel, values: dict[str, float]) -> None:
    """Warn for each feature outside the range the model was trained on."""
    ranges = model.metadata["feature_range"]
    for key in FEATURES:
        low, high = ranges[key]
        v = values[key]
        if not (low <= v <= high):
            from ..features import FEATURE_NAMES

            warnings.warn(f"{key} ({FEATURE_NAMES[key]}) = {v:.5g} is outside the model's "
                          f"training range {low:.5g}..{high:.5g}: the identification "
                          "extrapolates", InputWarning, stacklevel=2)


def estimate(model: UniversalModel, values: dict[str, float], refine: str = "none"):
    """Parameters (SI dict incl. mu0_pa) and 90% intervals from feature values (P1..P19)."""
    if refine not in REFINE:
        raise InputError(f"refine = {refine!r}: allowed {', '.join(REFINE)}")
    x = np.array([[values[k] for k in FEATURES]])
    est = model.estimate(x)
    params = dict(zip(TARGETS, est["values"][0].tolist()))
    interval = {k: [float(lo), float(hi)] for k, lo, hi in zip(TARGETS, est["low"][0], est["high"][0])}
    if refine == "surrogate":
        params = refine_on_surrogate(model, values, params)
    return params, interval


def refine_on_surrogate(model: UniversalModel, values: dict[str, float],
                        start: dict[str, float]) -> dict[str, float]:
    """Least squares on the forward surrogate: the material parameters (speed fixed, within the
    training ranges) whose predicted features (P15, the speed, excluded) best match the
    measured ones, in the standardised units the surrogate was trained in."""
    from scipy.optimize import least_squares

    names = space.MATERIAL_PARAMETERS
    ranges = model.ranges
    speed = values["P15"]
    measured = model.feature_scaler.forward(np.array([values[k] for k in FEATURES]))
    used = np.array([k != "P15" for k in FEATURES])

    def residual(u):
        p = space.from_unit(u[None], ranges, names)[0]
        out = model.simulate(np.array([[*p, speed]]))
        predicted = model.feature_scaler.forward(out["features"][0])
        return (predicted - measured)[used]

    u0 = np.clip(space.to_unit(np.array([[start[k] for k in names]]), ranges, names)[0],
                 1e-6, 1 - 1e-6)
    solution = least_squares(residual, u0, bounds=(0.0, 1.0), diff_step=1e-3, max_nfev=60)
    p = dict(zip(names, space.from_unit(solution.x[None], ranges, names)[0].tolist()))
    p["mu0_pa"] = 2.0 * (p["c10_pa"] + p["c01_pa"])
    return p


def identify(processed, model: UniversalModel, *, verify: bool = True,
             refine: str = "none", options=None) -> Identification:
    """Identify the universal ball from a processed test (`pipeline.process`)."""
    from ..fe import load_ball

    started = time.perf_counter()
    values = processed.features.values
    check_range(model, values)
    template = model.metadata["template"]
    mass = processed.features.mass_kg
    if mass and abs(mass / template["mass_kg"] - 1) > 0.02:
        warnings.warn(f"mass_kg = {mass:g} differs from the model's ball ({template['mass_kg']:g} "
                      "kg) by more than 2%: the identified ball keeps the model's mass",
                      InputWarning, stacklevel=2)
    params, interval = estimate(model, values, refine)
    spec = space.universal_ball_spec(params, template, "identified-universal")
    load_ball(spec)  # checked as `simulate --ball` will check it
    result = Identification(params, interval, spec, float(values["P15"]), refine)
    if verify:
        result.simulated, result.verification = verify_run(spec, processed.features, options)
    result.wall_time_s = time.perf_counter() - started
    return result


def verify_run(spec: dict, measured_features, options=None):
    """One FE run of the identified ball at the test's speed, compared with the test."""
    from ..features import extract_features
    from ..fe import SolverOptions, load_ball, simulate

    speed = measured_features.values["P15"]
    fe = simulate(load_ball(spec), speed, options or SolverOptions())
    simulated = extract_features(fe.record())
    nrmse = pulse_nrmse(*features_pulse(measured_features), *features_pulse(simulated))
    return fe, compare(measured_features.values, simulated.values, nrmse)
