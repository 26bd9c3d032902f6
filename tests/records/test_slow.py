"""Longer sweeps of the verification checks (run with -m slow)."""

import numpy as np
import pytest

from ballimpact import extract_features, process
from ballimpact.pulses import half_sine, triangle

from test_features_analytic import (
    MASS_KG, PEAK_N, SPEED_M_S, assert_features, half_sine_closed_form, triangle_closed_form)
from test_kelvin_voigt import BALL, RATE_HZ, peak_force

pytestmark = pytest.mark.slow


@pytest.mark.parametrize("phase", np.linspace(0, 1, 40, endpoint=False))
def test_analytic_pulses_at_every_sampling_phase(phase):
    """All 19 features within 2% at 20 kHz for 40 phases of the sampling grid."""
    scalars = dict(phase=phase, mass_kg=MASS_KG, impact_speed_m_s=SPEED_M_S)
    assert_features(extract_features(half_sine(PEAK_N, 1e-3, 20e3, **scalars)).values,
                    half_sine_closed_form(1e-3), 0.02)
    assert_features(extract_features(triangle(PEAK_N, 0.3e-3, 0.7e-3, 20e3, **scalars)).values,
                    triangle_closed_form(0.3e-3, 0.7e-3), 0.02)


@pytest.mark.parametrize("options", [dict(filter="cfc10000", method="samples"), dict()])
def test_noisy_pulse_with_cfc_filter_over_many_seeds(options):
    """3% noise, 40 noise realisations: peak force and contact time within 3%, filtered by
    cfc10000 and described by the samples (docs/features.md, "Choosing a filter"), and with the
    default processing, unfiltered (the fitted edges; a filter spreads this pulse's force step
    at contact, which the fitted edges then measure: +2% contact time on average)."""
    record = BALL.record(RATE_HZ)
    worst_peak = worst_contact = 0.0
    for seed in range(40):
        rng = np.random.default_rng(1000 + seed)
        noisy = record.replace(
            force_n=record.force_n + 0.03 * peak_force() * rng.standard_normal(record.sample_count))
        values = process(noisy, uncertainty=False, **options).features.values
        worst_peak = max(worst_peak, abs(values["P6"] / peak_force() - 1))
        worst_contact = max(worst_contact, abs(values["P1"] / BALL.contact_time_s - 1))
    print(f"worst peak error {worst_peak:.4f}, worst contact-time error {worst_contact:.4f}")
    assert worst_peak < 0.03 and worst_contact < 0.03
