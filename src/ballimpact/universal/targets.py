"""Universal-ball constants from stated targets: the ball of a given size whose impact on a rigid
plane at a speed has a given COR and dynamic stiffness.

Sports balls are specified by what a lab measures at a standard speed, not by their moduli: a
COR against a rigid wall at 26.8 m/s (60 mph, as ASTM F1887) and a dynamic stiffness
DS = F_peak^2 / (m v^2) (N/m, the quantity of ASTM F2845, here against a flat rigid wall).
`constants_for` turns those two numbers into a homogeneous universal ball (Mooney-Rivlin, D1 = 0,
one Prony term) of the ball's size and mass:

1. The targets are mapped onto the model's reference ball at the same speed
   (`similarity`: COR unchanged, DS by (m0 / R0^2) / (m / R^2), since forces scale with m v^2 / R).
2. Two targets fix two constants. The other two are fixed choices:
   - C01 = 0 (`C01_OVER_C10`): the middle of the model's C01 range; COR and DS carry no
     information on the shape of the strain energy, and with C01 = 0 every C10 of the model's
     range is reachable (mu0 = 2 C10 spans 8-14 MPa on the built-in model's reference ball).
   - tau1 at the geometric middle of the model's tau1 range on the reference ball (tau1 is
     learned on a log axis), mapped to the ball by R / R0: the group tau1 v / R then sits in the
     middle of what the model was trained on, as far from its edges as it can be.
   The remaining (mu0, g1) are solved for on the forward surrogate within the model's ranges
   (least squares, started from the best point of a grid over the ranges). A target the
   surrogate cannot reach is an `InputError` naming it and the reachable range.
3. The constants are mapped back to the ball (`similarity.map_params`), and ONE FE run of the
   found ball at the speed (the study's mesh scaled to the ball, `identify.scaled_options`)
   reports its COR and DS against the targets. If the surrogate missed by more than
   `COR_TOLERANCE` in COR or `DS_TOLERANCE` in DS, up to `max_corrections` further FE runs
   correct it: each moves the surrogate's aim by the FE's miss (a Newton step on the FE with the
   surrogate's Jacobian) and solves again.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..checks import check_integer, check_range
from ..errors import InputError
from ..records.features import dynamic_stiffness
from ..standards import SIXTY_MPH_M_S
from .similarity import BallSize, groups, map_params

#: the standard speed of ball COR tests, 60 mph (ASTM F1887; `standards.SIXTY_MPH_M_S`)
STANDARD_SPEED_M_S = SIXTY_MPH_M_S
#: C01 / C10 of the balls found (see the module docstring: why 0)
C01_OVER_C10 = 0.0
#: an FE check within these of the targets needs no correction (COR absolute, DS relative)
COR_TOLERANCE = 0.01
DS_TOLERANCE = 0.03
#: the surrogate's own solution must meet the targets to these (else: out of reach)
_SOLVE_COR = 0.002
_SOLVE_DS = 0.005
#: grid over (mu0, g1) for the start point and the reachable ranges
_GRID = 41


def map_dynamic_stiffness(ds_n_m: float, source: BallSize, target: BallSize) -> float:
    """A dynamic stiffness F_peak^2 / (m v^2) (N/m) of a `source` ball's impact mapped to the
    similar impact of a `target` ball at the same speed: forces scale with m v^2 / R, so DS
    scales with m / R^2."""
    return ds_n_m * (target.mass_kg / target.radius_m ** 2) \
        / (source.mass_kg / source.radius_m ** 2)


def fixed_choices(model) -> dict[str, float]:
    """The constants not solved for, on the model's reference ball: C01 / C10 and tau1 (s, the
    geometric middle of the model's tau1 range)."""
    low, high = model.ranges["tau1_s"]
    return {"c01_over_c10": C01_OVER_C10, "tau1_s": math.sqrt(low * high)}


def _mu0_range(model) -> tuple[float, float]:
    """mu0 = 2 (C10 + C01) = 2 C10 (1 + C01/C10) over the C10 range, with C01 inside its range."""
    (c10_lo, c10_hi), (c01_lo, c01_hi) = model.ranges["c10_pa"], model.ranges["c01_pa"]
    r = C01_OVER_C10
    lo = max(c10_lo, c01_lo / r if r > 0 else c10_lo, c01_hi / r if r < 0 else c10_lo)
    hi = min(c10_hi, c01_hi / r if r > 0 else c10_hi, c01_lo / r if r < 0 else c10_hi)
    return 2 * lo * (1 + r), 2 * hi * (1 + r)


def _reference_params(model, mu0_pa: float, g1: float) -> dict[str, float]:
    c10 = mu0_pa / (2 * (1 + C01_OVER_C10))
    c10 = float(c10)
    return {"c10_pa": c10, "c01_pa": C01_OVER_C10 * c10, "g1": float(g1),
            "tau1_s": fixed_choices(model)["tau1_s"]}


def _surrogate(model, mu0, g1, speed_m_s: float, reference: BallSize):
    """COR and DS (N/m) of the reference ball from the forward surrogate, arrays of (mu0, g1)."""
    from .model import FEATURES

    mu0, g1 = np.broadcast_arrays(np.atleast_1d(mu0), np.atleast_1d(g1))
    tau1 = fixed_choices(model)["tau1_s"]
    c10 = mu0 / (2 * (1 + C01_OVER_C10))
    rows = np.column_stack([c10, C01_OVER_C10 * c10, g1, np.full(len(c10), tau1),
                            np.full(len(c10), speed_m_s)])
    out = model.simulate(rows)["features"]
    peak = out[:, FEATURES.index("P6")]
    return out[:, FEATURES.index("P17")], dynamic_stiffness(peak, reference.mass_kg, speed_m_s)


def solve_on_surrogate(model, size: BallSize, cor: float, ds_n_m: float,
                       speed_m_s: float = STANDARD_SPEED_M_S) -> dict[str, Any]:
    """(mu0, g1) on the model's reference ball whose surrogate impact at `speed_m_s` has `cor`
    and the reference-ball equivalent of `ds_n_m` (N/m, of the ball of `size`). Returns the
    reference ball's constants and the surrogate's COR and DS (mapped to the ball); an
    `InputError` names a target out of the surrogate's reach and the reachable range."""
    from scipy.optimize import least_squares

    from .identify import reference_size

    reference = reference_size(model)
    ds_ref = map_dynamic_stiffness(ds_n_m, size, reference)
    (mu_lo, mu_hi), (g_lo, g_hi) = _mu0_range(model), model.ranges["g1"]
    mu_grid, g_grid = np.meshgrid(np.linspace(mu_lo, mu_hi, _GRID), np.linspace(g_lo, g_hi, _GRID))
    cor_grid, ds_grid = _surrogate(model, mu_grid.ravel(), g_grid.ravel(), speed_m_s, reference)

    def residual(u):  # COR in units of its tolerance, DS on a log axis in units of its own
        c, d = _surrogate(model, mu_lo + u[0] * (mu_hi - mu_lo), g_lo + u[1] * (g_hi - g_lo),
                          speed_m_s, reference)
        return np.array([(c[0] - cor) / COR_TOLERANCE, math.log(d[0] / ds_ref) / DS_TOLERANCE])

    misses = (((cor_grid - cor) / COR_TOLERANCE) ** 2
              + (np.log(ds_grid / ds_ref) / DS_TOLERANCE) ** 2)
    best = int(np.argmin(misses))
    u0 = np.array([(mu_grid.ravel()[best] - mu_lo) / (mu_hi - mu_lo),
                   (g_grid.ravel()[best] - g_lo) / (g_hi - g_lo)])
    solution = least_squares(residual, np.clip(u0, 1e-6, 1 - 1e-6), bounds=(0.0, 1.0),
                             diff_step=1e-4, xtol=1e-10, ftol=1e-10, max_nfev=100)
    mu0 = mu_lo + solution.x[0] * (mu_hi - mu_lo)
    g1 = g_lo + solution.x[1] * (g_hi - g_lo)
    c, d = (float(a[0]) for a in _surrogate(model, mu0, g1, speed_m_s, reference))
    if abs(c - cor) > _SOLVE_COR or abs(d / ds_ref - 1) > _SOLVE_DS:
        scale = map_dynamic_stiffness(1.0, reference, size)
        ds_range = f"{ds_grid.min() * scale:.4g}..{ds_grid.max() * scale:.4g} N/m"
        if not ds_grid.min() <= ds_ref <= ds_grid.max():
            name, words = "ds_n_m", f"{ds_n_m:.4g} N/m; reachable {ds_range}"
        else:
            near = np.abs(np.log(ds_grid / ds_ref)) <= DS_TOLERANCE
            at = cor_grid[near] if near.any() else cor_grid
            name, words = "cor", (f"{cor:g} with dynamic stiffness {ds_n_m:.4g} N/m; reachable "
                                  f"at that stiffness COR {at.min():.3f}..{at.max():.3f} "
                                  f"(at any: {cor_grid.min():.3f}..{cor_grid.max():.3f}, DS "
                                  f"{ds_range})")
        raise InputError(f"target {name} = {words}: out of the universal model's reach for a "
                         f"ball of diameter {2 * size.radius_m:g} m and mass {size.mass_kg:g} kg "
                         f"at {speed_m_s:g} m/s (C01 = 0, tau1 v / R fixed at its range's "
                         "middle)")
    params = _reference_params(model, mu0, g1)
    return {"reference_params": params, "cor": c, "ds_n_m": d * map_dynamic_stiffness(
        1.0, reference, size)}


def fe_check(model, size: BallSize, params: dict[str, float], speed_m_s: float, options=None,
             name: str = "universal") -> dict[str, Any]:
    """One FE run of the universal ball of `size` with `params` (SI, on that ball) at
    `speed_m_s`: its COR (P17) and DS = F_peak^2 / (m v^2) (N/m) from the run's features, as a
    lab would compute them from the record."""
    from ..fe import load_ball, simulate
    from ..balls.ball import universal_spec
    from ..records.features import extract_features
    from .identify import scaled_options

    spec = universal_spec(params, size.radius_m, size.density_kg_m3,
                          model.metadata["template"]["moduli"], name)
    result = simulate(load_ball(spec), speed_m_s, options or scaled_options(model, size))
    features = extract_features(result.record())
    return {"cor": float(features.values["P17"]),
            "ds_n_m": float(features.dynamic_stiffness_n_m),
            "peak_force_n": float(features.values["P6"]),
            "contact_time_s": float(features.values["P1"]),
            "wall_time_s": float(result.wall_time_s)}


def constants_for(model, size: BallSize, cor: float, ds_n_m: float,
                  speed_m_s: float = STANDARD_SPEED_M_S, *, verify: bool = True,
                  max_corrections: int = 2, options=None) -> dict[str, Any]:
    """The universal-ball constants (c10_pa, c01_pa, g1, tau1_s; SI) of a ball of `size`
    whose impact on a rigid plane at `speed_m_s` (m/s) has the COR `cor` and the dynamic
    stiffness `ds_n_m` = F_peak^2 / (m v^2) (N/m). See the module docstring for the method.

    Returns a JSON-able dict: `params` (with mu0_pa), `ball` (a ball file's specification),
    `targets`, `choices` (the fixed C01 / C10 and tau1), `groups` (`similarity.GROUPS`),
    `surrogate` (its COR and DS of the found ball), and with `verify` `fe_check` (the FE runs:
    COR, DS, their misses; the last run is the reported one) and `corrections` (FE-driven
    corrections made). `options`: FE settings (default: the study's mesh scaled to the ball)."""
    from ..balls.ball import universal_spec
    from .identify import check_speed, reference_size

    if not isinstance(size, BallSize):
        raise InputError(f"size: expected a BallSize(radius_m, mass_kg), got {type(size).__name__}")
    cor = check_range("cor", cor, 0.0, 1.0, low_open=True, high_open=True)
    ds_n_m = check_range("ds_n_m", ds_n_m, 0.0, low_open=True, unit="N/m")
    speed_m_s = check_range("speed_m_s", speed_m_s, 0.0, low_open=True, unit="m/s")
    max_corrections = check_integer("max_corrections", max_corrections, 0)
    check_speed(model, speed_m_s)
    reference = reference_size(model)
    aim_cor, aim_ds = cor, ds_n_m
    solved = solve_on_surrogate(model, size, aim_cor, aim_ds, speed_m_s)
    runs: list[dict[str, Any]] = []
    note = ""
    while verify:
        params = map_params(solved["reference_params"], reference, size)
        run = fe_check(model, size, params, speed_m_s, options)
        run.update(cor_error=run["cor"] - cor, ds_relative_error=run["ds_n_m"] / ds_n_m - 1,
                   surrogate_cor=solved["cor"], surrogate_ds_n_m=solved["ds_n_m"], params=params)
        runs.append(run)
        if abs(run["cor_error"]) <= COR_TOLERANCE and abs(run["ds_relative_error"]) <= DS_TOLERANCE:
            break
        if len(runs) > max_corrections:
            note = (f"FE misses the targets after {max_corrections} correction(s): COR "
                    f"{run['cor']:.4f} against {cor:g}, DS {run['ds_n_m']:.4g} against "
                    f"{ds_n_m:.4g} N/m")
            break
        # a Newton step on the FE with the surrogate's Jacobian: move the aim by the FE's miss
        aim_cor -= run["cor_error"]
        aim_ds /= 1 + run["ds_relative_error"]
        try:
            solved = solve_on_surrogate(model, size, aim_cor, aim_ds, speed_m_s)
        except InputError as exc:
            note = f"correction stopped: the corrected aim is out of reach ({exc})"
            break
    best = min(runs, key=lambda r: (abs(r["cor_error"]) / COR_TOLERANCE) ** 2
               + (r["ds_relative_error"] / DS_TOLERANCE) ** 2) if runs else None
    params = best["params"] if best else map_params(solved["reference_params"], reference, size)
    params = {**params, "mu0_pa": 2.0 * (params["c10_pa"] + params["c01_pa"])}
    choices = fixed_choices(model)
    out: dict[str, Any] = {
        "params": params,
        "ball": universal_spec(params, size.radius_m, size.density_kg_m3,
                               model.metadata["template"]["moduli"], "universal"),
        "ball_size": {"diameter_m": 2 * size.radius_m, "mass_kg": size.mass_kg,
                      "density_kg_m3": size.density_kg_m3},
        "targets": {"cor": cor, "dynamic_stiffness_n_m": ds_n_m, "impact_speed_m_s": speed_m_s},
        "choices": {"c01_over_c10": choices["c01_over_c10"],
                    "tau1_s": choices["tau1_s"] * size.radius_m / reference.radius_m,
                    "tau1_reference_s": choices["tau1_s"]},
        "groups": groups(params, size, speed_m_s),
        "surrogate": {"cor": best["surrogate_cor"] if best else solved["cor"],
                      "dynamic_stiffness_n_m": best["surrogate_ds_n_m"] if best
                      else solved["ds_n_m"]},
    }
    if verify:
        out["fe_check"] = {
            "cor": best["cor"], "dynamic_stiffness_n_m": best["ds_n_m"],
            "peak_force_n": best["peak_force_n"], "contact_time_s": best["contact_time_s"],
            "cor_error": best["cor_error"], "ds_relative_error": best["ds_relative_error"],
            "cor_tolerance": COR_TOLERANCE, "ds_tolerance": DS_TOLERANCE,
            "passed": bool(abs(best["cor_error"]) <= COR_TOLERANCE
                           and abs(best["ds_relative_error"]) <= DS_TOLERANCE),
            "runs": [{k: v for k, v in r.items() if k != "params"} for r in runs]}
        out["corrections"] = len(runs) - 1
        if note:
            out["fe_check"]["note"] = note
    return out


__all__ = ["C01_OVER_C10", "COR_TOLERANCE", "DS_TOLERANCE", "STANDARD_SPEED_M_S",
           "constants_for", "fe_check", "fixed_choices", "map_dynamic_stiffness",
           "solve_on_surrogate"]
