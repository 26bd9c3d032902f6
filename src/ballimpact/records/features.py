"""Characteristic values of an impact: the 19 of thesis table 6-1 and the load-cell identities.

All values come from one continuous description of the pulse, so that they do not depend on the
sampling rate: the force is taken as piecewise linear through the samples of the contact window,
its two ends at zero force, and the refined peak (see `refine_peak`). Crossing times, integrals and
moments of that curve are computed exactly, never by counting samples.

Definitions (docs/features.md; times relative to contact start):

- P1 contact time; P2, P3, P4 spans with force >= 10, 50, 90% of the peak (first up-crossing to
  last down-crossing); P5 peak time; P6 peak force; P7..P10 = P6 / P1..P4.
- P11 kurtosis and P14 skewness of the force values over the contact window sampled uniformly in
  time (biased and non-excess, as MATLAB `kurtosis`/`skewness` used by the thesis' `PARA`): here the
  continuous limit, (1/P1) times the integral of the powers of the curve.
- P12 = integral of F after the peak / integral before it.
- P13 = integral of F from the middle of the 90% window to the end of the 10% window / integral from
  the start of the 10% window to that middle (as the appendix code computes it; the text only says
  "integrated skewness based on P2 and P4").
- P15 impact speed, P16 rebound speed (measured, or from the impulse when not measured), P17 COR =
  P16 / P15, P18 mean deceleration (P15 + P16) / P1, P19 peak deceleration = change of velocity
  across the 90% window / P4, the velocity coming from integrating -F/m.

Load-cell identities (Cross 1999): impulse J = m (v_in + v_out); ball-centre compression
y(t) = v_in t - (1/m) double integral of F; energy lost = loop integral of F dy
= m v_in^2 (1 - e^2) / 2 with e the impulse COR.
"""

from __future__ import annotations

import warnings
from collections.abc import Collection
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..errors import InputError, InputWarning
from ..checks import check_allow
from .plausibility import check_momentum, check_polarity, select_pulse
from ..checks import check_positive
from .pulse_curve import PulseCurve
from .record import ContactWindow, ImpactRecord, contact_window

FEATURE_NAMES: dict[str, str] = {
    "P1": "contact_time_s",
    "P2": "span_above_10pct_s",
    "P3": "span_above_50pct_s",
    "P4": "span_above_90pct_s",
    "P5": "peak_time_s",
    "P6": "peak_force_n",
    "P7": "peak_force_per_contact_time_n_per_s",
    "P8": "peak_force_per_span_10pct_n_per_s",
    "P9": "peak_force_per_span_50pct_n_per_s",
    "P10": "peak_force_per_span_90pct_n_per_s",
    "P11": "kurtosis",
    "P12": "impulse_ratio_after_before_peak",
    "P13": "impulse_ratio_after_before_90pct_middle",
    "P14": "skewness",
    "P15": "impact_speed_m_s",
    "P16": "rebound_speed_m_s",
    "P17": "cor",
    "P18": "mean_deceleration_m_s2",
    "P19": "peak_deceleration_m_s2",
}

#: Default relative tolerance of the impulse-momentum check.
DEFAULT_IMPULSE_TOLERANCE = 0.05


# --------------------------------------------------------------------------- the pulse curve


def refine_peak(time_s: np.ndarray, force_n: np.ndarray, index: int) -> tuple[float, float]:
    """Sub-sample peak (time s, force N) around the largest sample `index`.

    Two local models compete on the five samples around the maximum: a parabola through the middle
    three (a rounded peak) and two straight lines through the outer pairs meeting in a cusp (a
    kinked peak, e.g. a triangle). Each predicts the samples it did not use; the one with the smaller
    misfit wins. With fewer neighbours, the parabola alone; the sample itself if neither is valid.
    """
    t, f, i = time_s, force_n, index
    best = (float(t[i]), float(f[i]))
    if i < 1 or i > f.size - 2:
        return best
    candidates = []
    a, b, c = np.polyfit(t[i - 1 : i + 2] - t[i], f[i - 1 : i + 2], 2)
    if a < 0:
        vertex = -b / (2 * a)
        if t[i - 1] - t[i] <= vertex <= t[i + 1] - t[i]:
            misfit = 0.0
            if i >= 2 and i <= f.size - 3:
                for j in (i - 2, i + 2):
                    x = t[j] - t[i]
                    misfit += abs(a * x * x + b * x + c - f[j])
            candidates.append((misfit, float(t[i] + vertex), float(c - b * b / (4 * a))))
    if 2 <= i <= f.size - 3:
        left = np.polyfit(t[i - 2 : i], f[i - 2 : i], 1)
        right = np.polyfit(t[i + 1 : i + 3], f[i + 1 : i + 3], 1)
        if left[0] > 0 and right[0] < 0:
            tc = (right[1] - left[1]) / (left[0] - right[0])
            if t[i - 1] <= tc <= t[i + 1]:
                predicted = min(np.polyval(left, t[i]), np.polyval(right, t[i]))
                misfit = 2 * abs(predicted - f[i])  # one residual, weighted like the parabola's two
                candidates.append((misfit, float(tc), float(np.polyval(left, tc))))
    if candidates:
        _, time, force = min(candidates)
        # a sub-sample peak rises above the top sample by less than the top sample rises above
        # its lower neighbour; more means the local model does not fit (a step, a flat top)
        if f[i] <= force <= 2 * f[i] - min(f[i - 1], f[i + 1]):
            best = (time, force)
    return best


def pulse_curve(record: ImpactRecord, window: ContactWindow) -> PulseCurve:
    """The piecewise-linear pulse over the contact window (times from contact start)."""
    # every sample strictly between the zero-force ends: those of the window, and any below the
    # threshold but above zero that the edge extrapolation reached past
    inside = (record.time_s > window.start_s) & (record.time_s < window.end_s)
    knots_t = [window.start_s, *record.time_s[inside], window.end_s]
    knots_f = [0.0, *record.force_n[inside], 0.0]
    peak = int(np.argmax(record.force_n))
    peak_t, peak_f = refine_peak(record.time_s, record.force_n, peak)
    t = np.array(knots_t) - window.start_s
    f = np.array(knots_f)
    if peak_f > f.max():
        at = int(np.searchsorted(t, peak_t - window.start_s))
        t = np.insert(t, at, peak_t - window.start_s)
        f = np.insert(f, at, peak_f)
    keep = np.concatenate([[True], np.diff(t) > 0])  # a crossing may coincide with a sample
    return PulseCurve(t[keep], f[keep])


# --------------------------------------------------------------------------- features


@dataclass(frozen=True)
class ImpactFeatures:
    """Everything `extract_features` derives from one record (SI units, times from contact start).

    `values` maps P1..P19 to numbers (names in `FEATURE_NAMES`); the curves `time_s`, `force_n`,
    `velocity_m_s` and `displacement_m` are the pulse curve's knots and the integrated ball-centre
    motion at them.
    """

    values: dict[str, float]
    window: ContactWindow
    mass_kg: float
    rebound_speed_source: str
    impulse_n_s: float
    impulse_expected_n_s: float | None
    impulse_relative_error: float | None
    impulse_tolerance: float
    impulse_cor: float
    max_compression_m: float
    energy_lost_j: float
    dynamic_stiffness_n_m: float
    time_s: np.ndarray
    force_n: np.ndarray
    velocity_m_s: np.ndarray
    displacement_m: np.ndarray
    warnings: list[str] = field(default_factory=list)
    method: str = "samples"
    uncertainty: dict[str, float] | None = None
    sample_interval_s: float | None = None  # the record's median time step (s)
    #: the record's samples over the contact (times from its start, the ends at zero force):
    #: what a model's pulse is compared with (`comparison.features_pulse`), noise and all, so
    #: that misfits and their standard errors see the measurement as it was; None for
    #: `samples`, whose `time_s`, `force_n` are the samples
    samples_time_s: np.ndarray | None = None
    samples_force_n: np.ndarray | None = None
    smoothing: float | None = None  # the fitted pulse's spline smoothing (unit interval, peak)

    @property
    def impulse_check_passed(self) -> bool | None:
        if self.impulse_relative_error is None:
            return None
        return abs(self.impulse_relative_error) <= self.impulse_tolerance

    def named(self) -> dict[str, float]:
        """The 19 values keyed by their descriptive names."""
        return {FEATURE_NAMES[key]: value for key, value in self.values.items()}

    def to_dict(self) -> dict[str, Any]:
        """JSON-able summary using the command-line contract's keys."""
        v = self.values
        return {
            "peak_force_n": v["P6"],
            "contact_time_s": v["P1"],
            "cor": v["P17"],
            "impact_speed_m_s": v["P15"],
            "rebound_speed_m_s": v["P16"],
            "rebound_speed_source": self.rebound_speed_source,
            "mass_kg": self.mass_kg,
            "impulse_n_s": self.impulse_n_s,
            "impulse_expected_n_s": self.impulse_expected_n_s,
            "impulse_relative_error": self.impulse_relative_error,
            "impulse_tolerance": self.impulse_tolerance,
            "impulse_check_passed": self.impulse_check_passed,
            "impulse_cor": self.impulse_cor,
            "max_compression_m": self.max_compression_m,
            "energy_lost_j": self.energy_lost_j,
            "dynamic_stiffness_n_m": self.dynamic_stiffness_n_m,
            "contact_window": {
                "start_s": self.window.start_s,
                "end_s": self.window.end_s,
                "threshold_n": self.window.threshold_n,
                "noise_rms_n": self.window.noise_rms_n,
            },
            "features": dict(v),
            "feature_names": dict(FEATURE_NAMES),
            "pulse_method": self.method,
            "uncertainty": self.uncertainty_dict(),
            "warnings": list(self.warnings),
        }

    def uncertainty_dict(self) -> dict[str, Any] | None:
        """The standard uncertainties (same units as the values; the 90% interval is the value
        +- 1.645 of them), keyed like `to_dict`: `features` P1..P19 and the named quantities."""
        if self.uncertainty is None:
            return None
        u = self.uncertainty
        named = {"peak_force_n": "P6", "contact_time_s": "P1", "cor": "P17",
                 "rebound_speed_m_s": "P16"}
        out: dict[str, Any] = {key: u.get(p) for key, p in named.items()}
        for key in ("impulse_n_s", "impulse_cor", "max_compression_m", "energy_lost_j",
                    "dynamic_stiffness_n_m"):
            out[key] = u.get(key)
        out["features"] = {key: u.get(key) for key in self.values}
        out["interval"] = "standard uncertainty from the record's noise (bootstrap); 90% interval = value +- 1.645 u"
        return out


def dynamic_stiffness(peak_force_n, mass_kg, impact_speed_m_s):
    """The dynamic stiffness (N/m) of an impact: the linear spring that a mass `mass_kg` (kg)
    striking it at `impact_speed_m_s` (m/s) loads to `peak_force_n` (N), whose peak is
    v sqrt(k m): k = F_peak^2 / (m v^2) (the quantity of ASTM F2845)."""
    return peak_force_n ** 2 / (mass_kg * impact_speed_m_s ** 2)


def curve_values(curve: PulseCurve, mass_kg: float, impact_speed_m_s: float,
                 rebound_speed_m_s: float) -> dict[str, float]:
    """P1..P19 of the pulse `curve` with these scalars (SI; see the module's definitions)."""
    mass, v_in, v_out = mass_kg, impact_speed_m_s, rebound_speed_m_s
    peak_at = int(np.argmax(curve.knots_n))
    peak_time, peak = float(curve.knots_s[peak_at]), float(curve.knots_n[peak_at])
    spans = {fraction: curve.span(fraction * peak) for fraction in (0.1, 0.5, 0.9)}
    widths = {fraction: end - start for fraction, (start, end) in spans.items()}
    p1 = curve.duration_s
    mean, m2, m3, m4 = (curve.mean_power(power, peak) for power in (1, 2, 3, 4))
    variance = m2 - mean**2
    third = m3 - 3 * mean * m2 + 2 * mean**3
    fourth = m4 - 4 * mean * m3 + 6 * mean**2 * m2 - 3 * mean**4
    (start10, end10), (start90, end90) = spans[0.1], spans[0.9]
    middle90 = 0.5 * (start90 + end90)
    return {
        "P1": p1,
        "P2": widths[0.1],
        "P3": widths[0.5],
        "P4": widths[0.9],
        "P5": peak_time,
        "P6": peak,
        "P7": peak / p1,
        "P8": peak / widths[0.1],
        "P9": peak / widths[0.5],
        "P10": peak / widths[0.9],
        "P11": fourth / variance**2,
        "P12": curve.integral(peak_time, p1) / curve.integral(0.0, peak_time),
        "P13": curve.integral(middle90, end10) / curve.integral(start10, middle90),
        "P14": third / variance**1.5,
        "P15": v_in,
        "P16": v_out,
        "P17": v_out / v_in,
        "P18": (v_in + v_out) / p1,
        "P19": curve.integral(start90, end90) / mass / widths[0.9],
    }


def extract_features(
    record: ImpactRecord,
    *,
    impulse_tolerance: float = DEFAULT_IMPULSE_TOLERANCE,
    threshold_fraction: float = 1e-3,
    noise_factor: float = 5.0,
    allow: Collection[str] = (),
    method: str = "samples",
    uncertainty: bool = False,
    noise_rms_n: float | None = None,
    smoothing: float | None = None,
    checked: bool = False,
) -> ImpactFeatures:
    """The 19 characteristic values and the load-cell identities of one impact.

    **Arguments:**

    - `record`: needs `mass_kg` and `impact_speed_m_s`; `rebound_speed_m_s` is estimated from the
      impulse, v_out = J/m - v_in, when missing. Remove the baseline and filter before calling.
    - `impulse_tolerance`: relative misfit allowed between the impulse J and m (v_in + v_out) when
      the rebound speed is measured; beyond it an `InputWarning` is issued (and listed in
      `warnings`).
    - `threshold_fraction`, `noise_factor`: the contact-window threshold (see `contact_window`).
    - `allow`: plausibility checks to turn from errors into warnings (`checks.CHECKS`).
    - `method`: `"samples"` (default) takes the pulse as piecewise linear through the samples,
      its ends extrapolated to zero from the window's outermost samples: exact for a noise-free
      record (a simulation). `"fit"` fits the contact start and end with the shape a contact
      must have and smooths between them (`reconstruct.fitted_pulse_curve`): for measured,
      noisy records (`pipeline.process` uses it); a record whose noise does not raise the
      contact threshold above `threshold_fraction` of the peak is described by its samples.
    - `noise_rms_n`: describe the record as one of this noise (N RMS) would be described (its
      threshold, the fit's smoothing and the edges' weight against their prior): a model's clean
      pulse compared with a noisy test (`comparison.measured_like`), with the test's spline
      `smoothing` (`ImpactFeatures.smoothing`).
    - `uncertainty`: also the standard uncertainty of every value from the record's noise
      (`reconstruct.bootstrap_uncertainty`; `ImpactFeatures.uncertainty`).
    - `checked`: the record has passed `plausibility.check_polarity` and `select_pulse` already
      (`pipeline.process` runs them before the baseline), so they are not run again.

    **Raises:** `InputError` if the mass or impact speed is missing, if the pulse is negative
    (`plausibility.check_polarity`: an inverted load cell), if there is no pulse or several
    (`plausibility.select_pulse`), if the impulse and the speeds cannot belong together
    (`plausibility.check_momentum`: a unit slip, COR > 1), or if the impulse is too small for the
    ball to have stopped (J < m v_in).
    """
    impulse_tolerance = check_positive("impulse_tolerance", impulse_tolerance)
    allow = check_allow(allow)
    if record.mass_kg is None:
        raise InputError("mass_kg: the ball mass is required (e.g. --mass-kg 0.16)")
    if record.impact_speed_m_s is None:
        raise InputError("impact_speed_m_s: the impact speed is required (e.g. --impact-speed-m-s 25)")
    mass, v_in = record.mass_kg, record.impact_speed_m_s

    if not checked:
        check_polarity(record)  # an inverted pulse: an error naming the fix
        select_pulse(record)  # several pulses: an error that lists them
    if method not in METHODS:
        raise InputError(f"method: {method!r}; allowed: {', '.join(METHODS)}")
    window, curve, fitted = _window_and_curve(record, threshold_fraction, noise_factor, method,
                                              noise_rms_n=noise_rms_n, smoothing=smoothing)
    impulse = curve.integral(0.0, curve.duration_s)
    wav = str(record.metadata.get("file", "")).lower().endswith(".wav")
    check_momentum(impulse, mass, v_in, record.rebound_speed_m_s, allow, wav=wav)
    notes: list[str] = []
    if impulse < mass * v_in:
        raise InputError(
            f"impulse {impulse:.4g} N s is less than m v_in = {mass * v_in:.4g} N s, so the ball "
            "did not even stop: check mass_kg, impact_speed_m_s and the force scaling"
        )
    if record.rebound_speed_m_s is None:
        v_out, source = impulse / mass - v_in, "impulse"
        expected = relative_error = None
    else:
        v_out, source = record.rebound_speed_m_s, "measured"
        expected = mass * (v_in + v_out)
        relative_error = impulse / expected - 1.0
        if abs(relative_error) > impulse_tolerance:
            where = f"{record.metadata['file']}: " if "file" in record.metadata else ""
            notes.append(
                f"{where}impulse check: integral of F dt = {impulse:.4g} N s differs from "
                f"m (v_in + v_out) = {expected:.4g} N s by {relative_error:+.1%} "
                f"(tolerance {impulse_tolerance:.1%})"
            )
    for note in notes:
        warnings.warn(note, InputWarning, stacklevel=2)

    values, quantities, velocity, displacement = _describe(curve, mass, v_in, v_out)
    spread = None
    if uncertainty:
        from .reconstruct import bootstrap_uncertainty

        def values_of(draw: ImpactRecord) -> dict[str, float]:
            _, c, _ = _window_and_curve(draw, threshold_fraction, noise_factor, method, fitted)
            return _all_values(c, mass, v_in, record.rebound_speed_m_s)

        spread = bootstrap_uncertainty(record, curve, window, values_of)
    return ImpactFeatures(
        values={key: float(value) for key, value in values.items()},
        window=window,
        mass_kg=mass,
        rebound_speed_source=source,
        impulse_expected_n_s=expected,
        impulse_relative_error=relative_error,
        impulse_tolerance=impulse_tolerance,
        **quantities,
        time_s=curve.knots_s,
        force_n=curve.knots_n,
        velocity_m_s=velocity,
        displacement_m=displacement,
        warnings=notes,
        method="samples" if fitted is None else "fit",
        uncertainty=spread,
        sample_interval_s=float(np.median(np.diff(record.time_s))),
        **_samples_pulse(record, window, fitted),
        smoothing=None if fitted is None else fitted.smoothing,
    )


def _samples_pulse(record: ImpactRecord, window: ContactWindow, fitted) -> dict[str, Any]:
    """`samples_time_s`, `samples_force_n` of a fitted pulse (none for the samples')."""
    if fitted is None:
        return {}
    inside = (record.time_s > window.start_s) & (record.time_s < window.end_s)
    t = np.concatenate([[window.start_s], record.time_s[inside], [window.end_s]])
    f = np.concatenate([[0.0], record.force_n[inside], [0.0]])
    return {"samples_time_s": t - window.start_s, "samples_force_n": f}


#: The pulse descriptions of `extract_features(method=...)`.
METHODS = ("samples", "fit")


def _window_and_curve(record: ImpactRecord, threshold_fraction: float, noise_factor: float,
                      method: str, like=None, noise_rms_n: float | None = None,
                      smoothing: float | None = None):
    """The contact window (its ends the curve's, for `fit`), the pulse curve and, for `fit`,
    the `reconstruct.FittedPulse` (None otherwise); `like` as in `fitted_pulse_curve`;
    `noise_rms_n` as in `extract_features`."""
    raised = threshold_fraction
    if noise_rms_n:
        raised = max(threshold_fraction, noise_factor * noise_rms_n / float(record.force_n.max()))
    window = contact_window(record, threshold_fraction=raised, noise_factor=noise_factor)
    if noise_rms_n:
        window = replace(window, noise_rms_n=noise_rms_n)
    # a record whose noise does not raise the threshold (a simulation, a clean record) is
    # described exactly by its samples
    if method == "fit" and window.threshold_n > threshold_fraction * record.force_n.max():
        from .reconstruct import fitted_pulse_curve

        fitted = fitted_pulse_curve(record, window, like, smoothing)
        if fitted is not None:
            return (replace(window, start_s=fitted.start.time_s, end_s=fitted.end.time_s),
                    fitted.curve, fitted)
    return window, pulse_curve(record, window), None


def _all_values(curve: PulseCurve, mass: float, v_in: float,
                measured_rebound: float | None) -> dict[str, float]:
    """The 19 values and the load-cell quantities of `curve` (the bootstrap's draws)."""
    impulse = curve.integral(0.0, curve.duration_s)
    v_out = impulse / mass - v_in if measured_rebound is None else measured_rebound
    values, quantities, _, _ = _describe(curve, mass, v_in, v_out)
    return {**values, **quantities}


def _describe(curve: PulseCurve, mass: float, v_in: float, v_out: float):
    """The 19 values of `curve`, its load-cell quantities (impulse, impulse COR, largest
    compression, energy lost, dynamic stiffness: `ImpactFeatures`' fields), and the ball's
    velocity (m/s) and displacement (m) through the contact."""
    values = curve_values(curve, mass, v_in, v_out)
    velocity = curve.velocity(v_in, mass)
    displacement = curve.displacement(velocity, mass)
    impulse = curve.integral(0.0, curve.duration_s)
    quantities = {"impulse_n_s": impulse, "impulse_cor": impulse / (mass * v_in) - 1.0,
                  "max_compression_m": float(np.max(displacement)),
                  "energy_lost_j": curve.work(velocity, mass),
                  "dynamic_stiffness_n_m": dynamic_stiffness(values["P6"], mass, v_in)}
    return values, quantities, velocity, displacement
