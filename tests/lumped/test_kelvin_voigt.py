"""A linear spring-dashpot impact (docs/lumped.md "Verification"): the load-cell identities hold and
the integrated ball-centre motion returns to the closed form; with 3% noise and a CFC filter, peak
force and contact time stay within 3%."""

import warnings

import numpy as np
import pytest

from ballimpact import InputWarning, apply_filter, extract_features, process, remove_baseline
from ballimpact.records.pulses import KelvinVoigt

# a cricket ball (160 g) at 10 m/s, contact about 1 ms, COR 0.83
BALL = KelvinVoigt(mass_kg=0.16, stiffness_n_m=1.5e6, damping_n_s_m=60.0, impact_speed_m_s=10.0)
RATE_HZ = 1e6


def peak_force():
    return float(BALL.force_n(np.linspace(0, BALL.contact_time_s, 200001)).max())


def test_closed_form_contact_time_and_cor_match_the_ode():
    """The KelvinVoigt helper's closed forms against a direct ODE solution (1e-6)."""
    from scipy.integrate import solve_ivp

    m, k, c, v = BALL.mass_kg, BALL.stiffness_n_m, BALL.damping_n_s_m, BALL.impact_speed_m_s
    leave = lambda t, s: k * s[0] + c * s[1]  # noqa: E731
    leave.terminal, leave.direction = True, -1
    solution = solve_ivp(lambda t, s: [s[1], -(k * s[0] + c * s[1]) / m], (1e-9, 1), [v * 1e-9, v],
                         events=leave, rtol=1e-12, atol=1e-15)
    assert solution.t_events[0][0] == pytest.approx(BALL.contact_time_s, rel=1e-6)
    assert -solution.y_events[0][0][1] / v == pytest.approx(BALL.cor, rel=1e-6)


def test_impulse_check_and_integrated_motion():
    features = extract_features(BALL.record(RATE_HZ))
    # impulse = m (v_in + v_out) within 0.1%
    assert features.impulse_check_passed
    assert abs(features.impulse_relative_error) < 1e-3
    assert features.impulse_cor == pytest.approx(BALL.cor, rel=1e-3)
    assert features.values["P1"] == pytest.approx(BALL.contact_time_s, rel=2e-3)
    # y(t) = v_in t - (1/m) double integral of F returns x(t) = (v/w) e^(-bt) sin(wt)
    # (compared at absolute times: the detected start may be up to one sample before the force
    # step c v_in at t = 0, and before it the ball flies freely)
    t = features.time_s + features.window.start_s
    exact = np.where(t >= 0, BALL.displacement_m(np.clip(t, 0, None)), BALL.impact_speed_m_s * t)
    exact -= exact[0]
    assert np.max(np.abs(features.displacement_m - exact)) < 2e-3 * exact.max()
    assert features.velocity_m_s[-1] == pytest.approx(-BALL.cor * BALL.impact_speed_m_s, rel=2e-3)
    assert features.energy_lost_j == pytest.approx(
        BALL.mass_kg * BALL.impact_speed_m_s**2 * (1 - BALL.cor**2) / 2, rel=1e-2)


def test_rebound_speed_from_impulse_when_not_measured():
    features = extract_features(BALL.record(RATE_HZ, measured_rebound=False))
    assert features.rebound_speed_source == "impulse"
    assert features.values["P17"] == pytest.approx(BALL.cor, rel=1e-3)
    assert features.impulse_check_passed is None


def test_impulse_check_warns_beyond_tolerance():
    record = BALL.record(RATE_HZ).replace(rebound_speed_m_s=0.9 * BALL.cor * BALL.impact_speed_m_s)
    with pytest.warns(InputWarning, match="impulse check"):
        features = extract_features(record, impulse_tolerance=0.02)
    assert features.impulse_check_passed is False
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert extract_features(record, impulse_tolerance=0.10).impulse_check_passed


@pytest.mark.parametrize("seed", range(5))
def test_noisy_pulse_with_cfc_filter(seed):
    """3% (of peak, RMS) white noise and a load-cell offset; CFC filtered: within 3%."""
    record = BALL.record(RATE_HZ)
    rng = np.random.default_rng(seed)
    noisy = record.replace(force_n=record.force_n + 50.0
                           + 0.03 * peak_force() * rng.standard_normal(record.sample_count))
    features = process(noisy, filter="cfc10000").features
    assert features.values["P6"] == pytest.approx(peak_force(), rel=0.03)
    assert features.values["P1"] == pytest.approx(BALL.contact_time_s, rel=0.03)


def test_low_cfc_class_warns_for_a_short_pulse():
    with pytest.warns(InputWarning, match="CFC 1000 .* low for a"):
        apply_filter(remove_baseline(BALL.record(RATE_HZ)), "cfc1000")


@pytest.mark.slow
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
