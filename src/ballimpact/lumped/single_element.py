"""Single-element model (thesis 4.2, fig. 4-1): a nonlinear spring with a linear viscous damper,
m y'' = -(k y^alpha + c y'). The closed form of its undamped limit, F = k y^a, is
`closedform.undamped_power_law`."""

from __future__ import annotations

import jax.numpy as jnp
from ..checks import check_range
from .base import Parameter
from .engine import OdeModel, signed_power

STIFFNESS = Parameter("k", "N/m^alpha", "spring stiffness, F = k y^alpha", "stiffness", "alpha")
EXPONENT = Parameter("alpha", "1", "spring exponent (1 linear, 1.5 Hertzian)")
DAMPING = Parameter("c", "N s/m", "viscous damping coefficient")


def force(q, state):
    k, alpha, c = q[0], q[1], q[2]
    return k * signed_power(state[0], alpha) + c * state[1]


def split(p, mass):
    return p[None, :], jnp.atleast_1d(mass)


def bounds(scale):
    return {
        "k": scale.stiffness_force_bounds_n,
        "alpha": (1.0, 2.5),
        "c": (0.0, 1.5 * scale.force_per_speed_n_s_m),
    }


def validate(params):
    check_range("params.k", params["k"], 0.0, low_open=True)
    check_range("params.alpha", params["alpha"], 0.5, 5.0)
    check_range("params.c", params["c"], 0.0)


MODEL = OdeModel(
    name="single_element",
    summary="nonlinear spring + viscous damper, F = k y^alpha + c y' (thesis 4.2)",
    parameters=(STIFFNESS, EXPONENT, DAMPING),
    bounds=bounds,
    split=split,
    force=force,
    validate=validate,
)
