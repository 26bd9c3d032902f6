"""Lumped models against their closed forms (docs/lumped.md "Verification"), with the
issue's 0.1% tolerance unless stated."""

import math

import numpy as np
import pytest

from ballimpact import InputError, extract_features
from ballimpact.closedform import hertz_impact, power_law_contact_constant, undamped_power_law
from ballimpact.lumped import (
    MODELS,
    hunt_crossley_cor,
    hunt_crossley_lambda,
    kelvin_voigt_from_test,
    simulate,
    thesis_tables,
)
from ballimpact.lumped.simulate import parameter_vector, run_one
from ballimpact.lumped.thesis import sim1
from ballimpact.records.pulses import KelvinVoigt

M, V = 0.16, 20.0


def contact(record):
    return record.metadata["contact_time_s"]


def test_power_law_constant_known_values():
    assert power_law_contact_constant(1.0) == pytest.approx(math.pi, rel=1e-12)
    assert power_law_contact_constant(1.5) == pytest.approx(2.94328, rel=2e-6)


@pytest.mark.parametrize("exponent", [1.0, 1.25, 1.5, 2.0])
def test_undamped_power_law_spring(exponent):
    k = 2e7 * 0.006 ** (1.3 - exponent)  # about 12 kN at 6 mm whatever the exponent
    record = simulate("single_element", {"k": k, "alpha": exponent, "c": 0.0},
                      impact_speed_m_s=V, mass_kg=M)
    y_max, f_max, t_c = undamped_power_law(k, exponent, M, V)
    assert contact(record) == pytest.approx(t_c, rel=1e-3)
    assert (record.force_n.max() / k) ** (1 / exponent) == pytest.approx(y_max, rel=1e-3)
    assert record.force_n.max() == pytest.approx(f_max, rel=1e-3)
    assert record.rebound_speed_m_s == pytest.approx(V, rel=1e-6)  # elastic


@pytest.mark.parametrize("k, c", [(1.5e6, 60.0), (1.5e6, 250.0), (4e6, 400.0)])
def test_kelvin_voigt_force_based_separation(k, c):
    exact = KelvinVoigt(M, k, c, 10.0)
    b, w0 = c / (2 * M), math.sqrt(k / M)
    w = math.sqrt(w0**2 - b**2)
    t_c = (math.pi - math.atan(2 * b * w / (w0**2 - 2 * b**2))) / w  # as written in the issue
    record = simulate("kelvin_voigt", {"k": k, "c": c}, impact_speed_m_s=10.0, mass_kg=M)
    assert contact(record) == pytest.approx(t_c, rel=1e-3)
    assert record.rebound_speed_m_s / 10.0 == pytest.approx(math.exp(-b * t_c), rel=1e-3)
    assert contact(record) == pytest.approx(exact.contact_time_s, rel=1e-6)


@pytest.mark.parametrize("lam, n", [(0.005, 1.5), (0.03, 1.5), (0.08, 1.2), (0.03, 2.0)])
def test_hunt_crossley_cor_identity(lam, n):
    record = simulate("hunt_crossley", {"k": 2e7, "n": n, "lambda": lam}, impact_speed_m_s=V,
                      mass_kg=M)
    e, z = record.rebound_speed_m_s / V, lam * V
    assert z * (1 + e) == pytest.approx(math.log((1 + z) / (1 - e * z)), rel=1e-3)
    assert e == pytest.approx(hunt_crossley_cor(lam, V), rel=1e-3)


def test_simon_model_obeys_the_hunt_crossley_cor_identity():
    """Simon's law is Hunt-Crossley's with n = 3/2, so its COR obeys the same identity."""
    simon = simulate("simon", {"k": 2e7, "alpha": 0.03}, impact_speed_m_s=V, mass_kg=M)
    e, z = simon.rebound_speed_m_s / V, 0.03 * V
    assert z * (1 + e) == pytest.approx(math.log((1 + z) / (1 - e * z)), rel=1e-3)


@pytest.mark.parametrize("cor", [0.001, 0.03, 0.3, 0.55, 0.9, 0.999, 0.999999])
def test_hunt_crossley_lambda_and_cor_are_inverse(cor):
    lam = hunt_crossley_lambda(cor, V)
    z = lam * V
    if cor >= 0.1:  # below, 1 - e z rounds away and the identity cannot be evaluated directly
        assert z * (1 + cor) == pytest.approx(math.log1p(z) - math.log1p(-cor * z), rel=1e-9)
    assert hunt_crossley_cor(lam, V) == pytest.approx(cor, rel=1e-9)


@pytest.mark.parametrize("call, message", [
    (lambda: hunt_crossley_lambda(1.0, V), r"cor = 1: allowed range \(0, 0.999999\]"),
    (lambda: hunt_crossley_lambda(0.5, 0.0), "impact_speed_m_s"),
    (lambda: hunt_crossley_cor(-0.1, V), "lambda"),
])
def test_hunt_crossley_helpers_reject_bad_input(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_a_run_that_does_not_separate_keeps_its_velocity_history():
    model = MODELS["kelvin_voigt"]
    batch = model.run_batch(np.array([[1.5e6, 60.0]]), M, 10.0, 1e-6, 300)  # 0.3 of the contact
    assert not batch.separated[0] and np.isnan(batch.contact_time_s[0])
    assert np.all(np.diff(batch.velocity_m_s[0]) < 0)  # still decelerating, not overwritten


def test_hertz_model_equals_hertz_closed_form():
    e_modulus, nu, radius, v = 10e6, 0.45, 0.036, 1.0
    e_star = e_modulus / (1 - nu**2)
    delta = (15 * M * v**2 / (16 * e_star * math.sqrt(radius))) ** 0.4  # Hertz
    f_max = 4 / 3 * e_star * math.sqrt(radius) * delta**1.5
    t_c = 2.94328 * delta / v
    record = simulate("hertz", {"youngs_modulus_pa": e_modulus, "poissons_ratio": nu,
                                "radius_m": radius}, impact_speed_m_s=v, mass_kg=M)
    assert contact(record) == pytest.approx(t_c, rel=1e-3)
    assert record.force_n.max() == pytest.approx(f_max, rel=1e-3)
    assert hertz_impact(e_modulus, nu, radius, M, v) == pytest.approx((delta, f_max, t_c), rel=1e-5)
    # the rounded closed form, t_c = 2.868 (m^2 / (R E*^2 v))^(1/5)
    assert contact(record) == pytest.approx(2.868 * (M**2 / (radius * e_star**2 * v)) ** 0.2,
                                            rel=1e-3)


def test_lieberman_johnson_rigid_damper_limit():
    """A rigid damper puts spring 2 in parallel with spring 1: an elastic power-law spring.
    (The soft-damper limit is a stiff ODE that a fixed explicit step cannot follow.)"""
    params = {"k1": 1e7, "alpha": 1.3, "k2": 2e7, "beta": 1.3, "c": 1e9}
    record = simulate("lieberman_johnson", params, impact_speed_m_s=V, mass_kg=M)
    _, f_max, t_c = undamped_power_law(3e7, 1.3, M, V)
    assert contact(record) == pytest.approx(t_c, rel=1e-3)
    assert record.force_n.max() == pytest.approx(f_max, rel=1e-3)
    assert record.rebound_speed_m_s == pytest.approx(V, rel=1e-3)


def test_lieberman_johnson_dissipates_through_its_damper():
    params = {"k1": 1e7, "alpha": 1.3, "k2": 2e7, "beta": 1.3, "c": 300.0}
    record = simulate("lieberman_johnson", params, impact_speed_m_s=V, mass_kg=M)
    assert 0.2 < record.rebound_speed_m_s / V < 0.95


def test_three_element_with_proportional_units_is_the_single_element():
    single = {"k": 2e7, "alpha": 1.3, "c": 80.0}
    shares = (0.5, 0.3, 0.2)
    three = {}
    for i, share in enumerate(shares, 1):
        three.update({f"k{i}": single["k"] * share, f"alpha{i}": 1.3, f"c{i}": 80.0 * share,
                      f"m{i}": M * share})
    a = simulate("single_element", single, impact_speed_m_s=V, mass_kg=M)
    b = simulate("three_element", three, impact_speed_m_s=V, mass_kg=M)
    assert contact(b) == pytest.approx(contact(a), rel=1e-9)
    assert b.rebound_speed_m_s == pytest.approx(a.rebound_speed_m_s, rel=1e-9)
    np.testing.assert_allclose(b.force_n, a.force_n, rtol=1e-6, atol=1e-6 * a.force_n.max())


def test_batch_equals_single_runs():
    model = MODELS["single_element"]
    sets = [{"k": k, "alpha": a, "c": c} for k, a, c in
            [(2e7, 1.3, 80.0), (5e6, 1.1, 150.0), (1e8, 1.6, 40.0), (2e7, 1.3, 0.0), (3e6, 1.0, 10.0)]]
    batch = model.run_batch(np.array([parameter_vector(model, p) for p in sets]), M, V, 2e-6, 800)
    for i, params in enumerate(sets):
        single = model.run_batch(parameter_vector(model, params)[None], M, V, 2e-6, 800)
        np.testing.assert_allclose(batch.force_n[i], single.force_n[0], rtol=1e-12, atol=1e-9)
        assert batch.contact_time_s[i] == pytest.approx(single.contact_time_s[0], rel=1e-12)


def test_simulated_record_feeds_the_feature_extraction():
    exact = KelvinVoigt(M, 1.5e6, 60.0, 10.0)
    record = simulate("kelvin_voigt", {"k": 1.5e6, "c": 60.0}, impact_speed_m_s=10.0, mass_kg=M,
                      rate_hz=1e6)
    features = extract_features(record)
    assert features.values["P1"] == pytest.approx(exact.contact_time_s, rel=2e-3)
    assert features.values["P17"] == pytest.approx(exact.cor, rel=1e-6)
    assert abs(features.impulse_relative_error) < 1e-3
    assert record.velocity_m_s[0] == 10.0
    assert record.velocity_m_s[-1] == pytest.approx(-exact.cor * 10.0, rel=1e-9)


def test_kelvin_voigt_inverse_formulas_round_trip():
    exact = KelvinVoigt(M, 1.5e6, 120.0, 10.0)
    back = kelvin_voigt_from_test(exact.contact_time_s, 10.0, 10.0 * exact.cor, M)
    assert back["k"] == pytest.approx(1.5e6, rel=1e-9)
    assert back["c"] == pytest.approx(120.0, rel=1e-9)
    # thesis eq. 2-19..2-22: separation at x = 0, t_c = pi / w, with and without the b^2 term
    b, w = 120.0 / (2 * M), math.sqrt(1.5e6 / M - (120.0 / (2 * M)) ** 2)
    t_x = math.pi / w
    cor_x = math.exp(-b * t_x)
    thesis = kelvin_voigt_from_test(t_x, 10.0, 10.0 * cor_x, M, separation="displacement")
    assert thesis["k"] == pytest.approx(1.5e6, rel=1e-9)
    assert thesis["c"] == pytest.approx(120.0, rel=1e-9)
    printed = kelvin_voigt_from_test(t_x, 10.0, 10.0 * cor_x, M, separation="displacement",
                                     keep_b_squared=False)
    assert thesis["k"] - printed["k"] == pytest.approx(M * b**2, rel=1e-9)


def _sim1_literal(k, a, c, m, v, dt=2e-5, y0=0.0):
    """Appendix Sim1, line by line, scalar."""
    y1 = y0
    y2 = y1 - v * dt
    f = -math.copysign(1.0, y2 - y0) * k * abs(y2 - y0) ** a
    v = v - f / m * dt
    forces = [f]
    while y2 < y0:
        y1 = y2
        y2 = y1 - v * dt
        f1 = -math.copysign(1.0, y2 - y0) * k * abs(y2 - y0) ** a if y2 != y0 else 0.0
        f2 = -c * abs(y2 - y1) if y2 >= y1 else 0.0
        f = f1 + f2
        v = v - f / m * dt
        forces.append(f)
    offset = max(forces[0], forces[-1])
    return [x - offset for x in forces if x >= offset], v


def test_thesis_sim1_reproduction_matches_a_literal_transcription():
    table = thesis_tables()["7-1"]
    for speed in table.speeds_m_s:
        p = table.params_at(speed)
        expected, final = _sim1_literal(p["k"], p["alpha"], p["c"], M, speed)
        pulses, _, _, v = sim1([p["k"]], [p["alpha"]], [p["c"]], [M], speed)
        np.testing.assert_allclose(pulses[0], expected, rtol=1e-12, atol=1e-9)
        assert v[0] == pytest.approx(final, rel=1e-12)


def test_thesis_tables_replay_nearly_elastic():
    """Sim1's damping is c |dy| per step: with the tables' c the rebound is nearly elastic."""
    tables = thesis_tables()
    assert tables["7-1"].params["k"][3] == 1539811 and tables["7-2"].params["m3"][0] == 0.0837
    for key, mass in (("7-1", M), ("7-2", None)):
        for speed in tables[key].speeds_m_s:
            record = tables[key].simulate(speed, mass_kg=mass)
            assert record.rebound_speed_m_s / speed > 0.99
            assert 1e-3 < contact(record) < 1.8e-3


@pytest.mark.parametrize("model, params, mass, message", [
    ("single_element", {"k": 2e7, "alpha": 1.3}, M, "missing 'c'"),
    ("single_element", {"k": 2e7, "alpha": 1.3, "c": 1.0, "q": 2}, M, "unknown parameter"),
    ("single_element", {"k": -2e7, "alpha": 1.3, "c": 1.0}, M, "params.k"),
    ("single_element", {"k": 0.0, "alpha": 1.3, "c": 1.0}, M, r"params.k = 0: allowed range \(0, inf\)"),
    ("single_element", {"k": "x", "alpha": 1.3, "c": 1.0}, M,
     "params.k = 'x': expected a finite number"),
    ("hertz", {"youngs_modulus_pa": 1e7, "poissons_ratio": -1.0}, M, "params.poissons_ratio"),
    ("hunt_crossley", {"k": 2e7, "n": 9.0, "lambda": 0.0}, M, "params.n"),
    ("single_element", {"k": 2e7, "alpha": 1.3, "c": 1.0}, None, "mass_kg"),
    ("nope", {}, M, "unknown 'nope'"),
])
def test_bad_parameters_name_the_field(model, params, mass, message):
    with pytest.raises(InputError, match=message):
        simulate(model, params, impact_speed_m_s=V, mass_kg=mass)


def test_three_element_masses_must_add_up_to_the_ball_mass():
    params = {f"{n}{i}": v for i in (1, 2, 3) for n, v in (("k", 1e7), ("alpha", 1.3), ("c", 10.0))}
    params.update(m1=0.05, m2=0.05, m3=0.05)
    with pytest.raises(InputError, match="add up to 0.15"):
        simulate("three_element", params, impact_speed_m_s=V, mass_kg=M)
    assert simulate("three_element", params, impact_speed_m_s=V).mass_kg == pytest.approx(0.15)


def test_every_model_runs_and_separates():
    defaults = {
        "single_element": {"k": 2e7, "alpha": 1.3, "c": 80.0},
        "hunt_crossley": {"k": 2e7, "n": 1.5, "lambda": 0.03},
        "kelvin_voigt": {"k": 1.5e6, "c": 60.0},
        "hertz": {"youngs_modulus_pa": 1e7},
        "lieberman_johnson": {"k1": 1e7, "alpha": 1.3, "k2": 2e7, "beta": 1.3, "c": 300.0},
        "simon": {"k": 2e7, "alpha": 0.03},
        "single_element_thesis": {"k": 2e6, "alpha": 1.1, "c": 500.0},
    }
    three = {f"{n}{i}": v for i in (1, 2, 3) for n, v in (("k", 1e7), ("alpha", 1.3), ("c", 30.0))}
    defaults["three_element"] = {**three, "m1": 0.05, "m2": 0.05, "m3": 0.06}
    defaults["three_element_thesis"] = {**three, "m1": 0.05, "m2": 0.05, "m3": 0.06}
    assert set(defaults) == set(MODELS)
    for name, params in defaults.items():
        result = run_one(MODELS[name], params, M, V)
        assert result.separated[0] and 0 < result.rebound_speed_m_s[0] <= V * (1 + 1e-9), name
