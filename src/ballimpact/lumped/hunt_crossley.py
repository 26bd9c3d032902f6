"""Hunt-Crossley model: F = k y^n (1 + lambda y'). Damping proportional to the elastic force, so
the force starts and ends at zero; the COR depends only on z = lambda v_in:
z (1 + e) = ln[(1 + z) / (1 - e z)] (DESIGN.md "Verification")."""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from ..errors import InputError
from .base import Parameter, check_range
from .engine import OdeModel, signed_power
from .single_element import split


def force(q, state):
    k, n, lam = q[0], q[1], q[2]
    return k * signed_power(state[0], n) * (1.0 + lam * state[1])


def bounds(scale):
    return {
        "k": (0.3 * scale.peak_force_n, 3.0 * scale.peak_force_n),
        "n": (1.0, 2.5),
        "lambda": (0.0, 3.0 / scale.impact_speed_m_s),
    }


def validate(params):
    check_range("k", params["k"], 0.0)
    check_range("n", params["n"], 0.5, 5.0)
    check_range("lambda", params["lambda"], 0.0)


MODEL = OdeModel(
    name="hunt_crossley",
    summary="Hunt-Crossley, F = k y^n (1 + lambda y')",
    parameters=(
        Parameter("k", "N/m^n", "stiffness", "stiffness", "n"),
        Parameter("n", "1", "exponent (1.5 Hertzian)"),
        Parameter("lambda", "s/m", "damping factor"),
    ),
    bounds=bounds,
    split=split,
    force=force,
    validate=validate,
)


def _residual(z: float, cor: float) -> float:
    return z * (1.0 + cor) - (np.log1p(z) - np.log1p(-cor * z))


def hunt_crossley_cor(damping_s_m: float, impact_speed_m_s: float) -> float:
    """COR of a Hunt-Crossley impact: the root e of z (1 + e) = ln[(1 + z)/(1 - e z)], z = lambda v."""
    z = damping_s_m * impact_speed_m_s
    if z < 0:
        raise InputError(f"lambda: must be >= 0 s/m, got {damping_s_m!r}")
    if z == 0:
        return 1.0
    upper = min(1.0, 1.0 / z) * (1.0 - 1e-15)  # keeps 1 - e z > 0
    return float(brentq(lambda e: _residual(z, e), 1e-12, upper, xtol=1e-15))


def hunt_crossley_lambda(cor: float, impact_speed_m_s: float) -> float:
    """The damping factor lambda (s/m) that gives `cor` at `impact_speed_m_s`."""
    if not 0 < cor < 1:
        raise InputError(f"cor: must be in (0, 1), got {cor!r}")
    # the residual is z^2 (1 - e^2) / 2 > 0 for small z and -> -inf as e z -> 1
    z = brentq(lambda z: _residual(z, cor), 1e-6, (1.0 - 1e-12) / cor, xtol=1e-15)
    return float(z / impact_speed_m_s)
