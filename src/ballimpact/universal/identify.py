"""Identify a universal ball from one measured impact: features -> parameters with intervals
(inverse ensemble) -> optional refinement on the forward surrogate -> an FE run to verify.

What is reported is what is written: `mu0_pa` is the initial shear modulus of the written ball's
constants (2 (C10 + C01), in the template's moduli convention), and an estimate or an interval
that the model's training range cut short says so (a warning naming the parameter, and the
`at_training_bound` and `clipped_to_training_range` lists)."""

from __future__ import annotations

import time
import warnings
from collections.abc import Collection
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..checks import check_fraction, warn_outside_range
from ..errors import InputError, InputWarning
from ..records.features import FEATURE_NAMES
from ..checks import check_allow, flag
from . import space
from ..comparison import compare, features_pulse, pulse_nrmse
from ..verdict import Tolerances, judge
from .compression_check import (COMPRESSION_TOLERANCE, check_compression_tolerance,
                                judge_compression, load_compression_test)
from .similarity import BallSize, groups, map_features, map_params, map_ranges
from .design import param_ranges_from_groups, params_from_groups
from .model import FEATURES, TARGET_UNITS, TARGETS, UniversalModel, target_ranges

REFINE = ("none", "surrogate")
#: an estimate or an interval end within this fraction of the range (on the parameter's own axis,
#: log for tau1) of a training bound sits on it (the ensemble's outputs are clipped to the range)
ON_BOUND = 1e-6
#: the dimensionless groups (`similarity.GROUPS`) each parameter enters: named when it sits on a
#: training bound
GROUPS_OF = {"c10_pa": ("rho_v2_over_mu0", "c01_over_c10"),
             "c01_pa": ("rho_v2_over_mu0", "c01_over_c10"), "mu0_pa": ("rho_v2_over_mu0",),
             "g1": ("g1",), "tau1_s": ("tau1_v_over_r",)}


@dataclass
class Identification:
    params: dict[str, float]                  # c10_pa, c01_pa, g1, tau1_s and mu0_pa (SI)
    interval_90: dict[str, list[float]]
    ball: dict[str, Any]                      # ball specification for `simulate --ball`
    impact_speed_m_s: float
    refine: str
    verification: dict[str, Any] | None = None
    simulated: Any = field(default=None, repr=False)   # fe.ImpactResult of the verification
    wall_time_s: float = 0.0
    training_range: dict[str, list[float]] = field(default_factory=dict)
    at_training_bound: list[str] = field(default_factory=list)          # estimates on a bound
    clipped_to_training_range: list[str] = field(default_factory=list)  # intervals cut by one
    ball_size: dict[str, Any] = field(default_factory=dict)  # diameter_m, mass_kg, their source
    groups: dict[str, float] = field(default_factory=dict)   # `similarity.GROUPS` of the estimate
    group_range: dict[str, list[float]] = field(default_factory=dict)  # the model's, this speed
    groups_interval_90: dict[str, list[float]] = field(default_factory=dict)  # a groups model's

    def to_dict(self) -> dict[str, Any]:
        return {"params": self.params, "params_interval_90": self.interval_90,
                "ball_size": self.ball_size, "groups": self.groups,
                "groups_interval_90": self.groups_interval_90, "group_range": self.group_range,
                "training_range": self.training_range,
                "at_training_bound": self.at_training_bound,
                "clipped_to_training_range": self.clipped_to_training_range,
                "ball": self.ball, "impact_speed_m_s": self.impact_speed_m_s,
                "refine": self.refine, "verification": self.verification,
                "wall_time_s": self.wall_time_s}


def check_speed(model: UniversalModel, speed_m_s: float, allow: Collection[str] = (),
                where: str = "") -> None:
    """The `speed-range` check against the model's training speeds: outside them the inverse
    ensemble extrapolates in its most influential input, so this is an error unless allowed.
    A model of the groups has no speed axis (its ranges are the groups'; the FE check has its
    own speed check)."""
    if "impact_speed_m_s" not in model.ranges:
        return
    low, high = model.ranges["impact_speed_m_s"]
    if not low <= speed_m_s <= high:
        flag("speed-range", f"{where}impact speed {speed_m_s:g} m/s is outside the universal "
             f"model's training speeds {low:g}..{high:g} m/s: its identification would "
             "extrapolate; use a model trained over this speed (universal run --range "
             "impact_speed_m_s=LOW:HIGH)", check_allow(allow))


def warn_outside_training_range(model: UniversalModel, values: dict[str, float], where: str = "",
                                measured: dict[str, float] | None = None) -> None:
    """Warn (`checks.warn_outside_range`) for each feature outside the range the model was
    trained on (the speed, P15, has its own check: `check_speed`). `values` are on the model's
    ball; `measured`, when given, are the test's own before the mapping onto it
    (`similarity.map_features`), and the warning names both."""
    ranges = model.metadata["feature_range"]
    diameter = 2 * model.metadata["template"]["radius_m"]
    groups_model = model.design.name == "groups"
    for key in model.design.features:
        if key == "P15":
            continue
        low, high = ranges[key]
        mapped = " (made dimensionless by the test's ball and speed)" if groups_model else \
            "" if measured is None else (
            f" (the test's {measured[key]:.5g}, mapped onto the model's {diameter:g} m ball)")
        warn_outside_range(f"{where}{key} ({FEATURE_NAMES[key]})", values[key],
                           "model's training range", low, high,
                           consequence=f"the identification extrapolates{mapped}", stacklevel=2)


def estimate(model: UniversalModel, values: dict[str, float], refine: str = "none"):
    """Parameters (SI dict incl. mu0_pa) and 90% intervals from feature values (P1..P19).

    `mu0_pa` is 2 (C10 + C01) of the returned C10 and C01 (the ball's own shear modulus), not
    the ensemble's separate mu0 output; its interval is that output's calibrated interval,
    widened where needed to hold it (`_holding`). Every interval holds its estimate."""
    if refine not in REFINE:
        raise InputError(f"refine = {refine!r}: allowed {', '.join(REFINE)}")
    if model.design.name == "groups":
        raise InputError("estimate: a model of the groups' design is used through "
                         "`estimate_groups`")
    x = np.array([[values[k] for k in FEATURES]])
    est = model.estimate(x)
    params = dict(zip(TARGETS, est["values"][0].tolist()))
    interval = {k: [float(lo), float(hi)]
                for k, lo, hi in zip(TARGETS, est["low"][0], est["high"][0])}
    if refine == "surrogate":
        params = refine_on_surrogate(model, values, params)
    params["mu0_pa"] = 2.0 * (params["c10_pa"] + params["c01_pa"])
    # the ensemble's mu0 and that of its C10 + C01 differ (held out: median 0.18%, at most 2.9%;
    # more outside the training range): the interval covers both rather than hide the difference
    shift = {k: 0.0 for k in TARGETS}
    shift["mu0_pa"] = params["mu0_pa"] - float(est["values"][0][-1])
    ranges = target_ranges(model.ranges)
    interval = {k: _holding(interval[k], params[k], shift[k], ranges[k]) for k in TARGETS}
    return params, interval


#: the COR difference that counts as much as one standard deviation of every feature together
#: when the forward surrogate chooses among the inverse ensemble's proposals (`choose_groups`):
#: a test's COR comes from two speeds and is known far better than its pulse's shape
COR_SCALE = 0.02
#: proposals drawn from each ensemble member's Gaussian (seeded: an estimate is repeatable)
PROPOSALS = 256


def choose_groups(model: UniversalModel, x: np.ndarray) -> np.ndarray:
    """A model of the groups: the groups (unit targets scaled back to SI) that the forward
    surrogate finds closest to the test, among the inverse ensemble's proposals (its mixture
    mean, each member's mean, and those of `PROPOSALS` draws from each member's Gaussian that
    lie inside the model's box). Closest: the
    mean squared difference of the standardised features plus ((COR difference) / `COR_SCALE`)^2.

    Why: over the groups' box one pulse can come from two relaxation regimes (tau1 shorter or
    longer than the contact, with g1 to match), and the ensemble's mean of the two lands between
    them, on a ball that dissipates more than either (closed loop of the material families,
    docs/universal.md: |COR error| at the 90th percentile 0.05-0.11 from the mean, 0.003-0.018
    chosen)."""
    from .networks import member_outputs

    design = model.design
    z = model.feature_scaler.forward(x).astype(np.float32)
    means, log_sigmas = (np.asarray(a, np.float64)[:, 0, :]
                         for a in member_outputs(model.inverse, z))
    rng = np.random.default_rng(0)
    draws = model.target_scaler.inverse(np.concatenate(
        [mu + np.exp(ls) * rng.standard_normal((PROPOSALS, mu.size))
         for mu, ls in zip(means, log_sigmas)]))
    # draws outside the model's box are dropped, not clipped onto its bounds (where a loose
    # parameter's draws would pile up); the means are clipped as `UniversalModel.estimate` does
    inside = draws[np.all((draws > 0.0) & (draws < 1.0), axis=1)]
    unit = np.concatenate([np.clip(model.target_scaler.inverse(
        np.concatenate([means.mean(axis=0)[None], means])), 0.0, 1.0), inside])
    candidates = space.from_unit(unit, design.target_ranges(model.ranges), design.targets)
    predicted = model.simulate(candidates)["features"]
    cor = design.features.index("P17")
    distance = np.mean((model.feature_scaler.forward(predicted)
                        - model.feature_scaler.forward(x)) ** 2, axis=1)
    distance += ((predicted[:, cor] - x[0, cor]) / COR_SCALE) ** 2
    return candidates[int(np.argmin(distance))]


def estimate_groups(model: UniversalModel, values: dict[str, float], size: BallSize,
                    refine: str = "none") -> dict[str, Any]:
    """A model of the groups' design: the groups of a test of a ball of `size` from its features
    (P1..P19, SI) made dimensionless by that ball and the test's speed (`choose_groups`), their
    90% intervals (the ensemble's, widened where needed to hold the estimate), the ball's
    constants (`design.params_from_groups`) and their intervals (the corners of the groups'
    intervals: each constant is monotonic in each group, so every interval holds its estimate),
    and where the groups sit against the model's ranges."""
    if refine not in REFINE:
        raise InputError(f"refine = {refine!r}: allowed {', '.join(REFINE)}")
    if refine != "none":
        raise InputError("--refine surrogate: not available for a model of the groups' design "
                         "(its forward surrogate already chooses its estimate; use --refine "
                         "none)")
    design = model.design
    speed = float(values["P15"])
    x = design.inputs(np.array([[values[k] for k in FEATURES]]), size)
    est = model.estimate(x)
    names = design.targets
    found = dict(zip(names, choose_groups(model, x).tolist()))
    ranges = {k: list(v) for k, v in model.ranges.items()}
    box = {k: _holding([float(lo), float(hi)], found[k], 0.0, ranges[k])
           for k, lo, hi in zip(names, est["low"][0], est["high"][0])}
    _, on, clipped = training_bounds(model, found, box)
    return {"groups": found, "groups_interval_90": box,
            "params": params_from_groups(found, size, speed),
            "interval_90": param_ranges_from_groups(box, size, speed),
            "training_range": param_ranges_from_groups(ranges, size, speed),
            "group_range": ranges, "at_bound": on, "clipped": clipped}


def _holding(interval: list[float], value: float, shift: float,
             bounds: tuple[float, float]) -> list[float]:
    """The smallest interval holding `interval`, that interval moved by `shift` and `value`,
    within the training range `bounds` (as the ensemble's own intervals are)."""
    low = min(interval[0], interval[0] + shift, value)
    high = max(interval[1], interval[1] + shift, value)
    return [float(max(low, bounds[0])), float(min(high, bounds[1]))]


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


def training_bounds(model: UniversalModel, params: dict[str, float],
                    interval: dict[str, list[float]]) -> tuple[dict, list[str], list[str]]:
    """The training range of each of the model's targets (`design.targets`: the constants, or the
    groups), the targets whose estimate sits on a bound, and those whose 90% interval reaches
    one (clipped: the data may allow values beyond it)."""
    names = model.design.targets
    ranges = model.design.target_ranges(model.ranges)

    def unit(values):  # position in the range on the target's own axis (tau1: log)
        return space.to_unit(np.array([[values[k] for k in names]]), ranges, names)[0]

    u = unit(params)
    lows = unit({k: interval[k][0] for k in names})
    highs = unit({k: interval[k][1] for k in names})
    on = [k for k, x in zip(names, u) if x <= ON_BOUND or x >= 1 - ON_BOUND]
    clipped = [k for k, lo, hi in zip(names, lows, highs)
               if lo <= ON_BOUND or hi >= 1 - ON_BOUND]
    return {k: [float(v) for v in ranges[k]] for k in names}, on, clipped


def _bounded(found: Identification, name: str) -> tuple[float, list[float], list[float]]:
    """(estimate, 90% interval, training range) of `name`: a constant, or a group of a model of
    the groups (whose ranges are the groups')."""
    if name in found.params:
        return found.params[name], found.interval_90[name], found.training_range[name]
    return found.groups[name], found.groups_interval_90[name], found.group_range[name]


def _bound_words(name: str, value: float, bounds: list[float]) -> str:
    low, high = bounds
    side, bound = ("lower", low) if abs(value - low) <= abs(value - high) else ("upper", high)
    unit = "" if TARGET_UNITS[name] == "1" else f" {TARGET_UNITS[name]}"
    return f"{name} at its {side} bound {bound:g}{unit}"


def warn_bounds(found: Identification, where: str = "") -> None:
    """One warning for estimates on a training bound, one for intervals clipped by one."""
    if found.at_training_bound:
        words = ", ".join(_bound_words(k, value, bounds) for k in found.at_training_bound
                          for value, _, bounds in [_bounded(found, k)])
        constants = [k for k in found.at_training_bound if k in GROUPS_OF]
        if constants:  # the cricket model's constants: say which groups they enter
            bounded = dict.fromkeys(g for k in constants for g in GROUPS_OF[k])
            words += "; in dimensionless terms " + ", ".join(
                f"{g} = {found.groups[g]:.4g} at an end of the model's {lo:.4g}..{hi:.4g} at "
                "this speed" for g in bounded for lo, hi in [found.group_range[g]])
            words += ("; --model sports-ball-universal-model covers every solid sports ball at "
                      "5-60 m/s (docs/universal.md)")
        warnings.warn(f"{where}estimate on the edge of the universal model's training range: "
                      f"{words}; the test lies outside what the model was trained on, the "
                      "identified ball is the nearest one inside the range, not an estimate of "
                      "this ball (see the FE check)", InputWarning, stacklevel=3)
    clipped = [k for k in found.clipped_to_training_range if k not in found.at_training_bound]
    if clipped:
        words = ", ".join(_bound_words(k, _clipped_end(found, k), _bounded(found, k)[2])
                          for k in clipped)
        warnings.warn(f"{where}90% interval clipped to the universal model's training range: "
                      f"{words}; values beyond that bound are excluded by the model's range, "
                      "not by the test", InputWarning, stacklevel=3)


def _clipped_end(found: Identification, name: str) -> float:
    """The end of `name`'s interval that sits on a bound (the lower one if both do)."""
    _, (lo, hi), (low, high) = _bounded(found, name)
    return lo if abs(lo - low) <= abs(hi - high) else hi


def reference_size(model: UniversalModel) -> BallSize:
    """The ball of the model's study (its template): every test is mapped onto it."""
    template = model.metadata["template"]
    return BallSize(template["radius_m"], template["mass_kg"])


def group_ranges(model: UniversalModel, speed_m_s: float) -> dict[str, list[float]]:
    """The range of each dimensionless group (`similarity.GROUPS`) that the model's study covers
    at `speed_m_s` (m/s): its ranges of C10, C01, g1 and tau1 on the reference ball at that
    speed (the same for every ball size: the groups are what a test maps by)."""
    r = model.ranges
    (c10_lo, c10_hi), (c01_lo, c01_hi) = r["c10_pa"], r["c01_pa"]
    ref = reference_size(model)
    mu_lo, mu_hi = 2 * (c10_lo + c01_lo), 2 * (c10_hi + c01_hi)
    inertia = ref.density_kg_m3 * speed_m_s ** 2
    ratios = [a / b for a in (c01_lo, c01_hi) for b in (c10_lo, c10_hi)]
    return {"rho_v2_over_mu0": [inertia / mu_hi, inertia / mu_lo],
            "c01_over_c10": [min(ratios), max(ratios)], "g1": list(r["g1"]),
            "tau1_v_over_r": [t * speed_m_s / ref.radius_m for t in r["tau1_s"]]}


def identify(processed, model: UniversalModel, *, verify: bool = True,
             refine: str = "none", options=None, allow: Collection[str] = (),
             max_nrmse: float | None = None, size: BallSize | None = None,
             tolerances: Tolerances | None = None, compression=None,
             compression_tolerance: float = COMPRESSION_TOLERANCE) -> Identification:
    """Identify the universal ball from a processed test (`pipeline.process`).

    `size`: the tested ball's radius and mass (`similarity.BallSize`; default the model's ball's
    radius with the test's mass). The test is mapped onto the model's reference ball at the same
    speed (`similarity.map_features`: exact for homogeneous balls), identified there, and the
    constants mapped back (`similarity.map_params`), so the ball written is of the tested size
    and mass; its FE check runs on the study's mesh scaled to the ball (`options`, default
    `scaled_options`).

    The impact speed must lie within the model's training speeds (`check_speed`; `allow`
    holding "speed-range" makes that a warning, and lets the FE check run outside the FE range
    too). Estimates on a training bound and intervals clipped by one give warnings. The FE check
    (`verify`) judges force NRMSE, COR, contact time and peak force together
    (`verdict.judge` with `tolerances`, default `verdict.Tolerances()`; `max_nrmse` sets the
    force NRMSE's alone): `verification["passed"]` only when all pass, `verification["missed"]`
    names each miss, and a miss is an `InputWarning` (the command line exits 3). A
    `compression` test (`calibrate.compression.CompressionTest`, or its CSV's path) adds the
    criterion "compression": the identified ball squeezed as in the test, its force NRMSE
    within `compression_tolerance` (`compression_check.judge_compression`); it needs `verify`."""
    from ..fe import load_ball
    from ..balls.ball import universal_spec

    started = time.perf_counter()
    allow = check_allow(allow)
    tolerances = tolerances or Tolerances()
    compression_tolerance = check_compression_tolerance(compression_tolerance)
    if compression is not None and not verify:
        raise InputError("compression (--compression): a criterion of the FE check, which "
                         "verify=False (--no-verify) turns off")
    if max_nrmse is not None:
        tolerances = replace(tolerances, force_nrmse=check_max_nrmse(max_nrmse))
    values = model_inputs(processed, model, allow)
    source = processed.raw.metadata.get("file") if hasattr(processed, "raw") else None
    where = f"{source}: " if source else ""
    speed = float(values["P15"])
    check_speed(model, speed, allow, where)
    warn_failed_model(model)
    reference = reference_size(model)
    mass = processed.features.mass_kg
    if size is None:
        size = BallSize(reference.radius_m, mass or reference.mass_kg)
        given = "the model's ball (no diameter given)"
        if abs(size.mass_kg / reference.mass_kg - 1) > 0.02:
            warnings.warn(f"{where}no ball diameter given: the model's ball's "
                          f"{2 * reference.radius_m:g} m is assumed for this {size.mass_kg:g} kg "
                          "ball (--ball-diameter-m, or size= in Python, to give it)",
                          InputWarning, stacklevel=2)
    else:
        given = "given"
        if mass and abs(size.mass_kg / mass - 1) > 0.01:
            warnings.warn(f"{where}size: mass {size.mass_kg:g} kg differs from the test's "
                          f"{mass:g} kg by more than 1%: the test is mapped as a ball of "
                          f"{size.mass_kg:g} kg", InputWarning, stacklevel=2)
    template = model.metadata["template"]
    if model.design.name == "groups":
        dimensionless = dict(zip(model.design.features, model.design.inputs(
            np.array([[values[k] for k in FEATURES]]), size)[0]))
        warn_outside_training_range(model, dimensionless, where)
        found = estimate_groups(model, values, size, refine)
    else:
        mapped = map_features(values, size, reference)
        warn_outside_training_range(model, mapped, where,
                                    None if size == reference else values)
        found = _estimate_by_similarity(model, mapped, reference, size, speed, refine)
    spec = universal_spec(found["params"], size.radius_m, size.density_kg_m3,
                          template["moduli"], "identified-universal")
    ball = load_ball(spec, allow=allow)  # checked as `simulate --ball` will check it
    if compression is not None:  # a path, or a test deeper than the ball: before any FE run
        if isinstance(compression, (str, Path)):
            compression = load_compression_test(compression)
        compression.check_against(ball)
    result = Identification(found["params"], found["interval_90"], spec, speed, refine,
                            training_range=found["training_range"],
                            at_training_bound=found["at_bound"],
                            clipped_to_training_range=found["clipped"],
                            group_range=found["group_range"],
                            groups_interval_90=found.get("groups_interval_90", {}))
    result.ball_size = {"diameter_m": 2 * size.radius_m, "mass_kg": size.mass_kg,
                        "density_kg_m3": size.density_kg_m3, "diameter_source": given}
    result.groups = groups(found["params"], size, speed)
    warn_bounds(result, where)
    if verify:
        options = options or scaled_options(model, size)
        result.simulated, result.verification = verify_run(spec, processed.features, options,
                                                           allow)
        check = result.verification
        check.update(judge(check, tolerances, processed.features.uncertainty))
        check["force_nrmse_limit"] = tolerances.force_nrmse
        if compression is not None:
            judge_compression(check, spec, compression, compression_tolerance, allow)
        if not check["passed"]:
            warnings.warn(f"{where}FE check failed: {'; '.join(check['missed'])}: the identified "
                          "ball does not reproduce this test (see --plot)", InputWarning,
                          stacklevel=2)
    result.wall_time_s = time.perf_counter() - started
    return result


def _estimate_by_similarity(model: UniversalModel, mapped: dict[str, float],
                            reference: BallSize, size: BallSize, speed: float, refine: str
                            ) -> dict[str, Any]:
    """A material model (the cricket one): the constants of the reference ball from the test's
    features mapped onto it (`mapped`), mapped back to a ball of `size`, with their intervals,
    training ranges and bounds, as `estimate_groups` gives them for a model of the groups."""
    # the reported mu0 must be the written ball's: `estimate` gives 2 (C10 + C01) of the C10
    # and C01 that `universal_ball_spec` writes unchanged, which is what the ball's Mooney-Rivlin
    # material reads back as its initial shear modulus (`given_moduli_pa`); the mapping scales
    # C10, C01 and mu0 by one factor, so that stays true on the tested ball
    ref_params, ref_interval = estimate(model, mapped, refine)
    ranges, on, clipped = training_bounds(model, ref_params, ref_interval)
    return {"params": map_params(ref_params, reference, size),
            "interval_90": map_ranges(ref_interval, reference, size),
            "training_range": map_ranges(ranges, reference, size),
            "group_range": group_ranges(model, speed), "at_bound": on, "clipped": clipped}


def model_inputs(processed, model: UniversalModel, allow: Collection[str] = ()
                 ) -> dict[str, float]:
    """The test's features described as the model's training described its noisy copies
    (`UniversalModel.feature_method`): the built-in model learned the features of the pulse
    through its samples, whose contact time noise shortens, and is given them so; the FE check
    still compares with the test's own (fitted) features. `allow`: the checks allowed when the
    test was processed (described again, it meets them again)."""
    features = processed.features
    if features.method == model.feature_method or not hasattr(processed, "filtered"):
        return features.values
    from ..records.features import extract_features

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)  # said once already, by `process`
        return extract_features(processed.filtered, method=model.feature_method,
                                allow=allow).values


def scaled_options(model: UniversalModel, size: BallSize):
    """The model's FE settings (`solver_options`) with the element size scaled to the ball: the
    study's mesh, similar on a ball of another size."""
    from dataclasses import replace

    options = model.solver_options()
    return replace(options, element_size_m=options.element_size_m * size.radius_m
                   / reference_size(model).radius_m)


def warn_failed_model(model: UniversalModel) -> None:
    """A model written with `universal train --force` after failing its held-out check is used
    only with a loud warning (models older than the check carry no record of it)."""
    check = model.metadata.get("held_out_check")
    if isinstance(check, dict) and check.get("passed") is False:
        worst = check.get("worst")
        r2 = (check.get("r2") or {}).get(worst)
        figure = f" ({worst}: held-out R^2 {r2:.3g})" if isinstance(r2, (int, float)) else ""
        warnings.warn(f"the universal model failed its own held-out check{figure} and was "
                      "written with --force: its estimates are not to be trusted",
                      InputWarning, stacklevel=3)


def check_max_nrmse(value: float) -> float:
    """A force NRMSE limit: a fraction of the test's peak force in (0, 1]."""
    return check_fraction("max_nrmse (--max-nrmse)", float(value))


def verify_run(spec: dict, measured_features, options=None, allow: Collection[str] = ()):
    """One FE run of the identified ball at the test's speed, compared with the test."""
    from ..records.features import extract_features
    from ..fe import SolverOptions, load_ball, simulate

    speed = measured_features.values["P15"]
    fe = simulate(load_ball(spec), speed, options or SolverOptions(), allow=allow)
    simulated = extract_features(fe.record())
    nrmse = pulse_nrmse(*features_pulse(measured_features), *features_pulse(simulated))
    return fe, compare(measured_features.values, simulated.values, nrmse)
