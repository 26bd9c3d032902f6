"""Single-element model (thesis 4.2, fig. 4-1): a nonlinear spring with a linear viscous damper,
m y'' = -(k y^alpha + c y'). Also the closed form of its undamped limit, F = k y^a."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
from scipy.special import gamma

from .base import Parameter, check_range
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
    check_range("k", params["k"], 0.0, strict=True)
    check_range("alpha", params["alpha"], 0.5, 5.0)
    check_range("c", params["c"], 0.0)


MODEL = OdeModel(
    name="single_element",
    summary="nonlinear spring + viscous damper, F = k y^alpha + c y' (thesis 4.2)",
    parameters=(STIFFNESS, EXPONENT, DAMPING),
    bounds=bounds,
    split=split,
    force=force,
    validate=validate,
)


def power_law_contact_constant(exponent: float) -> float:
    """C(a) = 2 sqrt(pi) Gamma(1 + 1/(a+1)) / Gamma(1/2 + 1/(a+1)): t_c = C(a) y_max / v
    (C(1) = pi, C(1.5) = 2.94328)."""
    b = 1.0 / (exponent + 1.0)
    return float(2.0 * np.sqrt(np.pi) * gamma(1.0 + b) / gamma(0.5 + b))


def undamped_power_law(stiffness: float, exponent: float, mass_kg: float, speed_m_s: float):
    """Closed form of m y'' = -k y^a, y(0) = 0, y'(0) = v (docs/lumped.md "Verification"):
    returns (y_max in m, F_max in N, contact time in s)."""
    y_max = ((exponent + 1.0) * mass_kg * speed_m_s**2 / (2.0 * stiffness)) ** (1.0 / (exponent + 1.0))
    return y_max, stiffness * y_max**exponent, power_law_contact_constant(exponent) * y_max / speed_m_s
