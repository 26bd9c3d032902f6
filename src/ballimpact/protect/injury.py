"""Head-injury criteria of a sampled acceleration history: peak acceleration, the Head Injury
Criterion (HIC, HIC15, HIC36) and the Gadd Severity Index.

All inputs are SI: time in s, acceleration in m/s^2 (signed or already the resultant; the criteria
use its magnitude). The criteria themselves are defined on the acceleration in units of g
(g = 9.80665 m/s^2, `scipy.constants.g`) with time in s, which is how the published limits are
stated (e.g. HIC15 <= 700 in FMVSS 208).

Between samples the acceleration is taken as piecewise linear, so its integral is the trapezoidal
rule (`scipy.integrate.cumulative_trapezoid`).

Sources:
  - Gadd, C. W. (1966). Use of a weighted-impulse criterion for estimating injury hazard. Proc. 10th
    Stapp Car Crash Conference, SAE 660793.
  - Versace, J. (1971). A review of the severity index. Proc. 15th Stapp Car Crash Conference,
    SAE 710881.
  - NHTSA, FMVSS No. 208, Occupant crash protection, 49 CFR 571.208 (HIC15; HIC36 in earlier
    editions).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.constants import g as G_STANDARD
from scipy.integrate import cumulative_trapezoid, trapezoid

from ..errors import InputError

HIC15_WINDOW_S = 0.015
HIC36_WINDOW_S = 0.036

# Up to this many samples HIC is evaluated over every pair of samples (exact for the sampled,
# piecewise-linear history); 20,000 samples with 15,000 per window takes about a second.
EXACT_MAX_SAMPLES = 20_000
# Longer histories with more samples than this per window are first put on a uniform grid with this
# many steps per window, which bounds the work at (samples on the grid) x (steps per window).
RESAMPLED_STEPS_PER_WINDOW = 4_000
# Pairs whose duration exceeds the window by rounding only (t2 - t1 = window on a grid whose times
# are not exact in binary) still count as inside it.
_WINDOW_REL_TOL = 1e-9


@dataclass(frozen=True)
class HicResult:
    """Head Injury Criterion: `value` (a plain number by convention, computed with acceleration
    in g and time in s) and the interval [`t1_s`, `t2_s`] (s) that maximises it."""

    value: float
    t1_s: float
    t2_s: float


def peak_acceleration_g(time_s, acceleration_m_s2) -> float:
    """Largest magnitude of the acceleration (m/s^2, sampled at `time_s` in s), in g."""
    _, a = _history(time_s, acceleration_m_s2)
    return float(np.max(np.abs(a)) / G_STANDARD)


def gadd_severity_index(time_s, acceleration_m_s2) -> float:
    """Gadd Severity Index SI = integral of (|a|/g)^2.5 dt over the whole history (Gadd 1966).

    `time_s` in s, `acceleration_m_s2` in m/s^2; SI is a plain number by convention, computed with
    a in g and t in s. The integrand is sampled and integrated by the trapezoidal
    rule. Gadd proposed SI = 1000 as the threshold of danger to life for frontal head impacts."""
    t, a = _history(time_s, acceleration_m_s2)
    return float(trapezoid((np.abs(a) / G_STANDARD) ** 2.5, t))


def hic(time_s, acceleration_m_s2, window_s: float = HIC15_WINDOW_S) -> HicResult:
    """Head Injury Criterion (Versace 1971; the form used by NHTSA, FMVSS 208):

        HIC = max over t1 < t2, t2 - t1 <= window_s of (t2 - t1) * [ integral_t1^t2 a/g dt
              / (t2 - t1) ]^2.5

    with a the magnitude of the acceleration (`acceleration_m_s2` in m/s^2 at `time_s` in s),
    t in s and `window_s` in s (0.015 for HIC15, 0.036 for HIC36).

    How it is computed: the integral is the cumulative trapezoid of |a|/g (exact for the
    piecewise-linear history) and t1, t2 run over the sample times. For up to `EXACT_MAX_SAMPLES`
    samples, or whenever a window holds at most `RESAMPLED_STEPS_PER_WINDOW` samples, every pair of
    samples within the window is evaluated (vectorised over t1, one lag at a time so memory stays
    O(samples)): the exact maximum of this discrete definition. Longer, densely sampled histories
    are first put on a uniform grid of `RESAMPLED_STEPS_PER_WINDOW` steps per window (the integral
    is still that of the original piecewise-linear history, evaluated exactly at the grid
    points), so t1 and t2 are then resolved to window_s / 4000."""
    t, a = _history(time_s, acceleration_m_s2)
    window = float(window_s)
    if not np.isfinite(window) or window <= 0.0:
        raise InputError(f"window_s: must be a finite duration > 0 s, got {window_s!r}")
    a_g = np.abs(a) / G_STANDARD
    integral = cumulative_trapezoid(a_g, t, initial=0.0)
    if t.size > EXACT_MAX_SAMPLES and _max_lag(t, window) > RESAMPLED_STEPS_PER_WINDOW:
        t, integral = _resample(t, a_g, integral, window)
    lag_max = _max_lag(t, window)
    if lag_max < 1:
        raise InputError(f"window_s: {window} s is shorter than every sample interval of time_s "
                         f"(shortest {np.min(np.diff(t)):.6g} s)")
    # HIC over [t_i, t_j] is (dI / dt^0.6)^2.5 with dI = I_j - I_i; maximise the score
    # dI / dt^0.6 (monotone in HIC) and raise to 2.5 once at the end.
    limit = window * (1.0 + _WINDOW_REL_TOL)
    best, best_i, best_j = -1.0, 0, 1
    for lag in range(1, lag_max + 1):
        dt = t[lag:] - t[:-lag]
        d_integral = integral[lag:] - integral[:-lag]
        score = np.where(dt <= limit, d_integral / dt ** 0.6, -1.0)
        i = int(np.argmax(score))
        if score[i] > best:  # strict: among equal values keep the shortest interval
            best, best_i, best_j = float(score[i]), i, i + lag
    return HicResult(value=max(best, 0.0) ** 2.5, t1_s=float(t[best_i]), t2_s=float(t[best_j]))


def hic15(time_s, acceleration_m_s2) -> HicResult:
    """HIC with a 15 ms window (FMVSS 208); see `hic`. Inputs in s and m/s^2."""
    return hic(time_s, acceleration_m_s2, HIC15_WINDOW_S)


def hic36(time_s, acceleration_m_s2) -> HicResult:
    """HIC with a 36 ms window (FMVSS 208 before HIC15); see `hic`. Inputs in s and m/s^2."""
    return hic(time_s, acceleration_m_s2, HIC36_WINDOW_S)


def _history(time_s, acceleration_m_s2) -> tuple[np.ndarray, np.ndarray]:
    """The two arrays as 1-D floats, checked: same length, >= 2 samples, finite, time increasing."""
    arrays = []
    for name, values in (("time_s", time_s), ("acceleration_m_s2", acceleration_m_s2)):
        try:
            array = np.asarray(values, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InputError(f"{name}: not an array of numbers ({exc})") from None
        if array.ndim != 1:
            raise InputError(f"{name}: must be 1-D, got shape {array.shape}")
        bad = np.flatnonzero(~np.isfinite(array))
        if bad.size:
            raise InputError(f"{name}: non-finite value {array[bad[0]]} at index {bad[0]}")
        arrays.append(array)
    t, a = arrays
    if t.size != a.size:
        raise InputError(f"acceleration_m_s2: {a.size} samples but time_s has {t.size}")
    if t.size < 2:
        raise InputError(f"time_s: needs at least 2 samples, got {t.size}")
    steps = np.diff(t)
    if np.any(steps <= 0.0):
        k = int(np.flatnonzero(steps <= 0.0)[0])
        raise InputError(f"time_s: must be strictly increasing, but time_s[{k + 1}] = {t[k + 1]} "
                         f"<= time_s[{k}] = {t[k]}")
    return t, a


def _max_lag(t: np.ndarray, window: float) -> int:
    """Largest j - i with t[j] - t[i] <= window (same tolerance as `hic`)."""
    last = np.searchsorted(t, t + window * (1.0 + _WINDOW_REL_TOL), side="right") - 1
    return int(np.max(last - np.arange(t.size)))


def _resample(t: np.ndarray, a_g: np.ndarray, integral: np.ndarray,
              window: float) -> tuple[np.ndarray, np.ndarray]:
    """Uniform grid over [t[0], t[-1]] with at most window / RESAMPLED_STEPS_PER_WINDOW spacing,
    and the integral of the piecewise-linear a_g evaluated exactly at its points."""
    steps = int(np.ceil((t[-1] - t[0]) * RESAMPLED_STEPS_PER_WINDOW / window))
    grid = np.linspace(t[0], t[-1], steps + 1)
    i = np.clip(np.searchsorted(t, grid, side="right") - 1, 0, t.size - 2)
    h = t[i + 1] - t[i]
    s = grid - t[i]
    # Integral of a linear segment from t[i] to t[i] + s: a_i s + (a_{i+1} - a_i) s^2 / (2 h).
    on_grid = integral[i] + a_g[i] * s + (a_g[i + 1] - a_g[i]) * s * s / (2.0 * h)
    return grid, on_grid
