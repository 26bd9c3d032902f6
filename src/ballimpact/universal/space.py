"""The design space of the universal ball: its four material parameters and the impact speed.

The universal ball (thesis chapter 6) is one homogeneous Mooney-Rivlin layer (D1 = 0) with one
Prony term; its radius, mass and moduli convention come from a template ball and stay fixed in a
study. Default ranges: thesis table 6-2 (C10 4-7 MPa, C01 -1..1 MPa, g1 0-1 capped at 0.9 so
that the instantaneous modulus stays within 10x the long-term one, tau1 1e-5..1e-4 s) and speeds
5-45 m/s (the thesis' tests at 5.5-25 m/s and its future-work 45 m/s inside). tau1 is sampled
and learned in log scale (a time constant: each decade counts the same), the others linearly.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Collection
from typing import Any

import numpy as np

from ..checks import check_integer, check_range
from ..errors import InputError
from ..balls.checks import BALL_RANGES
from ..fe.speed_range import FE_SPEED_RANGE_M_S
from ..checks import check_allow, flag
PARAMETERS: dict[str, tuple[float, float, str]] = {
    "c10_pa": (4.0e6, 7.0e6, "Pa"),
    "c01_pa": (-1.0e6, 1.0e6, "Pa"),
    "g1": (0.0, 0.9, "1"),
    "tau1_s": (1.0e-5, 1.0e-4, "s"),
    "impact_speed_m_s": (5.0, 45.0, "m/s"),
}
MATERIAL_PARAMETERS = ("c10_pa", "c01_pa", "g1", "tau1_s")
#: The design space of a study in the dimensionless groups (`similarity.GROUPS`), the box that
#: covers solid sports balls at 5-60 m/s as far as the FE engine reaches (docs/universal.md,
#: "A study in the groups"): rho v^2 / mu0 from hard hockey and golf cores at 5 m/s (2e-4) to
#: the softest ball the engine runs without crushing its elements (0.25; at 0.3 an elastic ball
#: stops unstable), C01 / C10 and g1 as the thesis' table 6-2 gives them on a cricket ball,
#: tau1 v / R over three decades around the contact time (t_c v / R 0.06-1.4).
GROUP_PARAMETERS: dict[str, tuple[float, float, str]] = {
    "rho_v2_over_mu0": (2.0e-4, 0.25, "1"),
    "c01_over_c10": (-0.25, 0.25, "1"),
    "g1": (0.0, 0.9, "1"),
    "tau1_v_over_r": (5.0e-4, 1.0, "1"),
}
#: hard limits of each group's range: the FE engine's (rho v^2 / mu0 above 0.3 crushes the
#: elements of an elastic ball) and the materials' (C01 / C10 > -1: mu0 > 0)
GROUP_ALLOWED: dict[str, tuple[float, float]] = {
    "rho_v2_over_mu0": (1e-6, 0.3), "c01_over_c10": (-0.9, 1.0), "g1": (0.0, 0.99),
    "tau1_v_over_r": (1e-6, 100.0)}
_GROUP_NOTES = {"rho_v2_over_mu0": "above 0.3 the FE engine crushes an elastic ball's elements",
                "c01_over_c10": "mu0 = 2 C10 (1 + C01 / C10) must stay positive",
                "g1": "the relaxing fraction of the modulus",
                "tau1_v_over_r": "tau1 against the time to cross the ball"}
#: the design spaces of a study: the material constants and speed on its template ball, or the
#: dimensionless groups (speed chosen per run, `run_speed`)
DESIGN_SPACES = ("material", "groups")
LOG_SCALED = ("tau1_s", "rho_v2_over_mu0", "tau1_v_over_r")
#: hard limits of each range (physics, or the FE solver's checked speeds: a study must not
#: stop at its first run outside them)
ALLOWED: dict[str, tuple[float, float]] = {
    "c10_pa": (1e4, 1e9), "c01_pa": (-1e9, 1e9), "g1": (0.0, 0.99), "tau1_s": (1e-8, 1.0),
    "impact_speed_m_s": FE_SPEED_RANGE_M_S}
METHODS = ("sobol", "lhs")


def default_ranges() -> dict[str, tuple[float, float]]:
    return {name: (low, high) for name, (low, high, _) in PARAMETERS.items()}


def check_ranges(ranges: dict[str, Any], allow: Collection[str] = ()
                 ) -> dict[str, tuple[float, float]]:
    """Default ranges updated by `ranges` (name -> (low, high), SI), checked; `allow` holding
    "ball-units" makes balls softer than sports balls a warning."""
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
        if not (math.isfinite(low) and math.isfinite(high) and low < high):
            # an empty range would divide by its width in the unit scaling and the R^2
            raise InputError(f"range {name} = {low:g}:{high:g}: need finite LOW < HIGH"
                             + (" (swapped?)" if low > high else ""))
        unit = PARAMETERS[name][2] if PARAMETERS[name][2] != "1" else ""
        for end, bound in (("LOW", low), ("HIGH", high)):
            check_range(f"range {name} {end}", bound, lo_allowed, hi_allowed, unit=unit)
        out[name] = (low, high)
    # every ball of the design must be loadable: Mooney-Rivlin needs C10 + C01 > 0 (its initial
    # shear modulus is mu0 = 2 (C10 + C01)); the softest corner of the ranges decides
    softest = out["c10_pa"][0] + out["c01_pa"][0]
    if softest <= 0:
        raise InputError(f"ranges c10_pa low {out['c10_pa'][0]:g} + c01_pa low "
                         f"{out['c01_pa'][0]:g} = {softest:g} Pa: the softest balls would have "
                         "mu0 = 2 (C10 + C01) <= 0; raise either low end")
    # ... and a sports ball (`balls.checks.BALL_RANGES`), checked here rather than when the
    # study reaches that corner. Only the softest corner can fail: `ALLOWED` caps C10 and C01
    # at 1e9 Pa, so the stiffest balls stay below the range's top
    low_mu = BALL_RANGES["shear modulus"][0]
    if 2 * softest < low_mu:
        flag("ball-units", f"ranges c10_pa low {out['c10_pa'][0]:g} + c01_pa low "
             f"{out['c01_pa'][0]:g} Pa give balls with mu0 = 2 (C10 + C01) down to "
             f"{2 * softest:g} Pa, outside the shear moduli of sports balls (from {low_mu:g} "
             "Pa; values in MPa where Pa are expected?)", check_allow(allow))
    return out


def check_group_ranges(ranges: dict[str, Any]) -> dict[str, tuple[float, float]]:
    """`GROUP_PARAMETERS`' ranges updated by `ranges` (name -> (low, high)), checked against
    `GROUP_ALLOWED`."""
    out = {name: (low, high) for name, (low, high, _) in GROUP_PARAMETERS.items()}
    for name, value in ranges.items():
        if name not in GROUP_PARAMETERS:
            raise InputError(f"range {name!r}: unknown in a study of the groups; allowed "
                             f"{', '.join(GROUP_PARAMETERS)}")
        try:
            low, high = (float(v) for v in value)
        except (TypeError, ValueError):
            raise InputError(f"range {name}: expected LOW:HIGH numbers, got {value!r}") from None
        if not (math.isfinite(low) and math.isfinite(high) and low < high):
            raise InputError(f"range {name} = {low:g}:{high:g}: need finite LOW < HIGH")
        for end, bound in (("LOW", low), ("HIGH", high)):
            check_range(f"range {name} {end}", bound, *GROUP_ALLOWED[name],
                        note=_GROUP_NOTES[name])
        out[name] = (low, high)
    return out


def run_speed(rho_v2_over_mu0: np.ndarray | float) -> np.ndarray:
    """The impact speed (m/s) a run of the groups' design is made at: one at which a
    cricket-sized ball's contact lasts about 1 ms (t_c ~ 2.3 (R / v) (rho v^2 / mu0)^0.4), within
    5-60 m/s. Any speed gives the same dimensionless pulse (`similarity`); this one keeps the
    pulse well sampled at 100 kHz, as the noisy training copies are."""
    return np.clip(0.036 * 2.3 * np.asarray(rho_v2_over_mu0, np.float64) ** 0.4 / 1e-3,
                   5.0, 60.0)


def params_from_groups(points: np.ndarray, radius_m: float, density_kg_m3: float
                       ) -> np.ndarray:
    """Rows (c10_pa, c01_pa, g1, tau1_s, impact_speed_m_s) of a ball of `radius_m` and
    `density_kg_m3` from rows of `GROUP_PARAMETERS`' groups, each at its `run_speed`."""
    from .similarity import constants_of_groups

    points = np.atleast_2d(np.asarray(points, np.float64))
    speed = run_speed(points[:, 0])
    found = constants_of_groups(dict(zip(GROUP_PARAMETERS, points.T)), radius_m,
                                density_kg_m3, speed)
    return np.column_stack([*(found[k] for k in MATERIAL_PARAMETERS), speed])


def is_number(value: Any, finite: bool = True) -> bool:
    """A JSON number (not a bool), finite unless `finite` is False."""
    return (isinstance(value, (int, float)) and not isinstance(value, bool)
            and (not finite or math.isfinite(value)))


def count(low: int, high: int | None = None) -> tuple[Any, str]:
    """(test, what is expected) of `check_fields` for an integer (not a bool) from `low` to
    `high` (no upper limit if None)."""
    return (lambda v: isinstance(v, int) and not isinstance(v, bool) and low <= v
            and (high is None or v <= high),
            f"an integer >= {low}" if high is None else f"an integer {low}-{high}")


def is_pair(value: Any) -> bool:
    """[low, high]: two finite numbers, low <= high."""
    return (isinstance(value, (list, tuple)) and len(value) == 2
            and all(is_number(v) for v in value) and value[0] <= value[1])


def check_fields(data: Any, schema: dict[str, Any], where: str, prefix: str = "") -> None:
    """Check a JSON object against `schema`: key -> (test, what is expected), or a sub-schema (a
    dict) for a nested object. Keys outside the schema are free. `InputError` naming the file
    (`where`), the key's path and what was expected. The one check of the JSON files of studies
    and models."""
    if not isinstance(data, dict):
        raise InputError(f"{where}: {prefix.rstrip('.') or 'the file'} is not a JSON object "
                         f"(got {type(data).__name__})")
    for key, spec in schema.items():
        if key not in data:
            raise InputError(f"{where}: key '{prefix}{key}' missing")
        if isinstance(spec, dict):
            check_fields(data[key], spec, where, f"{prefix}{key}.")
            continue
        test, wanted = spec
        if not test(data[key]):
            shown = json.dumps(data[key])
            shown = shown if len(shown) <= 40 else shown[:37] + "..."
            raise InputError(f"{where}: '{prefix}{key}' = {shown}: expected {wanted}")


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


def unit_sample(runs: int, seed: int, method: str, dimensions: int) -> np.ndarray:
    """`runs` points in the unit cube of `dimensions` axes: a scrambled Sobol sequence or a Latin
    hypercube, seeded (the same arguments always give the same points)."""
    from scipy.stats import qmc

    if method not in METHODS:
        raise InputError(f"method = {method!r}: allowed {', '.join(METHODS)}")
    runs = check_integer("runs", runs, 1)
    if method == "sobol":
        with warnings.catch_warnings():  # balance is best at powers of 2; any count is valid
            warnings.simplefilter("ignore", UserWarning)
            return qmc.Sobol(dimensions, scramble=True, seed=seed).random(runs)
    return qmc.LatinHypercube(dimensions, seed=seed).random(runs)


def sample(runs: int, seed: int, method: str, ranges: dict[str, tuple[float, float]],
           names=tuple(PARAMETERS)) -> np.ndarray:
    """`runs` points (rows: `names`, by default c10_pa, c01_pa, g1, tau1_s, impact_speed_m_s in
    SI) of `unit_sample` mapped onto `ranges` (`from_unit`)."""
    return from_unit(unit_sample(runs, seed, method, len(names)), ranges, names)


def universal_ball_spec(params: dict[str, float], template: dict[str, Any],
                        name: str) -> dict[str, Any]:
    """The ball specification (`simulate --ball`'s JSON form) of the universal ball with
    `params` (c10_pa, c01_pa, g1, tau1_s) on a study's template (`template_geometry`)."""
    from ..balls.ball import universal_spec

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
