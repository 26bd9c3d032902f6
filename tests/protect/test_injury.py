"""Head-injury criteria (`ballimpact.protect.injury`) against closed forms, a brute-force double
loop and a continuous-time optimisation."""

import math

import numpy as np
import pytest
from scipy.constants import g
from scipy.optimize import minimize_scalar
from scipy.special import beta

from ballimpact.errors import InputError
from ballimpact.protect import (HicResult, gadd_severity_index, hic, hic15, hic36,
                                peak_acceleration_g)
from ballimpact.protect import injury

STEP = 1e-5  # s; 15 ms and 36 ms are whole numbers of steps


def _constant_pulse(amplitude_g, duration_s, pad_s=0.0):
    """A = amplitude_g for 0 <= t <= duration_s, zero on pad_s either side (sampled every STEP)."""
    n_pulse, n_pad = round(duration_s / STEP), round(pad_s / STEP)
    k = np.arange(-n_pad, n_pulse + n_pad + 1)
    a = np.where((k >= 0) & (k <= n_pulse), amplitude_g * g, 0.0)
    return k * STEP, a


def _half_sine(amplitude_g, duration_s, samples):
    t = np.linspace(0.0, duration_s, samples)
    return t, amplitude_g * g * np.sin(np.pi * t / duration_s)


def _continuous_half_sine_hic(amplitude_g, duration_s, window_s):
    """Continuous HIC of A sin(pi t / T) on [0, T] by nested bounded scalar searches: outer over
    the duration t2 - t1, inner over t1; the integral is in closed form."""
    def integral(t):
        return amplitude_g * duration_s / np.pi * (1.0 - np.cos(np.pi * t / duration_s))

    def best_for(length):
        res = minimize_scalar(lambda t1: -(integral(t1 + length) - integral(t1)) ** 2.5
                              / length ** 1.5, bounds=(0.0, duration_s - length),
                              method="bounded", options={"xatol": 1e-12})
        return -res.fun

    res = minimize_scalar(lambda length: -best_for(length),
                          bounds=(1e-6 * duration_s, min(window_s, duration_s)),
                          method="bounded", options={"xatol": 1e-12})
    return -res.fun


def _brute_force_hic(t, a, window_s):
    """The discrete definition, pair by pair: trapezoidal integral of |a|/g between samples."""
    a_g = np.abs(a) / g
    cumulative = [0.0]
    for k in range(1, len(t)):
        cumulative.append(cumulative[-1] + 0.5 * (a_g[k] + a_g[k - 1]) * (t[k] - t[k - 1]))
    best = (-1.0, None, None)
    for i in range(len(t)):
        for j in range(i + 1, len(t)):
            length = t[j] - t[i]
            if length > window_s:
                break
            value = length * ((cumulative[j] - cumulative[i]) / length) ** 2.5
            if value > best[0]:
                best = (value, t[i], t[j])
    return best


# --- Constant pulse: HIC = T A^2.5 (T <= window), window A^2.5 (T > window); SI = T A^2.5 -------

@pytest.mark.parametrize("duration_s", [0.004, 0.010, 0.015])
def test_constant_pulse_within_window_hic_is_whole_pulse(duration_s):
    # With zero padding the trapezoid ramps up and down over one step on either side; taking the
    # ramps in adds less integral than duration, so the maximum is still exactly [0, T].
    # T = 15 ms = the window itself checks that the window's end is included despite rounding.
    amplitude = 80.0
    t, a = _constant_pulse(amplitude, duration_s, pad_s=0.005)
    result = hic15(t, a)
    assert isinstance(result, HicResult)
    assert result.value == pytest.approx(duration_s * amplitude ** 2.5, rel=1e-9)
    assert result.t1_s == pytest.approx(0.0, abs=1e-12)
    assert result.t2_s == pytest.approx(duration_s, abs=1e-12)


@pytest.mark.parametrize("function, window_s", [(hic15, 0.015), (hic36, 0.036)])
def test_constant_pulse_longer_than_window_hic_is_window(function, window_s):
    amplitude = 60.0
    t, a = _constant_pulse(amplitude, 0.050, pad_s=0.005)
    result = function(t, a)
    assert result.value == pytest.approx(window_s * amplitude ** 2.5, rel=1e-9)
    assert result.t2_s - result.t1_s == pytest.approx(window_s, rel=1e-9)


def test_constant_pulse_severity_index():
    amplitude, duration = 50.0, 0.010
    t, a = _constant_pulse(amplitude, duration)
    assert gadd_severity_index(t, a) == pytest.approx(duration * amplitude ** 2.5, rel=1e-12)
    # Zero padding: the trapezoid of the sampled (|a|/g)^2.5 adds half a step at each end.
    t, a = _constant_pulse(amplitude, duration, pad_s=0.002)
    assert gadd_severity_index(t, a) == pytest.approx((duration + STEP) * amplitude ** 2.5,
                                                      rel=1e-12)


def test_sign_is_ignored():
    t, a = _constant_pulse(80.0, 0.010, pad_s=0.005)
    assert hic15(t, -a).value == pytest.approx(hic15(t, a).value, rel=1e-15)
    assert gadd_severity_index(t, -a) == pytest.approx(gadd_severity_index(t, a), rel=1e-15)
    assert peak_acceleration_g(t, -a) == pytest.approx(80.0, rel=1e-15)


# --- Half-sine pulse --------------------------------------------------------------------------

def test_half_sine_peak_and_severity_index():
    amplitude, duration = 120.0, 0.008
    t, a = _half_sine(amplitude, duration, 20_001)
    assert peak_acceleration_g(t, a) == pytest.approx(amplitude, rel=1e-12)
    # integral_0^T sin^2.5(pi t / T) dt = T / pi * B(1.75, 0.5)
    expected = amplitude ** 2.5 * duration / np.pi * beta(1.75, 0.5)
    assert gadd_severity_index(t, a) == pytest.approx(expected, rel=1e-4)


def test_peak_in_g_uses_standard_gravity():
    assert peak_acceleration_g([0.0, 1.0], [9.80665, -2.0]) == 1.0


@pytest.mark.parametrize("window_s", [0.004, 0.015])
def test_hic_matches_brute_force_on_coarse_irregular_grid(window_s):
    # Zero padding and an irregular grid exercise the window test with unequal steps; with
    # window 4 ms < the 10 ms pulse the window constraint is active.
    rng = np.random.default_rng(7)
    t = np.sort(np.concatenate([[0.0, 0.016], rng.uniform(0.0, 0.016, 150)]))
    a = np.where((t > 0.003) & (t < 0.013), 90.0 * g * np.sin(np.pi * (t - 0.003) / 0.010), 0.0)
    expected, t1, t2 = _brute_force_hic(t, a, window_s)
    result = hic(t, a, window_s)
    assert result.value == pytest.approx(expected, rel=1e-12)
    assert (result.t1_s, result.t2_s) == (t1, t2)


@pytest.mark.parametrize("duration_s, window_s, samples", [
    (duration, window, samples)
    for duration, window in [(0.010, 0.015), (0.030, 0.015), (0.030, 0.036)]
    for samples in (2_001, 20_001)] + [(0.010, 0.015, 20_000)])
def test_half_sine_hic_matches_continuous_optimum(duration_s, window_s, samples):
    # 2,001 and 20,000 samples take the exact all-pairs path; 20,001 samples with more than 4,000
    # per window take the resampled path. For T = 10 ms the optimum (about 0.67 T) is inside the
    # window; for T = 30 ms and HIC15 the window is the constraint.
    amplitude = 100.0
    t, a = _half_sine(amplitude, duration_s, samples)
    result = hic(t, a, window_s)
    continuous = _continuous_half_sine_hic(amplitude, duration_s, window_s)
    assert result.value == pytest.approx(continuous, rel=1e-3)
    # The sine is concave, so its piecewise-linear interpolant lies below it and sample endpoints
    # restrict the search: the discrete HIC can only be lower (1e-7: the bounded search stops
    # short of the window's end by its tolerance, ~1e-8 relative).
    assert result.value <= continuous * (1.0 + 1e-7)
    # Textbook: for a half-sine the optimal interval is symmetric about the peak.
    step = max(duration_s / (samples - 1), window_s / injury.RESAMPLED_STEPS_PER_WINDOW)
    assert abs(result.t1_s + result.t2_s - duration_s) <= step * (1.0 + 1e-9)
    assert result.t2_s - result.t1_s <= window_s * (1.0 + 1e-9)


def test_half_sine_unconstrained_interval_length():
    # Maximising sin^2.5(x) / x^1.5 over x = pi d / T (half-length d) gives tan x = 5 x / 3,
    # x = 1.0517...; the interval is 2 x T / pi ~ 0.6695 T when that fits in the window.
    x = minimize_scalar(lambda x: -math.sin(x) ** 2.5 / x ** 1.5, bounds=(0.1, 1.5),
                        method="bounded", options={"xatol": 1e-12}).x
    duration = 0.010
    t, a = _half_sine(100.0, duration, 2_001)
    result = hic15(t, a)
    step = duration / 2_000
    assert result.t2_s - result.t1_s == pytest.approx(2 * x * duration / np.pi, abs=2 * step)


# --- Long histories ---------------------------------------------------------------------------

@pytest.mark.parametrize("span_s", [0.05, 5.0])
def test_long_history_runs(span_s):
    # 50,000 samples: densely sampled (resampled path) and sparsely sampled (few per window).
    t = np.linspace(0.0, span_s, 50_000)
    a = 50.0 * g * np.exp(-((t - 0.5 * span_s) / 0.004) ** 2) + 5.0 * g * np.sin(900.0 * t)
    for function in (hic15, hic36):
        result = function(t, a)
        assert np.isfinite(result.value) and result.value > 0.0
        assert 0.0 < result.t2_s - result.t1_s <= (0.015 if function is hic15 else 0.036) + 1e-9
    assert np.isfinite(gadd_severity_index(t, a))


# --- Bad input --------------------------------------------------------------------------------

GOOD_T = np.linspace(0.0, 0.01, 11)
GOOD_A = np.full(11, 100.0)


@pytest.mark.parametrize("t, a, name", [
    (GOOD_T, GOOD_A[:-1], "acceleration_m_s2"),
    ([0.0], [1.0], "time_s"),
    ([], [], "time_s"),
    ([0.0, 0.002, 0.001], [1.0, 2.0, 3.0], "time_s"),
    ([0.0, 0.001, 0.001], [1.0, 2.0, 3.0], "time_s"),
    ([0.0, np.inf, 0.002], [1.0, 2.0, 3.0], "time_s"),
    ([0.0, 0.001, 0.002], [1.0, np.nan, 3.0], "acceleration_m_s2"),
    (np.zeros((2, 3)), np.zeros((2, 3)), "time_s"),
    (["a", "b"], [1.0, 2.0], "time_s"),
])
@pytest.mark.parametrize("function", [peak_acceleration_g, gadd_severity_index, hic, hic15, hic36])
def test_bad_history_raises_input_error(function, t, a, name):
    with pytest.raises(InputError, match=name) as info:
        function(t, a)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("window_s", [0.0, -0.015, np.nan, np.inf, 1e-6])
def test_bad_window_raises_input_error(window_s):
    # 1 us is shorter than every 1 ms sample interval: no interval to evaluate.
    with pytest.raises(InputError, match="window_s"):
        hic(GOOD_T, GOOD_A, window_s)
