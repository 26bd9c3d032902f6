"""ImpactRecord validation, baseline removal, contact window and resampling."""

import numpy as np
import pytest

from ballimpact import ImpactRecord, InputError, contact_window, remove_baseline, resample
from ballimpact.records.pulses import half_sine


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (dict(time_s=[0.0, 1.0, 1.0, 2.0]), r"time_s: must be strictly increasing; sample 2 .* repeated"),
        (dict(time_s=[0.0, 2.0, 1.0, 3.0]), r"time_s: .* sample 2 .* decreasing"),
        (dict(force_n=[0.0, np.nan, 1.0, 0.0]), r"force_n: sample 1 is not finite"),
        (dict(force_n=[0.0, 1.0, 0.0]), r"force_n: has 3 samples, time_s has 4"),
        (dict(mass_kg=0.0), r"mass_kg = 0: allowed range \(0, inf\)"),
        (dict(mass_kg=-0.16), r"mass_kg = -0.16: allowed range \(0, inf\)"),
        (dict(impact_speed_m_s=float("inf")), r"impact_speed_m_s = inf: expected a finite number in \(0, inf\)"),
        (dict(rebound_speed_m_s=-1.0), r"rebound_speed_m_s = -1: allowed range \[0, inf\)"),
    ],
)
def test_invalid_records_name_the_field(changes, message):
    fields = dict(time_s=[0.0, 1.0, 2.0, 3.0], force_n=[0.0, 1.0, 1.0, 0.0])
    with pytest.raises(InputError, match=message):
        ImpactRecord(**{**fields, **changes})


def test_baseline_offset_is_removed_within_the_noise():
    record = half_sine(1e4, 1e-3, 100e3)
    rng = np.random.default_rng(3)
    noise = 20.0 * rng.standard_normal(record.sample_count)
    cleaned = remove_baseline(record.replace(force_n=record.force_n + 150.0 + noise))
    pre = cleaned.metadata["baseline_samples"]
    assert pre >= 60
    # offset recovered to within 4 standard errors of the mean of the pre-impact noise
    assert cleaned.metadata["baseline_offset_n"] == pytest.approx(150.0, abs=4 * 20.0 / np.sqrt(pre))


def test_no_pre_impact_samples_means_no_offset():
    """A record starting at the impact has no baseline to measure: its samples stay as they are."""
    record = half_sine(1e4, 1e-3, 100e3, pre_s=0.0)
    shifted = record.replace(force_n=record.force_n + 100.0)
    unchanged = remove_baseline(shifted)
    assert unchanged.metadata["baseline_offset_n"] == 0.0
    assert np.array_equal(unchanged.force_n, shifted.force_n)


@pytest.mark.parametrize(("cut", "where"), [(slice(130, None), "starts"), (slice(None, -170), "ends")])
def test_pulse_cut_off_by_the_record_is_an_input_error(cut, where):
    record = half_sine(1e4, 1e-3, 100e3)  # 1 ms pre and post: samples 100..200 are the pulse
    cropped = ImpactRecord(record.time_s[cut], record.force_n[cut])
    with pytest.raises(InputError, match=f"where the record {where}"):
        contact_window(cropped)


def test_resample_refuses_absurd_rates():
    with pytest.raises(InputError, match=r"rate_hz: 1e\+12 Hz gives"):
        resample(half_sine(1e3, 1e-3, 100e3), 1e12)


def test_contact_window_threshold_follows_the_noise():
    record = half_sine(1e4, 1e-3, 100e3)
    rng = np.random.default_rng(4)
    noisy = record.replace(force_n=record.force_n + 30.0 * rng.standard_normal(record.sample_count))
    window = contact_window(noisy)
    assert window.noise_rms_n == pytest.approx(30.0, rel=0.2)
    assert window.threshold_n == pytest.approx(5 * window.noise_rms_n)
    # the zero-force ends are extrapolated past the raised threshold: within 2 samples of the truth
    assert abs(window.start_s) < 2e-5 and abs(window.end_s - 1e-3) < 2e-5


@pytest.mark.parametrize(
    ("force", "message"),
    [
        (lambda rng, n: rng.standard_normal(n), "no pulse above the noise"),
        (lambda rng, n: np.zeros(n), "no pulse"),
        (lambda rng, n: -np.abs(np.sin(np.linspace(0, np.pi, n))), "polarity"),
    ],
)
def test_no_pulse_is_an_input_error(force, message):
    rng = np.random.default_rng(5)
    time = np.arange(2000) * 1e-5
    with pytest.raises(InputError, match=message):
        contact_window(ImpactRecord(time, force(rng, time.size)))


def test_resample_to_a_uniform_grid():
    """A half-sine sampled at jittered times, resampled to 200 kHz: within 1e-4 of the peak."""
    rng = np.random.default_rng(6)
    time = np.sort(rng.uniform(0, 1e-3, 400))
    pulse = lambda t: 1e3 * np.sin(np.pi * t / 1e-3)  # noqa: E731
    uniform = resample(ImpactRecord(time, pulse(time)), 200e3)
    assert np.allclose(np.diff(uniform.time_s), 5e-6)
    assert np.max(np.abs(uniform.force_n - pulse(uniform.time_s))) < 1e-4 * 1e3
    assert uniform.metadata["resampled_hz"] == 200e3


def test_linear_resampling_keeps_the_zeros_after_a_separation_zero():
    """A triangle pulse ending in exact zeros (a model's separation), resampled linearly onto a
    grid of about 8.01 model steps: piecewise-linear data come back exactly (to rounding) and every
    sample after the pulse stays 0, where a cubic spline rings on into the tail."""
    time = np.arange(0.0, 3e-3, 2.5e-6)
    force = np.interp(time, [0.0, 5e-4, 1e-3], [0.0, 1e4, 0.0], right=0.0)
    record = ImpactRecord(time_s=time, force_n=force, mass_kg=0.16, impact_speed_m_s=20.0)
    linear = resample(record, 1.0 / 20.025e-6, method="linear")
    expected = np.interp(linear.time_s, [0.0, 5e-4, 1e-3], [0.0, 1e4, 0.0], right=0.0)
    assert np.max(np.abs(linear.force_n - expected)) < 1e-9 * 1e4
    assert np.all(linear.force_n[linear.time_s > 1.001e-3] == 0.0)
    cubic = resample(record, 1.0 / 20.025e-6)
    assert np.any(cubic.force_n[cubic.time_s > 1.001e-3] != 0.0)
    with pytest.raises(ValueError, match="method 'akima'"):
        resample(record, 1e5, method="akima")
