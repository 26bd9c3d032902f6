"""The design space of the universal ball: its four material parameters and the impact speed.

The universal ball (thesis chapter 6) is one homogeneous Mooney-Rivlin layer (D1 = 0) with one
Prony term; its radius, mass and moduli convention come from a template ball and stay fixed in a
study. Default ranges: thesis table 6-2 (C10 4-7 MPa, C01 -1..1 MPa, g1 0-1 capped at 0.9 so
that the instantaneous modulus stays within 10x the long-term one, tau1 1e-5..1e-4 s) and speeds
5-45 m/s (the thesis' tests at 5.5-25 m/s and its future-work 45 m/s inside). tau1 is sampled
and learned in log scale (a time constant: each decade counts the same), the others linearly.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from ..errors import InputError

#: parameter -> (default low, default high, unit)
PARAMETERS: dict[str, tuple[float, float, str]] = {
    "c10_pa": (4.0e6, 7.0e6, "Pa"),
    "c01_pa": (-1.0e6, 1.0e6, "Pa"),
    "g1": (0.0, 0.9, "1"),
    "tau1_s": (1.0e-5, 1.0e-4, "s"),
    "impact_speed_m_s": (5.0, 45.0, "m/s"),
}
MATERIAL_PARAMETERS = ("c10_pa", "c01_pa", "g1", "tau1_s")
LOG_SCALED = ("tau1_s",)
#: hard limits of each range (physics or the solver's validated envelope)
ALLOWED: dict[str, tuple[float, float]] = {
    "c10_pa": (1e4, 1e9), "c01_pa": (-1e9, 1e9), "g1": (0.0, 0.99), "tau1_s": (1e-8, 1.0),
    "impact_speed_m_s": (0.1, 100.0)}
METHODS = ("sobol", "lhs")


def default_ranges() -> dict[str, tuple[float, float]]:
    return {name: (low, high) for name, (low, high, _) in PARAMETERS.items()}


def check_ranges(ranges: dict[str, Any]) -> dict[str, tuple[float, float]]:
    """Default ranges updated by `ranges` (name -> (low, high), SI), checked."""
    out = default_ranges()
    for name, value in ranges.items():
        if name not in PARAMETERS:
            raise InputError(f"range {name!r}: unknown; allowed {', '.join(PARAMETERS)}")
        try:
            low, high = (float(v) for v in value)
        except (TypeError, ValueError):
            raise InputError(f"range {name}: expected LOW:HIGH numbers in SI, got {value!r}") \
                from None
        lo_allowed, hi_allowed = ALLOWED[name]
        if not (math.isfinite(low) and math.isfinite(high) and low <= high):
            raise InputError(f"range {name} = {low:g}:{high:g}: need finite LOW <= HIGH")
        if low < lo_allowed or high > hi_allowed:
            raise InputError(f"range {name} = {low:g}:{high:g}: allowed within "
                             f"{lo_allowed:g}:{hi_allowed:g} {PARAMETERS[name][2]}")
        out[name] = (low, high)
    return out


def _scale(name: str, value):
    """The axis a parameter is sampled and learned on: log for `LOG_SCALED`, else linear."""
    return np.log(value) if name in LOG_SCALED else value


def to_unit(values: np.ndarray, ranges: dict[str, tuple[float, float]],
            names=tuple(PARAMETERS)) -> np.ndarray:
    """Columns `names` of `values` (SI) mapped to [0, 1] on each parameter's axis (`_scale`)."""
    values = np.asarray(values, dtype=np.float64)
    out = np.empty_like(values)
    for j, name in enumerate(names):
        lo, hi = (_scale(name, np.float64(x)) for x in ranges[name])
        out[..., j] = (_scale(name, values[..., j]) - lo) / (hi - lo) if hi > lo else 0.5
    return out


def from_unit(unit: np.ndarray, ranges: dict[str, tuple[float, float]],
              names=tuple(PARAMETERS)) -> np.ndarray:
    """Inverse of `to_unit` (the range ends come back exactly)."""
    unit = np.asarray(unit, dtype=np.float64)
    out = np.empty_like(unit)
    for j, name in enumerate(names):
        low, high = ranges[name]
        lo, hi = (_scale(name, np.float64(x)) for x in (low, high))
        u = unit[..., j]
        value = lo + u * (hi - lo)
        value = np.exp(value) if name in LOG_SCALED else value
        out[..., j] = np.where(u == 0, low, np.where(u == 1, high, value))
    return out


def sample(runs: int, seed: int, method: str, ranges: dict[str, tuple[float, float]]) -> np.ndarray:
    """`runs` points (rows: c10_pa, c01_pa, g1, tau1_s, impact_speed_m_s in SI) of a scrambled
    Sobol sequence or a Latin hypercube, seeded. The same (runs, seed, method, ranges) always
    gives the same points."""
    from scipy.stats import qmc

    if method not in METHODS:
        raise InputError(f"method = {method!r}: allowed {', '.join(METHODS)}")
    if not (isinstance(runs, int) and runs >= 1):
        raise InputError(f"runs = {runs}: need an integer >= 1")
    d = len(PARAMETERS)
    if method == "sobol":
        with warnings.catch_warnings():  # balance is best at powers of 2; any count is valid
            warnings.simplefilter("ignore", UserWarning)
            unit = qmc.Sobol(d, scramble=True, seed=seed).random(runs)
    else:
        unit = qmc.LatinHypercube(d, seed=seed).random(runs)
    return from_unit(unit, ranges)


def universal_ball_spec(params: dict[str, float], template: dict[str, Any],
                        name: str) -> dict[str, Any]:
    """The ball specification (`simulate --ball`'s JSON form) of the universal ball with
    `params` (c10_pa, c01_pa, g1, tau1_s) on a study's template (`template_geometry`)."""
    from ..fe.ball import universal_spec

    return universal_spec(params, template["radius_m"], template["density_kg_m3"],
                          template["moduli"], name)


def template_geometry(ball) -> dict[str, Any]:
    """Radius, homogeneous density giving the template's mass, and moduli convention."""
    radius = ball.layers[-1].outer_radius_m
    mass = ball.mass_kg
    density = mass / (4.0 / 3.0 * math.pi * radius ** 3)
    moduli = ball.layers[0].material.moduli
    return {"template": ball.name, "radius_m": radius, "mass_kg": mass,
            "density_kg_m3": density, "moduli": moduli}
