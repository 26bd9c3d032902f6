"""The driver both explicit engines share (`fe.driver`): its differentiable fixed-increment run
for either kernel, checked by the momentum balance (the contact impulse is the change of the
ball's momentum) and its derivative against central differences."""

import math
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ballimpact.fe import SolverOptions, load_ball
from ballimpact.fe.driver import fixed_increment_run
from ballimpact.fe.axi.kernel import HISTORY as AXI_HISTORY
from ballimpact.fe.stable_increment import shrunk_increment
from ballimpact.fe.steps import LANCZOS_STEPS, REFRESH_LANCZOS_STEPS, cast
from ballimpact.fe.estimates import hertz_contact_time_s
from ballimpact.fe.axi.kernel import ball_arrays
from ballimpact.fe.engine import Axisymmetric, Hexahedral, kernel_for
from ballimpact.fe.hex.geometry import model_arrays
from ballimpact.oblique import ImpactCondition, Options3D
from ballimpact.fe.hex.kernel import HISTORY as HEX_HISTORY

SPEED_M_S = 20.0
BALL = load_ball("cricket-universal", impact_speed_m_s=SPEED_M_S)


def axisymmetric_case():
    options = SolverOptions(element_size_m=4e-3)
    kernel, _ = kernel_for(BALL, Axisymmetric(options))
    params = ball_arrays(BALL, kernel.geom, options)
    return (kernel, params, lambda speed: [speed], float(np.sum(params.mass_kg)), SPEED_M_S,
            AXI_HISTORY.index("contact_force_n"))


def hexahedral_case():
    options = Options3D(divisions=4, pole_grading=2.0)
    condition = ImpactCondition(SPEED_M_S, 30.0, 0.0, 0.3)
    kernel, _ = kernel_for(BALL, Hexahedral(options, half=True))
    params = model_arrays(BALL, None, kernel, options, condition)
    angle, spin = math.radians(30.0), np.array(condition.spin_vector_rad_s)
    return (kernel, params, lambda speed: [speed, angle, spin], float(params.ball_mass_kg),
            SPEED_M_S * math.cos(angle), HEX_HISTORY.index("contact_force_n"))


@pytest.mark.parametrize("case, history", [
    (axisymmetric_case, AXI_HISTORY),
    # 30 s on 2 cores, most of it compiling the reverse-mode 3D run
    pytest.param(hexahedral_case, HEX_HISTORY, marks=pytest.mark.slow)])
def test_fixed_increment_run_keeps_the_momentum_balance_and_differentiates(case, history):
    """Either kernel through the one public run: the contact impulse (trapezoidal, as the
    central-difference update integrates it) equals the mass times the change of the
    centre-of-mass velocity to 1e-9; d(rebound velocity)/d(impact speed) by reverse mode equals
    central differences within 1%, and is positive (a faster impact rebounds faster)."""
    kernel, params, initial, mass, normal, force_column = case()
    velocity_column = history.index("centre_velocity_z_m_s")
    with jax.enable_x64(True):
        p = jax.tree_util.tree_map(jnp.asarray, cast(params, kernel.dtype))
        # 0.9 of the stable increment at the start (the first chunk estimates it), over 1.5
        # Hertz contact times
        state = jax.jit(kernel.initial_state)(p, *initial(SPEED_M_S))
        dt = 0.9 * float(jax.jit(partial(kernel.chunk, n_steps=1))(p, state)[0].dt0)
        n_chunks = math.ceil(1.5 * hertz_contact_time_s(BALL, normal) / (dt * 100))

        @jax.jit
        def rebound(speed):
            rows = fixed_increment_run(kernel, p, initial(speed), dt, n_chunks, 100,
                                       (force_column, velocity_column))
            return rows[-1, 1], rows

        speed = jnp.asarray(SPEED_M_S)
        (v_end, rows), slope = jax.jit(jax.value_and_grad(rebound, has_aux=True))(speed)
        force, v_cm = np.asarray(rows, np.float64).T
        impulse = dt * (np.sum(force) - 0.5 * force[-1])  # force is 0 at t = 0
        assert force[-1] == 0.0 and force.max() > 0.0  # the window holds the whole contact
        assert impulse == pytest.approx(mass * (v_cm[-1] + normal), rel=1e-9)
        h = 1e-3
        central = (rebound(speed + h)[0] - rebound(speed - h)[0]) / (2 * h)
    assert float(v_end) > 0.0
    assert float(slope) == pytest.approx(float(central), rel=0.01)
    assert float(slope) > 0.0


# ---- one options class, one impact condition -----------------------------------------------
SHARED = {"integration": "full", "hourglass_scale": 0.1, "bulk_viscosity_linear": 0.1,
          "bulk_viscosity_quadratic": 1.0, "penalty_scale": 2.0, "contact_damping": 0.1,
          "time_step_scale": 0.7, "energy_error_limit": 0.1, "precision": "float32",
          "end_margin": 0.5, "time_limit_s": 0.01, "chunk_steps": 50}


@pytest.mark.parametrize("name, value", [
    ("hourglass_scale", 0.0), ("bulk_viscosity_linear", -0.1), ("penalty_scale", 101.0),
    ("contact_damping", 1.5), ("time_step_scale", 2.5), ("energy_error_limit", 0.0),
    ("end_margin", -1.0), ("time_limit_s", 11.0), ("chunk_steps", 0), ("chunk_steps", True),
    ("precision", "float16"), ("integration", "selective")])
def test_both_engines_refuse_a_shared_setting_with_one_message(name, value):
    """The settings both engines share are one class (`ExplicitOptions`), checked one way: the
    same bad value gets the same message from either engine's options."""
    from ballimpact.errors import InputError
    from ballimpact.fe.options import ExplicitOptions

    messages = []
    for options in (SolverOptions, Options3D):
        assert issubclass(options, ExplicitOptions)
        with pytest.raises(InputError) as error:
            options(**{name: value})
        messages.append(str(error.value))
    assert messages[0] == messages[1] and messages[0].startswith(f"{name} = ")


def test_shared_settings_reach_both_engines():
    for options in (SolverOptions(**SHARED), Options3D(**SHARED)):
        assert {k: getattr(options, k) for k in SHARED} == SHARED


def test_the_axisymmetric_engine_takes_a_normal_impact_condition():
    """`simulate` takes the 3D engine's `ImpactCondition`: a normal one runs as its speed does
    (the same bits), an oblique or spinning one is refused, pointing to the 3D solver."""
    from ballimpact.errors import InputError
    from ballimpact.fe import simulate

    options = SolverOptions(element_size_m=4e-3)
    by_speed = simulate(BALL, SPEED_M_S, options)
    by_condition = simulate(BALL, ImpactCondition(SPEED_M_S, friction=0.3), options)
    np.testing.assert_array_equal(by_speed.history["contact_force_n"],
                                  by_condition.history["contact_force_n"])
    for condition in (ImpactCondition(SPEED_M_S, angle_deg=20.0),
                      ImpactCondition(SPEED_M_S, spin_rad_s=100.0)):
        with pytest.raises(InputError, match="normal impacts without spin.*fe.Hexahedral"):
            simulate(BALL, condition, options)


def test_first_chunk_estimate_equals_the_loops_of_their_own():
    """The 3D kernel estimates its start increment in the first chunk, in one Lanczos loop of
    40 or 8 steps (`first_estimate_in_chunk`): the start increment equals that of a 40-step loop
    of its own at the undeformed state to 1e-12, and the next chunk's increment is the one an
    8-step loop of its own gives from the first chunk's state and Ritz vector (quantized
    levels: equal)."""
    kernel, params, initial, *_ = hexahedral_case()
    assert kernel.first_estimate_in_chunk
    chunk = jax.jit(partial(kernel.chunk, n_steps=1))
    estimate = jax.jit(kernel.max_frequency_squared, static_argnums=3)
    with jax.enable_x64(True):
        p = jax.tree_util.tree_map(jnp.asarray, cast(params, kernel.dtype))
        state0 = jax.jit(kernel.initial_state)(p, *initial(SPEED_M_S))
        assert float(state0.dt0) == 0.0
        state1, _ = chunk(p, state0)
        omega2, _ = estimate(p, state0.u, None, LANCZOS_STEPS)
        expected = float(p.increment_factor / jnp.sqrt(omega2))
        assert float(state1.dt0) == pytest.approx(expected, rel=1e-12)
        assert float(state1.dt) == float(state1.dt0)
        state2, _ = chunk(p, state1)
        omega2, _ = estimate(p, state1.u, state1.x_top, REFRESH_LANCZOS_STEPS)
        refreshed = shrunk_increment(state1.dt, state1.dt0, omega2, p.increment_factor)
        assert float(state2.dt) == float(refreshed)
        assert float(state2.dt0) == float(state1.dt0)

