"""Yeoh and Ogden (rubber) materials: material-point stresses against closed forms written here
(1e-10 relative), the small-strain shear modulus, objectivity of the 3D (eigenvalue) path,
the neo-Hookean special cases, input checks, and short impacts in both solvers (the 3D one slow)."""

import json
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ballimpact.errors import InputError
from ballimpact.fe import load_ball, simulate
from ballimpact.constitutive import NeoHookean, Sym, Yeoh, energy_and_stress, material_from_dict
from ballimpact.fe import SolverOptions

YEOH = {"model": "yeoh", "c10_pa": 1.1e6, "c20_pa": -4.0e4, "c30_pa": 1.5e3}
OGDEN = {"model": "ogden", "terms": [{"mu_pa": 1.6e6, "alpha": 2.6}, {"mu_pa": 2.0e3, "alpha": 6.0},
                                     {"mu_pa": -3.0e4, "alpha": -2.0}]}
STRETCHES = [0.45, 0.7, 0.93, 1.08, 1.5, 2.4, 3.2]


def _constants(material):
    return jax.tree_util.tree_map(jnp.asarray, material.hyperelastic_constants())


def _deviatoric_stress(material, stretches):
    """S_i = 2 dW_dev / dC_ii (Pa) at C = diag(l1^2, l2^2, l3^2), by autodiff of the energy."""
    with jax.enable_x64(True):
        C = Sym(*(jnp.asarray(float(x) ** 2) for x in stretches), jnp.asarray(0.0))
        (_, s_dev), _ = energy_and_stress(type(material).energy, C, _constants(material))
        return np.array([float(s) for s in s_dev[:3]])


def _nominal_from_energy(material, mode, lam):
    """Nominal stress P1 of an incompressible mode, the pressure eliminated by the stress-free
    direction: sigma_i = l_i^2 S_i - p (J = 1), p from sigma_3 = 0 (sigma_2 = 0 in uniaxial)."""
    l2 = {"uniaxial": lam ** -0.5, "equibiaxial": lam, "planar": 1.0}[mode]
    l3 = 1.0 / (lam * l2)
    s = _deviatoric_stress(material, (lam, l2, l3))
    free = 1 if mode == "uniaxial" else 2
    p = (l2, l3)[free - 1] ** 2 * s[free]
    return (lam ** 2 * s[0] - p) / lam


def _yeoh_nominal(c10, c20, c30, mode, lam):
    """Closed forms: P = 2 (l - l^-2) W1 (uniaxial, I1 = l^2 + 2/l), 2 (l - l^-5) W1 (equibiaxial,
    I1 = 2 l^2 + l^-4), 2 (l - l^-3) W1 (planar, I1 = l^2 + 1 + l^-2); W1 = dW/dI1."""
    i1, factor = {"uniaxial": (lam ** 2 + 2 / lam, lam - lam ** -2),
                  "equibiaxial": (2 * lam ** 2 + lam ** -4, lam - lam ** -5),
                  "planar": (lam ** 2 + 1 + lam ** -2, lam - lam ** -3)}[mode]
    x = i1 - 3
    return 2 * factor * (c10 + 2 * c20 * x + 3 * c30 * x ** 2)


def _ogden_nominal(terms, mode, lam):
    """Closed forms: P = sum 2 mu / a (l^(a-1) - l3^a / l), l3 = l^-1/2 (uniaxial), l^-2
    (equibiaxial), 1/l (planar)."""
    power = {"uniaxial": -0.5, "equibiaxial": -2.0, "planar": -1.0}[mode]
    return sum(2 * t["mu_pa"] / t["alpha"] * (lam ** (t["alpha"] - 1) - lam ** (power * t["alpha"] - 1))
               for t in terms)


@pytest.mark.parametrize("mode", ["uniaxial", "equibiaxial", "planar"])
def test_yeoh_nominal_stress_matches_closed_form(mode):
    mat = material_from_dict(YEOH)
    for lam in STRETCHES:
        expected = _yeoh_nominal(1.1e6, -4.0e4, 1.5e3, mode, lam)
        assert _nominal_from_energy(mat, mode, lam) == pytest.approx(expected, rel=1e-10)


@pytest.mark.parametrize("mode", ["uniaxial", "equibiaxial", "planar"])
def test_ogden_nominal_stress_matches_closed_form(mode):
    mat = material_from_dict(OGDEN)
    for lam in STRETCHES:
        expected = _ogden_nominal(OGDEN["terms"], mode, lam)
        assert _nominal_from_energy(mat, mode, lam) == pytest.approx(expected, rel=1e-10)


@pytest.mark.parametrize("spec, mu0", [(YEOH, 2 * 1.1e6), (OGDEN, 1.6e6 + 2.0e3 - 3.0e4)])
def test_small_strain_shear_modulus_is_mu0(spec, mu0):
    """Simple shear F = [[1, g, 0], [0, 1, 0], [0, 0, 1]]: d2W/dg2 at g = 0 is the shear modulus."""
    mat = material_from_dict(spec)
    assert mat.given_moduli_pa()[0] == pytest.approx(mu0, rel=1e-15)
    with jax.enable_x64(True):
        c = _constants(mat)

        def w(g):
            C = Sym(jnp.asarray(1.0), 1.0 + g * g, jnp.asarray(1.0), g)
            parts = type(mat).energy(C, c)
            return parts[0] + parts[1]

        assert float(jax.grad(jax.grad(w))(jnp.asarray(0.0))) == pytest.approx(mu0, rel=1e-9)
    # and the bulk modulus of D1 = 0: K0 = 20 mu0
    assert mat.bulk_modulus_pa() == pytest.approx(20 * mu0, rel=1e-12)


def _rotation(seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.diag(r))


@pytest.mark.parametrize("spec", [YEOH, OGDEN, {**OGDEN, "d1_per_pa": 2e-8}])
@pytest.mark.parametrize("stretches", [(1.3, 0.9, 0.8), (0.6, 1.4, 1.4), (1.2, 1.2, 0.71)])
def test_3d_path_is_objective(spec, stretches):
    """A general C = Q diag(l^2) Q^T (the 3D solver's eigenvalue path) gives the rotated principal
    stress (the direct path), volumetric part included: S = Q diag(S_i) Q^T."""
    mat = material_from_dict(spec)
    q = _rotation(sum(int(10 * x) for x in stretches))
    lam2 = np.array(stretches) ** 2
    with jax.enable_x64(True):
        c = _constants(mat)
        diag = Sym(*(jnp.asarray(x) for x in lam2), jnp.asarray(0.0))
        (w0, s0), (v0, p0) = energy_and_stress(type(mat).energy, diag, c)
        principal = np.diag([float(a + b) for a, b in zip(s0[:3], p0[:3])])
        general = Sym.from_matrix(jnp.asarray(q @ np.diag(lam2) @ q.T))
        (w1, s1), (v1, p1) = energy_and_stress(type(mat).energy, general, c)
        s = np.array([float(a + b) for a, b in zip(s1, p1)])
    expected = q @ principal @ q.T
    got = np.array([[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]])
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-10 * np.abs(principal).max())
    assert float(w1 + v1) == pytest.approx(float(w0 + v0), rel=1e-10)


@pytest.mark.parametrize("general", [False, True])
def test_special_cases_are_neo_hookean(general):
    """Yeoh with C20 = C30 = 0, and Ogden (mu, alpha = 2), are neo-Hookean C10 = mu / 2, to
    round-off, at compressible states, in both paths."""
    neo = NeoHookean(c10_pa=0.8e6, d1_per_pa=1e-8)
    yeoh = Yeoh(c10_pa=0.8e6, d1_per_pa=1e-8)
    ogden = material_from_dict({"model": "ogden", "terms": [{"mu_pa": 1.6e6, "alpha": 2.0}],
                                "d1_per_pa": 1e-8})
    m = _rotation(7) @ np.diag([1.5, 0.7, 0.9]) @ _rotation(8)  # a deformation gradient
    cm = m.T @ m
    if not general:
        cm[0, 2] = cm[2, 0] = cm[1, 2] = cm[2, 1] = 0.0
    with jax.enable_x64(True):
        C = Sym.from_matrix(jnp.asarray(cm))
        if not general:
            C = C._replace(yz=0.0, zx=0.0)
        results = []
        for mat in (neo, yeoh, ogden):
            (w, s), (v, p) = energy_and_stress(type(mat).energy, C, _constants(mat))
            results.append(np.array([float(w), float(v), *map(float, s), *map(float, p)]))
    scale = np.abs(results[0]).max()
    np.testing.assert_allclose(results[1], results[0], rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(results[2], results[0], rtol=0, atol=1e-12 * scale)


def test_long_term_and_instantaneous_scale_the_constants():
    prony = [{"g": 0.5, "tau_s": 1e-4}, {"g": 0.29, "tau_s": 1e-3}]
    for spec in (YEOH, OGDEN):
        long_term = material_from_dict({**spec, "prony": prony})
        instant = material_from_dict({**spec, "prony": prony, "moduli": "instantaneous"})
        s_long = _deviatoric_stress(long_term, (1.3, 0.95, 0.81))
        s_inst = _deviatoric_stress(instant, (1.3, 0.95, 0.81))
        np.testing.assert_allclose(s_inst, s_long * 0.21, rtol=1e-12)
        assert long_term.shear_modulus_pa(instantaneous=False) == pytest.approx(
            long_term.given_moduli_pa()[0], rel=1e-14)


@pytest.mark.parametrize("spec", [YEOH, {**OGDEN, "d1_per_pa": 1e-8, "moduli": "instantaneous",
                                          "prony": [{"g": 0.3, "k": 0.1, "tau_s": 1e-4}]}])
def test_specification_round_trip(spec):
    mat = material_from_dict(spec)
    assert material_from_dict(mat.to_dict()) == mat
    assert material_from_dict({"model": "yeoh", "c10_pa": 1e6}) == Yeoh(c10_pa=1e6)


@pytest.mark.parametrize("spec, fragments", [
    ({"model": "yeoh", "c10_pa": 0.0}, ["c10_pa = 0", "(0, inf)"]),
    ({"model": "yeoh"}, ["missing key 'c10_pa'"]),
    ({"model": "yeoh", "c10_pa": 1e6, "d1_per_pa": -1.0}, ["d1_per_pa = -1"]),
    ({"model": "yeoh", "c10_pa": 1e6, "c01_pa": 1.0}, ["unknown key 'c01_pa'"]),
    ({"model": "ogden", "terms": []}, ["terms", "1 to 6"]),
    ({"model": "ogden", "terms": [{"mu_pa": 1e6, "alpha": 2.0}] * 7}, ["terms", "1 to 6"]),
    ({"model": "ogden", "terms": [{"mu_pa": 1e6, "alpha": 0.0}]}, ["terms[0].alpha", "not be 0"]),
    ({"model": "ogden", "terms": [{"mu_pa": 1e5, "alpha": 2.0}, {"mu_pa": -2e5, "alpha": -2.0}]},
     ["sum of mu_pa = -100000: allowed range (0, inf) Pa"]),
    ({"model": "ogden", "terms": [{"mu_pa": 1e6, "alpha": 2.0, "nu": 0.0}]}, ["unknown key 'nu'"]),
])
def test_bad_rubber_input_names_the_key(spec, fragments):
    with pytest.raises(InputError) as error:
        material_from_dict(spec, where="ball.layers[0].material")
    message = str(error.value)
    assert message.startswith("ball.layers[0].material")
    for fragment in fragments:
        assert fragment in message, message


# ---- impacts ---------------------------------------------------------------------------------
R = 0.036
RHO = 0.160 / (4.0 / 3.0 * math.pi * R ** 3)
PRONY = [{"g": 0.4, "tau_s": 1e-4}]
RUBBER_BALL = {"name": "rubber", "layers": [
    {"name": "core", "outer_radius_m": 0.02, "density_kg_m3": RHO,
     "material": {**YEOH, "c10_pa": 2e6, "prony": PRONY}},
    {"name": "cover", "outer_radius_m": R, "density_kg_m3": RHO,
     "material": {**OGDEN, "moduli": "instantaneous", "prony": PRONY,
                  "terms": [{"mu_pa": 3e6, "alpha": 2.5}, {"mu_pa": -1e5, "alpha": -2.0}]}}]}


def test_yeoh_and_ogden_ball_runs_axisymmetric():
    """A Yeoh core in an Ogden cover (Prony terms in both, long-term and instantaneous) at 5 m/s
    on a coarse mesh: energy balance within the solver's limit, contact and rebound."""
    ball = load_ball(RUBBER_BALL)
    options = SolverOptions(element_size_m=6e-3)
    result = simulate(ball, 5.0, options)
    assert result.energy_balance_error < options.energy_error_limit
    assert result.energy_balance_error < 1e-3  # (measured 3.5e-5)
    assert 0.5 < result.cor < 1.0 and result.peak_force_n > 100.0
    # the ball was deformed well into the nonlinear range and stays Drucker-stable there
    assert result.stretch_range[0] < 0.85 and result.stretch_range[1] > 1.1


@pytest.mark.slow
def test_yeoh_and_ogden_ball_runs_in_3d():
    """The same ball in the 3D solver (eigenvalue path of the Ogden energy): energy balance
    within the limit, and peak force within 15% of the axisymmetric solver's on coarse meshes
    (measured 9%)."""
    from ballimpact.oblique import ImpactCondition, Options3D, simulate_oblique

    ball = load_ball(RUBBER_BALL)
    options = Options3D(divisions=6, pole_grading=2.0)
    three_d = simulate_oblique(ball, ImpactCondition(5.0), options)
    assert three_d.energy_balance_error < options.energy_error_limit
    axisymmetric = simulate(ball, 5.0, SolverOptions(element_size_m=6e-3))
    assert three_d.peak_force_n == pytest.approx(axisymmetric.peak_force_n, rel=0.15)


@pytest.mark.parametrize("material, fragments", [
    ({"model": "ogden", "terms": [{"mu_pa": -1e6, "alpha": 2.0}]},
     ["ball.layers[0].material", "ogden.terms: sum of mu_pa"]),
    ({"model": "yeoh", "c10_pa": -1e6}, ["ball.layers[0].material.c10_pa = -1e+06", "(0, inf)"]),
])
def test_cli_refuses_bad_rubber_constants(material, fragments, tmp_path, bad_input):
    path = tmp_path / "rubber.json"
    path.write_text(json.dumps({"name": "r", "layers": [
        {"name": "ball", "outer_radius_m": R, "density_kg_m3": RHO, "material": material}]}))
    bad_input(["simulate", "--ball", path, "--speed-m-s", "5"], "rubber.json", *fragments)
