"""The driver both explicit engines share (`fe.driver`): its differentiable fixed-increment run
for either kernel, checked by the momentum balance (the contact impulse is the change of the
ball's momentum) and its derivative against central differences."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from ballimpact.fe import SolverOptions, load_ball
from ballimpact.fe.driver import fixed_increment_run
from ballimpact.fe.kernel import HISTORY as AXI_HISTORY, cast, hertz_contact_time_s
from ballimpact.fe.solver import ball_arrays, kernel_for
from ballimpact.oblique import ImpactCondition, Options3D
from ballimpact.oblique import solver as solver3d
from ballimpact.oblique.kernel import HISTORY as HEX_HISTORY

SPEED_M_S = 20.0
BALL = load_ball("cricket-universal", impact_speed_m_s=SPEED_M_S)


def axisymmetric_case():
    options = SolverOptions(element_size_m=4e-3)
    kernel = kernel_for(BALL, options)
    params = ball_arrays(BALL, kernel.geom, options)
    return (kernel, params, lambda speed: [speed], float(np.sum(params["mass_kg"])), SPEED_M_S,
            AXI_HISTORY.index("contact_force_n"))


def hexahedral_case():
    options = Options3D(divisions=4, pole_grading=2.0)
    condition = ImpactCondition(SPEED_M_S, 30.0, 0.0, 0.3)
    kernel, _ = solver3d.kernel_for(BALL, None, options, True)
    params = solver3d.model_arrays(BALL, None, kernel, options, condition)
    angle, spin = math.radians(30.0), np.array(condition.spin_vector_rad_s)
    return (kernel, params, lambda speed: [speed, angle, spin], float(params["ball_mass_kg"]),
            SPEED_M_S * math.cos(angle), HEX_HISTORY.index("normal_force_n"))


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
        # 0.9 of the stable increment at the start, over 1.5 Hertz contact times
        dt = 0.9 * float(jax.jit(kernel.initial_state)(p, *initial(SPEED_M_S))["dt0"])
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
