"""Filters: the CFC class against the SAE J211-1 appendix C recursion written out independently,
its frequency response, and the polynomial-reproduction property of Savitzky-Golay, LOESS and the
polynomial fit."""

import numpy as np
import pytest

from ballimpact import ImpactRecord, InputError, apply_filter
from ballimpact.records.filters import cfc_filter, lowess, polynomial_fit, savitzky_golay
from ballimpact.records.pulses import half_sine


def j211_pass(x, rate_hz, cfc):
    """One pass of the J211-1 appendix C 2-pole difference equation, as the standard writes it."""
    wd = 2 * np.pi * cfc * 2.0775
    wa = np.sin(wd / rate_hz / 2) / np.cos(wd / rate_hz / 2)
    den = 1 + np.sqrt(2) * wa + wa**2
    a0 = wa**2 / den
    a1, a2 = 2 * a0, a0
    b1 = -2 * (wa**2 - 1) / den
    b2 = (-1 + np.sqrt(2) * wa - wa**2) / den
    y = np.zeros_like(x)
    for i in range(2, x.size):
        y[i] = a0 * x[i] + a1 * x[i - 1] + a2 * x[i - 2] + b1 * y[i - 1] + b2 * y[i - 2]
    return y


@pytest.mark.parametrize("cfc", [60, 180, 600, 1000])
def test_cfc_matches_the_j211_recursion(cfc):
    """Forward-backward J211 recursion vs ours on a random signal: same away from the ends, where
    start-up transients (J211 pads; scipy pads differently) have died out (1e-6 of the signal)."""
    rate = 20e3
    rng = np.random.default_rng(cfc)
    x = np.cumsum(rng.standard_normal(40000))
    reference = j211_pass(j211_pass(x, rate, cfc)[::-1], rate, cfc)[::-1]
    ours = cfc_filter(x, rate, cfc)
    middle = slice(10000, 30000)
    assert np.max(np.abs(ours[middle] - reference[middle])) < 1e-6 * np.ptp(x)


@pytest.mark.parametrize("cfc", [60, 1000])
def test_cfc_frequency_response(cfc):
    """Steady sine gain: 1 within 0.1% at 0.1 CFC; -3 dB within 0.5 dB at 1.65 CFC (J211's
    nominal corner); below -30 dB at 10 CFC."""
    rate = 100 * cfc
    t = np.arange(200000) / rate
    middle = slice(50000, 150000)

    def gain(frequency):
        x = np.sin(2 * np.pi * frequency * t)
        return np.sqrt(2) * np.sqrt(np.mean(cfc_filter(x, rate, cfc)[middle] ** 2))

    assert gain(0.1 * cfc) == pytest.approx(1.0, abs=1e-3)
    assert 20 * np.log10(gain(1.65 * cfc)) == pytest.approx(-3.0, abs=0.5)
    assert 20 * np.log10(gain(10 * cfc)) < -30


def test_cfc_needs_a_sampling_rate_above_twice_the_design_frequency():
    with pytest.raises(InputError, match="CFC 1000 needs a sampling rate above 4155 Hz"):
        cfc_filter(np.zeros(100), 4000.0, 1000)


def test_savgol_and_loess_reproduce_low_order_polynomials():
    """Local fits of degree >= the polynomial's reproduce it exactly (1e-9), ends included."""
    rate = 10e3
    t = np.arange(500) / rate
    quadratic = 3.0 + 2e3 * t - 4e6 * t**2
    cubic = quadratic + 5e8 * t**3
    assert np.allclose(savitzky_golay(cubic, rate, 2e-3), cubic, rtol=0, atol=1e-9 * np.ptp(cubic))
    assert np.allclose(lowess(quadratic, rate, 3e-3, degree=2), quadratic, rtol=0,
                       atol=1e-9 * np.ptp(quadratic))
    line = 1.0 + 5e3 * t
    assert np.allclose(lowess(line, rate, 3e-3, degree=1), line, rtol=0, atol=1e-9 * np.ptp(line))


@pytest.mark.parametrize("name", ["savgol", "lowess", "loess", "cfc10000"])
def test_smoothers_reduce_noise_and_keep_the_pulse(name):
    """On a 1 ms half-sine with 3% noise at 1 MHz: the residual from the clean pulse drops at
    least threefold, and the peak stays within 2%."""
    clean = half_sine(5e3, 1e-3, 1e6)
    rng = np.random.default_rng(7)
    noise = 0.03 * 5e3 * rng.standard_normal(clean.sample_count)
    smoothed = apply_filter(clean.replace(force_n=clean.force_n + noise), name)
    residual = smoothed.force_n - clean.force_n
    assert np.sqrt(np.mean(residual**2)) < np.sqrt(np.mean(noise**2)) / 3
    assert smoothed.force_n.max() == pytest.approx(5e3, rel=0.02)
    assert smoothed.metadata["filter"] == name


def test_polynomial_fit_reproduces_a_degree_five_pulse():
    t = np.linspace(0, 1e-3, 201)
    pulse = 1e4 * (t / 1e-3) * (1 - t / 1e-3) * (1 + 3 * (t / 1e-3) ** 3)  # degree 5
    padded_t = np.concatenate([t[0] - 1e-5 * np.arange(20, 0, -1), t, t[-1] + 1e-5 * np.arange(1, 21)])
    padded = np.concatenate([np.zeros(20), pulse, np.zeros(20)])
    fitted = polynomial_fit(padded_t, padded, 20, 220)
    assert np.allclose(fitted, padded, atol=1e-8 * pulse.max())
    record = ImpactRecord(padded_t, padded)
    assert np.allclose(apply_filter(record, "poly5").force_n, padded, atol=1e-6 * pulse.max())


def test_filter_input_errors():
    record = half_sine(1e3, 1e-3, 100e3)
    with pytest.raises(InputError, match="filter: unknown name 'butter'"):
        apply_filter(record, "butter")
    uneven = record.replace(time_s=record.time_s + 0.3e-5 * np.sin(np.arange(record.sample_count)))
    with pytest.raises(InputError, match="not uniformly sampled"):
        apply_filter(uneven, "cfc1000")
    with pytest.raises(InputError, match="window_s: .* need at least"):
        apply_filter(record, "savgol", window_s=2e-5)
    for name in ("savgol", "loess"):
        with pytest.raises(InputError, match="window_s: .* longer than the record"):
            apply_filter(record, name, window_s=1.0)
    with pytest.raises(InputError, match="CFC filter needs more than 9 samples"):
        cfc_filter(np.ones(7), 1e6, 1000)
