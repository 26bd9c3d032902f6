"""Prony-series fits of relaxation, creep and DMA data (material/viscoelastic.py): recovery of
known series from noisy synthetic tests, the creep interconversion against an independent
numerical solution of the Volterra equation, time-temperature shifting (WLF, Arrhenius), the
standard errors against the scatter of repeated fits, merging into a material, and bad input."""

import json
import math

import numpy as np
import pytest

from ballimpact.errors import InputError, InputWarning
from ballimpact.material import viscoelastic as ve

TWO_TERMS = [{"g": 0.4, "tau_s": 1e-3}, {"g": 0.3, "tau_s": 1e-1}]
DMA_TERMS = [{"g": 0.3, "tau_s": 1e-4}, {"g": 0.3, "tau_s": 1e-2}, {"g": 0.2, "tau_s": 1.0}]
DMA_E0_PA = 1e7
WLF = {"c1": 8.86, "c2_k": 101.6}
EA_J_MOL = 150e3
TEMPERATURES_C = (0.0, 20.0, 40.0)


def noisy(values, fraction, seed):
    return values * (1.0 + fraction * np.random.default_rng(seed).standard_normal(values.shape))


# ---- forward functions -----------------------------------------------------------------------

def test_relaxation_ratio_agrees_with_the_solver_relaxation_function():
    import jax

    from ballimpact.constitutive.viscoelastic import relaxation_function

    rng = np.random.default_rng(5)
    g = rng.uniform(0.0, 0.3, 3)
    tau = 10.0 ** rng.uniform(-5, 0, 3)
    t = np.concatenate([[0.0], np.logspace(-7, 2, 50)])
    ours = ve.relaxation_ratio([{"g": a, "tau_s": b} for a, b in zip(g, tau)], t)
    with jax.enable_x64(True):  # float64 as the solver runs it
        theirs = np.asarray(relaxation_function(t, g, tau))
    assert np.max(np.abs(ours - theirs)) < 1e-14


def test_one_term_interconversion_matches_the_closed_form():
    # one term: J/J0 = 1 + g/(1-g) (1 - exp(-t (1-g) / tau)), from s G^ s J^ = 1 by hand
    g, tau = 0.6, 2e-3
    j, retard = ve.retardation_spectrum([g], [tau])
    assert j[0] == pytest.approx(g / (1 - g), rel=1e-13)
    assert retard[0] == pytest.approx(tau / (1 - g), rel=1e-13)


def test_interconversion_round_trip_and_long_time_limit():
    g, tau = np.array([0.1, 0.35, 0.25, 0.2]), np.array([1e-5, 3e-4, 2e-2, 5.0])
    j, retard = ve.retardation_spectrum(g, tau)
    # J(inf)/J(0) = G(0)/G(inf) = 1/(1 - sum g)
    assert j.sum() == pytest.approx(1.0 / (1.0 - g.sum()) - 1.0, rel=1e-12)
    # retardation times interlace with, and are longer than, the relaxation times
    assert np.all(retard > tau) and np.all(retard[:-1] < tau[1:])
    g_back, tau_back = ve.relaxation_spectrum(j, retard)
    assert np.max(np.abs(g_back - g)) < 1e-12
    assert np.max(np.abs(tau_back / tau - 1)) < 1e-12


def volterra_trapezoid(g, tau, t_end, h):
    """J(t)/J(0) from J(t) G(0) + int_0^t J(t - s) G'(s) ds = 1 (G(0) = 1), trapezoidal rule on a
    uniform grid: independent of the Laplace-domain interconversion. Error O(h^2)."""
    steps = int(round(t_end / h))
    t = h * np.arange(steps + 1)
    dg = -np.sum(g / tau * np.exp(-t[:, None] / tau), axis=1)  # G'(t)
    j = np.empty(steps + 1)
    j[0] = 1.0
    for n in range(1, steps + 1):
        history = j[n - 1:0:-1] @ dg[1:n]  # sum_{m=1}^{n-1} J_{n-m} G'_m
        j[n] = (1.0 - h * (history + 0.5 * j[0] * dg[n])) / (1.0 + 0.5 * h * dg[0])
    return t, j


def test_creep_ratio_solves_the_volterra_equation():
    g, tau = np.array([0.4, 0.3]), np.array([1e-2, 1e-1])
    t, j_numeric = volterra_trapezoid(g, tau, t_end=1.5, h=1e-4)
    j_exact = ve.creep_ratio([{"g": a, "tau_s": b} for a, b in zip(g, tau)], t)
    # trapezoid error O(h^2): measured 3.7e-5 at h = 1e-4 s and 1.5e-4 at 2e-4 s
    assert np.max(np.abs(j_exact - j_numeric)) < 1e-4
    assert j_exact[-1] == pytest.approx(1 / 0.3, rel=1e-3)  # near J(inf)/J(0) = 1/(1 - sum g)


def test_dma_moduli_limits():
    # w -> inf: E' -> E0, E'' -> 0; w -> 0: E' -> E0 (1 - sum g); one term: E'' peaks at w tau = 1
    # with E0 g / 2
    storage, loss = ve.dma_moduli(DMA_TERMS, DMA_E0_PA, np.array([1e-9, 1e12]))
    assert storage[0] == pytest.approx(DMA_E0_PA * 0.2, rel=1e-6)
    assert storage[1] == pytest.approx(DMA_E0_PA, rel=1e-6)
    assert loss[0] / DMA_E0_PA < 1e-6 and loss[1] / DMA_E0_PA < 1e-6
    _, peak = ve.dma_moduli([{"g": 0.5, "tau_s": 0.01}], 1.0, np.array([1 / (2 * np.pi * 0.01)]))
    assert peak[0] == pytest.approx(0.25, rel=1e-14)


# ---- relaxation and creep fits ---------------------------------------------------------------

def test_two_term_relaxation_recovered_from_noisy_data():
    t = np.logspace(-5, 1, 60)
    data = noisy(ve.relaxation_ratio(TWO_TERMS, t), 0.003, seed=11)
    fit = ve.fit_relaxation(t, data, 2)
    dense = np.logspace(-5, 1, 600)
    error = np.max(np.abs(ve.relaxation_ratio(fit.terms, dense)
                          - ve.relaxation_ratio(TWO_TERMS, dense)))
    assert error < 0.01
    for got, want in zip(fit.terms, TWO_TERMS):
        assert abs(got["g"] - want["g"]) < 0.02
        assert got["tau_s"] == pytest.approx(want["tau_s"], rel=0.05)
        assert got["k"] == 0.0
    assert fit.r2 > 0.999 and fit.notes == ()
    assert fit.instantaneous_modulus_pa is None and fit.shift is None
    json.dumps(fit.to_dict(), allow_nan=False)


def test_relaxation_standard_errors_match_the_scatter_of_repeated_fits():
    t = np.logspace(-5, 1, 60)
    clean = ve.relaxation_ratio(TWO_TERMS, t)
    # additive noise: the fit's residuals are in ratio units, and the linearised errors assume
    # one noise level for all points (with noise proportional to the ratio they come out ~1.4x
    # the scatter, from the early, noisier points)
    fits = [ve.fit_relaxation(t, clean + 0.003 * np.random.default_rng(100 + k).standard_normal(
        t.size), 2) for k in range(40)]
    g = np.array([[term["g"] for term in f.terms] for f in fits])
    reported = np.mean([f.standard_errors["g"] for f in fits], axis=0)
    # 40 samples: the sample deviation is within ~25% of the true one (2 sigma)
    ratio = g.std(axis=0, ddof=1) / reported
    assert np.all((ratio > 0.7) & (ratio < 1.4)), ratio


def test_creep_fit_gives_back_the_relaxation_function():
    t = np.logspace(-5, 2, 70)
    data = noisy(ve.creep_ratio(TWO_TERMS, t), 0.003, seed=12)
    fit = ve.fit_creep(t, data, 2)
    dense = np.logspace(-5, 2, 600)
    error = np.max(np.abs(ve.relaxation_ratio(fit.terms, dense)
                          - ve.relaxation_ratio(TWO_TERMS, dense)))
    assert error < 0.01
    assert fit.test == "creep" and fit.sum_g < 1.0


def test_fits_are_deterministic_for_a_seed():
    t = np.logspace(-4, 1, 40)
    data = noisy(ve.relaxation_ratio(TWO_TERMS, t), 0.01, seed=3)
    assert ve.fit_relaxation(t, data, 3, seed=7).to_dict() == \
        ve.fit_relaxation(t, data, 3, seed=7).to_dict()


def test_sum_of_g_stays_below_one_for_a_fully_relaxing_test():
    t = np.logspace(-4, 2, 50)
    data = np.maximum(np.exp(-t / 1e-2), 1e-6)  # relaxes to (almost) nothing
    for terms in (1, 3):
        fit = ve.fit_relaxation(t, data, terms)
        assert fit.sum_g <= ve.SUM_G_MAX + 1e-15 and fit.sum_g > 0.99
        ve.merge_prony({"model": "neo_hookean", "c10_pa": 1e6}, fit.prony)


# ---- DMA with time-temperature shifting -------------------------------------------------------

def dma_data(log_shift, noise=0.003, seed=21):
    f = np.tile(np.logspace(-1, 2, 20), 3)
    temperature = np.repeat(TEMPERATURES_C, 20)
    storage, loss = ve.dma_moduli(DMA_TERMS, DMA_E0_PA, f * 10.0 ** log_shift(temperature))
    return f, noisy(storage, noise, seed), noisy(loss, noise, seed + 1), temperature


def assert_master_curve(fit, tolerance=0.01):
    reduced = np.logspace(-2.5, 4.5, 300)  # the reduced range the shifted data cover (Hz)
    s0, l0 = ve.dma_moduli(DMA_TERMS, DMA_E0_PA, reduced)
    s1, l1 = ve.dma_moduli(fit.terms, fit.instantaneous_modulus_pa, reduced)
    assert np.max(np.abs(s1 / s0 - 1)) < tolerance
    assert np.max(np.abs(l1 / l0 - 1)) < tolerance


def test_dma_wlf_shift_and_master_curve_recovered():
    f, storage, loss, temperature = dma_data(
        lambda t: ve.wlf_log10_shift(t, WLF["c1"], WLF["c2_k"], 20.0))
    fit = ve.fit_dma(f, storage, loss, 3, temperature_c=temperature, shift="wlf")
    assert fit.shift["model"] == "wlf" and fit.shift["reference_c"] == 20.0  # the median
    assert fit.shift["c1"] == pytest.approx(WLF["c1"], rel=0.05)
    assert fit.shift["c2_k"] == pytest.approx(WLF["c2_k"], rel=0.05)
    truth = ve.wlf_log10_shift(np.array(TEMPERATURES_C), WLF["c1"], WLF["c2_k"], 20.0)
    got = [level["log10_a_t"] for level in fit.shift["log10_a_t"]]
    assert np.max(np.abs(np.array(got) - truth)) < 0.02  # decades
    assert fit.instantaneous_modulus_pa == pytest.approx(DMA_E0_PA, rel=0.01)
    assert_master_curve(fit)
    assert set(fit.standard_errors) == {"g", "tau_s", "instantaneous_modulus_pa", "c1", "c2_k"}
    json.dumps(fit.to_dict(), allow_nan=False)


def test_dma_point_order_does_not_matter():
    f, storage, loss, temperature = dma_data(
        lambda t: ve.wlf_log10_shift(t, WLF["c1"], WLF["c2_k"], 20.0))
    order = np.random.default_rng(4).permutation(f.size)
    a = ve.fit_dma(f, storage, loss, 3, temperature_c=temperature)
    b = ve.fit_dma(f[order], storage[order], loss[order], 3, temperature_c=temperature[order])
    assert b.shift["c1"] == pytest.approx(a.shift["c1"], rel=1e-6)
    assert b.shift["c2_k"] == pytest.approx(a.shift["c2_k"], rel=1e-6)


def test_dma_arrhenius_shift_and_master_curve_recovered():
    f, storage, loss, temperature = dma_data(
        lambda t: ve.arrhenius_log10_shift(t, EA_J_MOL, 20.0))
    fit = ve.fit_dma(f, storage, loss, 3, temperature_c=temperature, shift="arrhenius")
    assert fit.shift["activation_energy_j_mol"] == pytest.approx(EA_J_MOL, rel=0.05)
    assert_master_curve(fit)


def test_dma_reference_temperature_moves_the_wlf_constants_as_wlf_says():
    # WLF at another reference Tr' = 0 C: C1' = C1 C2 / (C2 + Tr' - Tr), C2' = C2 + Tr' - Tr
    f, storage, loss, temperature = dma_data(
        lambda t: ve.wlf_log10_shift(t, WLF["c1"], WLF["c2_k"], 20.0), noise=0.0)
    fit = ve.fit_dma(f, storage, loss, 3, temperature_c=temperature, reference_c=0.0)
    c2 = WLF["c2_k"] - 20.0
    assert fit.shift["c2_k"] == pytest.approx(c2, rel=1e-4)
    assert fit.shift["c1"] == pytest.approx(WLF["c1"] * WLF["c2_k"] / c2, rel=1e-4)


def test_dma_at_one_temperature_needs_no_shift():
    f = np.logspace(-1, 3, 30)
    storage, loss = ve.dma_moduli([{"g": 0.5, "tau_s": 1e-2}], 5e6, f)
    fit = ve.fit_dma(f, noisy(storage, 0.003, 1), noisy(loss, 0.003, 2), 1)
    assert fit.shift is None
    assert fit.instantaneous_modulus_pa == pytest.approx(5e6, rel=0.01)
    assert fit.terms[0]["g"] == pytest.approx(0.5, abs=0.01)
    assert fit.terms[0]["tau_s"] == pytest.approx(1e-2, rel=0.02)
    assert fit.to_dict()["long_term_modulus_pa"] == pytest.approx(2.5e6, rel=0.02)


# ---- into a material ---------------------------------------------------------------------------

def test_merge_prony_loads_and_keeps_long_term_constants():
    from ballimpact.constitutive import material_from_dict

    material = {"model": "mooney_rivlin", "c10_pa": 1.5e6, "c01_pa": 0.5e6}
    merged = ve.merge_prony(material, TWO_TERMS)
    assert "prony" not in material  # the input is not changed
    loaded = material_from_dict(merged)
    assert [(t.g, t.k, t.tau_s) for t in loaded.prony] == [(0.4, 0.0, 1e-3), (0.3, 0.0, 1e-1)]
    assert loaded.c10_pa == 1.5e6 and loaded.moduli == "long_term"
    # long-term constants: the instantaneous shear modulus is 2 (C10 + C01) / (1 - sum g)
    assert loaded.shear_modulus_pa() == pytest.approx(4e6 / 0.3, rel=1e-12)
    bulk = material_from_dict(ve.merge_prony(material, TWO_TERMS, bulk=True))
    assert [t.k for t in bulk.prony] == [0.4, 0.3]


def test_merge_prony_errors_name_the_key():
    foam = {"model": "ogden_hyperfoam", "terms": [{"mu_pa": 1e5, "alpha": 4.0, "nu": 0.1}]}
    ve.merge_prony(foam, TWO_TERMS)  # g only: loads
    with pytest.raises(InputError, match="prony.k"):
        ve.merge_prony(foam, TWO_TERMS, bulk=True)  # hyperfoam relaxes its whole stress with g
    with pytest.raises(InputError, match=r"core\.prony: sum of g"):
        ve.merge_prony({"model": "neo_hookean", "c10_pa": 1e6},
                       [{"g": 0.6, "tau_s": 1.0}, {"g": 0.5, "tau_s": 2.0}], where="core")


# ---- bad input ---------------------------------------------------------------------------------

T20 = np.logspace(-3, 1, 20)
R20 = ve.relaxation_ratio(TWO_TERMS, T20)


@pytest.mark.parametrize("call, fragments", [
    (lambda: ve.fit_relaxation(T20, R20, 0), ("terms = 0: allowed range [1, 10]",)),
    (lambda: ve.fit_relaxation(T20, R20, 11), ("terms = 11: allowed range [1, 10]",)),
    (lambda: ve.fit_relaxation(T20, R20, 2.5), ("terms = 2.5: expected an integer in [1, 10]",)),
    (lambda: ve.fit_relaxation(T20[:6], R20[:6], 3), ("6 points", "more than 2 x terms = 6")),
    (lambda: ve.fit_relaxation(T20, R20 * 2e6, 2), ("ratio[0]", "(0, 1.05]", "not the modulus")),
    (lambda: ve.fit_relaxation(T20, -R20, 2), ("ratio[0]",)),
    (lambda: ve.fit_relaxation(-T20, R20, 2), ("time_s[0]",)),
    (lambda: ve.fit_relaxation(T20, R20[:-1], 2), ("ratio", "19 values", "expected 20")),
    (lambda: ve.fit_relaxation(np.r_[T20[:-1], np.nan], R20, 2), ("time_s[19]", "finite")),
    (lambda: ve.fit_creep(T20, R20, 2), ("ratio", "J(t)/J(0)")),
    (lambda: ve.fit_dma(T20, R20, R20, 2, shift="vft"), ("shift", "wlf", "arrhenius")),
    (lambda: ve.fit_dma(T20, R20, -R20, 2), ("loss_pa[0]",)),
    (lambda: ve.fit_dma(-T20, R20, R20, 2), ("frequency_hz[0]",)),
    (lambda: ve.fit_dma(T20, R20, R20, 2, temperature_c=np.full(20, -300.0)), ("temperature_c",)),
])
def test_bad_input_is_one_line_naming_the_field(call, fragments):
    with pytest.raises(InputError) as info:
        call()
    message = str(info.value)
    assert "\n" not in message
    for fragment in fragments:
        assert fragment in message, (fragment, message)


def test_short_span_with_several_terms_warns():
    t = np.linspace(0.1, 0.5, 30)
    with pytest.warns(InputWarning, match="under one"):
        ve.fit_relaxation(t, ve.relaxation_ratio(TWO_TERMS, t), 2)


def test_standard_errors_are_json_safe_when_infinite():
    fit = ve.PronyFit(terms=({"g": 0.1, "k": 0.0, "tau_s": 1.0},), r2=math.nan,
                      standard_errors={"g": (math.inf,), "tau_s": (1.0,)})
    out = fit.to_dict()
    assert out["standard_errors"]["g"] == [None] and out["r2"] is None
    json.dumps(out, allow_nan=False)
