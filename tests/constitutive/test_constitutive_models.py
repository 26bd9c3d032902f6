"""Material point tests (docs/fe.md "Verification"): uniaxial stress of Mooney-Rivlin and Ogden
hyperfoam against closed forms (1e-6), stress relaxation after a step stretch against g_R(t)
(1e-3), and the long_term / instantaneous conventions (exactly 1 - sum g)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.optimize import brentq

from ballimpact.errors import InputError
from ballimpact.constitutive import (
    MaterialConstants,
    MooneyRivlin,
    OgdenHyperfoam,
    Sym,
    material_from_dict,
    prony_update,
    relaxation_function,
    stress_parts,
)

STRETCHES = [0.55, 0.7, 0.9, 1.0, 1.1, 1.4, 1.8]


def _principal_stress(material, stretches):
    """Nominal (first Piola-Kirchhoff) principal stresses P_i = lambda_i S_ii (Pa), by autodiff."""
    s_dev, s_vol = _stress(material, stretches)
    return np.asarray(stretches) * (s_dev[:3] + s_vol[:3])


def _diagonal(stretches):
    return Sym(*(jnp.asarray(s) ** 2 for s in stretches), jnp.asarray(0.0))


def _stress(material, stretches):
    """(S_relaxing, S_volumetric) as arrays (S_xx, S_yy, S_zz, S_xy) at principal stretches."""
    with jax.enable_x64(True):
        consts = jax.tree_util.tree_map(jnp.asarray, material.hyperelastic_constants())
        s_dev, s_vol = stress_parts(material.energy, _diagonal(stretches), consts)
        return np.array(s_dev, dtype=float), np.array(s_vol, dtype=float)


def _mooney_rivlin_nominal(c10, c01, k, l1, l2):
    """Closed form for principal stretches (l1, l2, l2): nominal stresses (P1, P2)."""
    J = l1 * l2 * l2
    i1 = l1 ** 2 + 2 * l2 ** 2
    i2 = 2 * l1 ** 2 * l2 ** 2 + l2 ** 4
    a, b = J ** (-2 / 3), J ** (-4 / 3)
    p = k * (J - 1)  # pressure part: Cauchy stress k (J - 1)
    out = []
    for li in (l1, l2):
        # Cauchy: sigma_i = (2/J) [C10 a (l_i^2 - I1/3) + C01 b (I1 l_i^2 - l_i^4 - 2 I2 / 3)] + p
        sigma = 2 / J * (c10 * a * (li ** 2 - i1 / 3) + c01 * b * (i1 * li ** 2 - li ** 4 - 2 * i2 / 3)) + p
        out.append(sigma * J / li)
    return out


@pytest.mark.parametrize("d1", [0.0, 1e-8])
def test_mooney_rivlin_uniaxial_stress_matches_closed_form(d1):
    mat = MooneyRivlin(c10_pa=4.72e6, c01_pa=-0.45e6, d1_per_pa=d1)
    k = mat.hyperelastic_constants().k_pa
    for l1 in STRETCHES:
        # lateral stretch of uniaxial stress from the closed form, then compare both stresses
        l2 = brentq(lambda x, l1=l1: _mooney_rivlin_nominal(4.72e6, -0.45e6, k, l1, x)[1], 0.3, 3.0,
                    xtol=1e-15, rtol=1e-15)
        p1, _ = _mooney_rivlin_nominal(4.72e6, -0.45e6, k, l1, l2)
        got = _principal_stress(mat, [l1, l2, l2])
        scale = max(abs(p1), 1e3)
        assert got[0] == pytest.approx(p1, rel=1e-6, abs=1e-6 * scale)
        assert abs(got[1]) < 1e-6 * scale


def test_mooney_rivlin_incompressible_limit():
    """With a very stiff bulk, the uniaxial nominal stress tends to 2 (l - l^-2)(C10 + C01 / l)."""
    c10, c01 = 4.5e6, -0.5e6
    mat = MooneyRivlin(c10_pa=c10, c01_pa=c01, d1_per_pa=2.0 / (1e7 * 2 * (c10 + c01)))
    k = mat.hyperelastic_constants().k_pa
    for l1 in STRETCHES:
        l2 = brentq(lambda x, l1=l1: _mooney_rivlin_nominal(c10, c01, k, l1, x)[1], 0.3, 3.0, xtol=1e-15)
        got = _principal_stress(mat, [l1, l2, l2])[0]
        expected = 2 * (l1 - l1 ** -2) * (c10 + c01 / l1)
        assert got == pytest.approx(expected, rel=1e-5, abs=1.0)


@pytest.mark.parametrize("terms", [
    [{"mu_pa": 70.3e6, "alpha": 4.0, "nu": 0.0}],
    [{"mu_pa": 1.2e6, "alpha": 6.5, "nu": 0.2}, {"mu_pa": -0.3e6, "alpha": -2.0, "beta": 0.1}],
])
def test_hyperfoam_uniaxial_stress_matches_closed_form(terms):
    mat = material_from_dict({"model": "ogden_hyperfoam", "terms": terms})

    def nominal(l1, l2):
        # Cauchy sigma_i = (2/J) sum mu_k / a_k (l_i^a_k - J^(-a_k b_k)); nominal P_i = sigma_i J / l_i
        J = l1 * l2 * l2
        out = []
        for li in (l1, l2):
            s = sum(2 * t.mu_pa / t.alpha * (li ** t.alpha - J ** (-t.alpha * t.beta)) for t in mat.terms)
            out.append(s / li)
        return out

    for l1 in STRETCHES:
        l2 = brentq(lambda x, l1=l1: nominal(l1, x)[1], 0.2, 5.0, xtol=1e-15, rtol=1e-15)
        p1, _ = nominal(l1, l2)
        got = _principal_stress(mat, [l1, l2, l2])
        scale = max(abs(p1), 1e3)
        assert got[0] == pytest.approx(p1, rel=1e-6, abs=1e-6 * scale)
        assert abs(got[1]) < 1e-6 * scale
    if terms[0]["nu"] == 0.0:  # nu = 0: no lateral contraction, P = (2 mu / a)(l^a - 1) / l
        for l1 in STRETCHES:
            expected = 2 * 70.3e6 / 4.0 * (l1 ** 4 - 1) / l1
            assert _principal_stress(mat, [l1, 1.0, 1.0])[0] == pytest.approx(expected, rel=1e-9,
                                                                                abs=1e-3)


def test_hyperfoam_tangent_is_finite_at_equal_stretches():
    mat = OgdenHyperfoam(terms=material_from_dict(
        {"model": "ogden_hyperfoam", "terms": [{"mu_pa": 70.3e6, "alpha": 4.0, "nu": 0.0}]}).terms)
    with jax.enable_x64(True):
        consts = jax.tree_util.tree_map(jnp.asarray, mat.hyperelastic_constants())

        def stress(c):
            return jnp.stack(stress_parts(mat.energy, Sym(*c), consts)[0])

        for c in ((1.0, 1.0, 1.0, 0.0), (0.8, 0.8, 1.1, 0.0)):
            tangent = jax.jacfwd(stress)(tuple(jnp.asarray(x) for x in c))
            assert np.all(np.isfinite(np.asarray(tangent)))
        # small-strain modulus: dS11/dE11 = E0 = 2 mu0 (1 + nu) for nu = 0
        tangent = jax.jacfwd(stress)(tuple(jnp.asarray(x) for x in (1.0, 1.0, 1.0, 0.0)))
        assert float(tangent[0][0]) * 2 == pytest.approx(2 * 70.3e6, rel=1e-9)


@pytest.mark.parametrize("model", [
    {"model": "mooney_rivlin", "c10_pa": 4.72e6, "c01_pa": -0.45e6, "d1_per_pa": 0.0},
    {"model": "neo_hookean", "c10_pa": 2e6},
    {"model": "linear_elastic", "youngs_modulus_pa": 10e6, "poissons_ratio": 0.45},
    {"model": "ogden_hyperfoam", "terms": [{"mu_pa": 70.3e6, "alpha": 4.0, "nu": 0.0}]},
])
def test_relaxation_after_step_stretch_follows_g_r(model):
    prony = [{"g": 0.41, "k": 0.0, "tau_s": 7e-5}, {"g": 0.2, "k": 0.0, "tau_s": 1e-3}]
    mat = material_from_dict({**model, "prony": prony})
    with jax.enable_x64(True):
        consts = jax.tree_util.tree_map(jnp.asarray, mat.hyperelastic_constants())
        s_dev = jnp.stack(stress_parts(mat.energy, _diagonal([0.7, 1.1, 1.2]), consts)[0])
        zero = jnp.zeros_like(s_dev)
        g, tau = mat.constants().prony_g, mat.constants().prony_tau_s
        q = prony_update(jnp.zeros((2, 4)), zero, s_dev, g, tau, 1e-12)  # the step
        t, times, relaxing = 1e-12, [], []
        for dt in np.full(60, 5e-5):
            q = prony_update(q, s_dev, s_dev, g, tau, dt)
            t += dt
            times.append(t)
            relaxing.append(np.asarray(s_dev - q.sum(0))[0])
        expected = np.asarray(relaxation_function(np.array(times), g, tau)) * float(s_dev[0])
    np.testing.assert_allclose(relaxing, expected, rtol=1e-3)
    assert abs(relaxing[-1]) < 0.5 * abs(float(s_dev[0]))  # it did relax: g_R(3 ms) = 0.39


def test_prony_update_is_exact_for_a_linear_ramp():
    """dQ/dt = (g S0(t) - Q)/tau with S0 = t: Q(t) = g [t - tau (1 - exp(-t/tau))]."""
    with jax.enable_x64(True):
        g, tau = jnp.array([0.6]), jnp.array([2e-4])
        q, t = jnp.zeros((1,)), 0.0
        for dt in (1e-5, 7e-5, 3e-4, 1e-6):
            q = prony_update(q, jnp.array(t), jnp.array(t + dt), g, tau, dt)
            t += dt
        assert float(q[0]) == pytest.approx(0.6 * (t - 2e-4 * (1 - np.exp(-t / 2e-4))), rel=1e-12)


@pytest.mark.parametrize("model", [
    {"model": "mooney_rivlin", "c10_pa": 4.02e6, "c01_pa": -0.41e6},
    {"model": "linear_elastic", "youngs_modulus_pa": 10e6, "poissons_ratio": 0.45},
    {"model": "ogden_hyperfoam", "terms": [{"mu_pa": 70.3e6, "alpha": 4.0, "nu": 0.1}]},
])
def test_long_term_and_instantaneous_differ_by_one_minus_sum_g(model):
    prony = [{"g": 0.5, "k": 0.0, "tau_s": 1e-4}, {"g": 0.29, "k": 0.0, "tau_s": 1e-3}]
    long_term = material_from_dict({**model, "prony": prony, "moduli": "long_term"})
    instant = material_from_dict({**model, "prony": prony, "moduli": "instantaneous"})
    factor = 1.0 - 0.79
    for stretches in ([0.7, 1.05, 1.05], [1.3, 0.9, 0.95]):
        p_long = _principal_stress(long_term, stretches)
        p_inst = _principal_stress(instant, stretches)
        if model["model"] == "ogden_hyperfoam":  # the whole stress relaxes
            np.testing.assert_allclose(p_inst, p_long * factor, rtol=1e-12)
        else:  # only the deviatoric part; compare the relaxing parts
            d_long, d_inst = _stress(long_term, stretches)[0], _stress(instant, stretches)[0]
            np.testing.assert_allclose(d_inst, d_long * factor, rtol=1e-12, atol=1e-9)
    assert instant.shear_modulus_pa() == pytest.approx(long_term.shear_modulus_pa() * factor,
                                                       rel=1e-12)


def test_mooney_rivlin_d1_zero_means_bulk_twenty_shear():
    mat = MooneyRivlin(c10_pa=4.02e6, c01_pa=-0.41e6)
    assert mat.bulk_modulus_pa() == pytest.approx(20 * 2 * (4.02e6 - 0.41e6))


@pytest.mark.parametrize("spec, key", [
    ({"model": "mooney_rivlin", "c10_pa": 1e6}, "c01_pa"),
    ({"model": "mooney_rivlin", "c10_pa": 1e6, "c01_pa": 0.0, "c20_pa": 1.0}, "c20_pa"),
    ({"model": "mooney_rivlin", "c10_pa": 1e6, "c01_pa": 0.0, "moduli": "short"}, "moduli"),
    ({"model": "linear_elastic", "youngs_modulus_pa": 1e6, "poissons_ratio": 0.5}, "poissons_ratio"),
    ({"model": "neo_hookean", "c10_pa": 1e6, "prony": [{"g": 1.2, "tau_s": 1e-4}]}, "g"),
    ({"model": "neo_hookean", "c10_pa": 1e6, "prony": [{"g": 0.2, "tau_s": 0.0}]}, "tau_s"),
    ({"model": "ogden_hyperfoam", "terms": [{"mu_pa": 1e6, "alpha": 2.0}]}, "nu"),
    ({"model": "ogden_hyperfoam", "terms": [{"mu_pa": 1e6, "alpha": 2.0, "nu": 0.0}],
      "prony": [{"g": 0.2, "k": 0.1, "tau_s": 1e-4}]}, "k"),
    ({"model": "rubber"}, "model"),
])
def test_bad_material_names_the_key(spec, key):
    with pytest.raises(InputError, match=key):
        material_from_dict(spec)


def test_d1_zero_bulk_is_twenty_instantaneous_shear_in_both_conventions():
    prony = [{"g": 0.79, "k": 0.0, "tau_s": 8e-5}]
    for moduli in ("long_term", "instantaneous"):
        mat = material_from_dict({"model": "mooney_rivlin", "c10_pa": 4.02e6, "c01_pa": -0.41e6,
                                  "prony": prony, "moduli": moduli})
        assert mat.bulk_modulus_pa() == pytest.approx(20 * mat.shear_modulus_pa(), rel=1e-12)


def test_material_errors_carry_the_key_path():
    with pytest.raises(InputError, match=r"ball.layers\[1\].material: .*c10_pa \+ c01_pa"):
        material_from_dict({"model": "mooney_rivlin", "c10_pa": 1e6, "c01_pa": -2e6},
                           where="ball.layers[1].material")


@pytest.mark.parametrize("spec", [
    {"model": "linear_elastic", "youngs_modulus_pa": 1e8, "poissons_ratio": 0.4},
    {"model": "neo_hookean", "c10_pa": 2e6},
    {"model": "mooney_rivlin", "c10_pa": 4.72e6, "c01_pa": -0.45e6},
    {"model": "yeoh", "c10_pa": 3e6, "c20_pa": -1e5, "c30_pa": 1e4},
    {"model": "ogden", "terms": [{"mu_pa": 4e6, "alpha": 2.0}, {"mu_pa": 2e6, "alpha": -1.5}]},
    {"model": "ogden_hyperfoam", "terms": [{"mu_pa": 2e6, "alpha": 8.0, "nu": 0.1}]},
])
def test_constants_are_typed_and_travel_in_kept_programs(spec):
    """Every model's constants are a `MaterialConstants` whose `hyperelastic` is the model's own
    NamedTuple, fields in alphabetical order (they flatten as the dicts they replaced did), and
    they pass through a serialized `jax.export` program (the FE programs kept on disk)."""
    material = material_from_dict({**spec, "prony": [{"g": 0.3, "k": 0.0, "tau_s": 1e-4}]})
    constants = material.constants()
    assert isinstance(constants, MaterialConstants)
    assert isinstance(constants.hyperelastic, type(material).Constants)
    for typed in (constants, constants.hyperelastic):
        assert list(typed._fields) == sorted(typed._fields)
    flat = constants.flat()
    assert set(flat) == set(constants.hyperelastic._fields) | set(constants._fields) - {
        "hyperelastic"}
    assert flat["shear_modulus_pa"] == pytest.approx(material.shear_modulus_pa(), rel=1e-15)

    def stress(c, components):
        s_dev, s_vol = stress_parts(type(material).energy, Sym(*components), c.hyperelastic)
        return jnp.stack(s_dev) + jnp.stack(s_vol)

    with jax.enable_x64(True):
        components = tuple(_diagonal([0.8, 1.1, 1.2]))[:4]  # yz, zx left out: the 2D path
        args = (jax.tree_util.tree_map(jnp.asarray, constants), components)
        kept = jax.export.deserialize(jax.export.export(jax.jit(stress))(*args).serialize())
        assert np.array_equal(np.asarray(kept.call(*args)), np.asarray(jax.jit(stress)(*args)))
