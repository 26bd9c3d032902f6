"""The fast engine (issue 9): the increment from the assembled system, the energy stop, reduced
integration with hourglass control, float32, and batches that vary speeds and materials."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.sparse.linalg as sla

from ballimpact.errors import InputWarning, SimulationError
from ballimpact.balls.ball import BallModel, Layer
from ballimpact.fe.axi.kernel import ball_arrays
from ballimpact.fe.steps import cast
from ballimpact.constitutive import material_from_dict
from ballimpact.fe import Axisymmetric, SolverOptions, simulate, simulate_batch
from ballimpact.fe.engine import kernel_for

RADIUS, DENSITY = 0.036, 800.0
UNIVERSAL = {"model": "mooney_rivlin", "c10_pa": 4.72e6, "c01_pa": -0.45e6,
             "prony": [{"g": 0.7, "k": 0.0, "tau_s": 7e-5}]}


def _sphere(material: dict, name="sphere", density=DENSITY) -> BallModel:
    return BallModel(name, (Layer("l", RADIUS, density, material_from_dict(material)),))


@pytest.mark.parametrize("integration", ["reduced", "full"])
def test_lanczos_increment_matches_arpack(integration):
    """omega_max^2 of the assembled M^-1 (K + K_contact) by the solver's Lanczos estimate
    against ARPACK (scipy eigsh) on the same operator: within 1e-6, never below."""
    ball = _sphere(UNIVERSAL)
    options = SolverOptions(element_size_m=3e-3, integration=integration)
    kernel, _ = kernel_for(ball, Axisymmetric(options))
    with jax.enable_x64(True):
        params = jax.tree_util.tree_map(jnp.asarray, cast(ball_arrays(ball, kernel.geom, options),
                                                          np.float64))
        n = len(kernel.geom.nodes_m)
        zeros = jnp.zeros((2, n))
        estimate, _ = jax.jit(kernel.max_frequency_squared, static_argnums=3)(
            params, zeros, None, 40)
        # the same operator assembled independently: K v by forward differences of the forces
        mats = kernel.initial_materials(params)
        elastic = params._replace(bv_linear_pa_s=0 * params.bv_linear_pa_s,
                                  bv_quadratic_pa_s2=0 * params.bv_quadratic_pa_s2)
        forces = jax.jit(lambda u: kernel.internal(elastic, u, mats, jnp.ones(
            kernel.geom.n_elements), 1e-18)[0])
        scale = 1.0 / np.sqrt(np.asarray(params.mass_kg))
        mask = np.stack([kernel.geom.nodes_m[:, 0] > 0, np.ones(n, bool)]).astype(float)
        s = kernel.geom.surface_nodes
        eps = 1e-9

        def apply(x):
            v = x.reshape(2, n) * scale * mask
            kv = np.array((forces(jnp.asarray(eps * v)) - forces(jnp.asarray(-eps * v))) / (2 * eps))
            kv[1, s] += np.asarray(params.penalty_n_m) * v[1, s]
            return (kv * scale * mask).reshape(-1)

        reference = sla.eigsh(sla.LinearOperator((2 * n, 2 * n), matvec=apply), k=1,
                              which="LA", tol=1e-10)[0][0]
    assert float(estimate) == pytest.approx(reference, rel=1e-6)
    assert float(estimate) >= reference * (1 - 1e-9)


def test_too_large_increment_is_a_clear_error():
    with pytest.warns(InputWarning, match="above the stability limit"):
        options = SolverOptions(element_size_m=4e-3, time_step_scale=1.3)
    # the instability shows as energy growth or, when it grows within a chunk, inverted elements
    with pytest.raises(SimulationError, match="time_step_scale"):
        simulate(_sphere(UNIVERSAL), 20.0, options)
    with pytest.warns(InputWarning):
        every_step = SolverOptions(element_size_m=4e-3, time_step_scale=1.3, chunk_steps=1)
    with pytest.raises(SimulationError, match="energy balance error above energy_error_limit"):
        simulate(_sphere(UNIVERSAL), 20.0, every_step)


def test_increment_shrinks_as_the_ball_stiffens():
    result = simulate(_sphere(UNIVERSAL), 45.0, SolverOptions(element_size_m=3e-3))
    assert result.final_time_increment_s < result.stable_time_increment_s
    assert result.energy_balance_error < 0.01
    # the pulse comes back uniformly sampled, so the 19 features can be taken from it
    from ballimpact.records.features import extract_features

    features = extract_features(result.record()).values
    assert features["P6"] == pytest.approx(result.peak_force_n, rel=0.01)


def test_hourglass_energy_small_and_point_load_controlled():
    """A point-like load (one node pulled hard at the pole) excites hourglass modes; with control
    the hourglass energy stays a small fraction, and the run stays sound."""
    ball = _sphere({"model": "neo_hookean", "c10_pa": 2e6})
    options = SolverOptions(element_size_m=3e-3, penalty_scale=100.0)  # a stiff point contact
    result = simulate(ball, 10.0, options)
    e = result.energies_j
    assert 0.0 < e["peak_hourglass_energy_j"] < 0.01 * e["peak_internal_energy_j"]
    assert result.energy_balance_error < 0.01


def test_reduced_and_full_integration_agree():
    ball = _sphere(UNIVERSAL)
    reduced = simulate(ball, 20.0, SolverOptions(element_size_m=3e-3))
    full = simulate(ball, 20.0, SolverOptions(element_size_m=3e-3, integration="full"))
    assert reduced.peak_force_n == pytest.approx(full.peak_force_n, rel=0.02)
    assert reduced.contact_time_s == pytest.approx(full.contact_time_s, rel=0.02)
    assert reduced.cor == pytest.approx(full.cor, abs=0.01)


def test_float32_matches_float64():
    ball = _sphere(UNIVERSAL)
    double = simulate(ball, 25.0, SolverOptions(element_size_m=3e-3))
    single = simulate(ball, 25.0, SolverOptions(element_size_m=3e-3, precision="float32"))
    assert single.precision == "float32" and double.precision == "float64"
    assert single.peak_force_n == pytest.approx(double.peak_force_n, rel=1e-3)
    assert single.contact_time_s == pytest.approx(double.contact_time_s, rel=1e-3)
    assert single.cor == pytest.approx(double.cor, abs=0.002)


def test_batch_of_16_speeds_and_materials_equals_single_runs():
    rng = np.random.default_rng(7)
    balls, speeds = [], rng.uniform(5.0, 40.0, 16)
    for i in range(16):
        spec = {"model": "mooney_rivlin", "c10_pa": rng.uniform(4e6, 7e6),
                "c01_pa": rng.uniform(-1e6, 1e6) * 0.3,
                "prony": [{"g": rng.uniform(0.0, 0.9), "k": 0.0, "tau_s": rng.uniform(1e-5, 1e-4)}]}
        balls.append(_sphere(spec, f"set{i}", density=rng.uniform(780, 860)))
    options = SolverOptions(element_size_m=4e-3)
    batch = simulate_batch(balls, speeds, options)
    for ball, speed, together in zip(balls, speeds, batch):
        alone = simulate(ball, speed, options)
        assert together.impact_speed_m_s == speed and together.steps == alone.steps
        np.testing.assert_allclose(together.history["contact_force_n"],
                                   alone.history["contact_force_n"], rtol=1e-9,
                                   atol=1e-9 * alone.peak_force_n)
        assert together.cor == pytest.approx(alone.cor, rel=1e-9)
        assert together.contact_time_s == pytest.approx(alone.contact_time_s, rel=1e-9)


def test_batch_speeds_must_match_the_balls():
    from ballimpact.errors import InputError

    ball = _sphere(UNIVERSAL)
    with pytest.raises(InputError, match="impact_speeds_m_s"):
        simulate_batch([ball, ball], [10.0, 20.0, 30.0])
