"""Hunt-Crossley model: F = k y^n (1 + lambda y'). Damping proportional to the elastic force, so
the force starts and ends at zero; the COR depends only on z = lambda v_in:
z (1 + e) = ln[(1 + z) / (1 - e z)] (docs/lumped.md "Verification")."""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from ..checks import check_positive, check_range
from .base import Parameter
from .engine import OdeModel, signed_power
from .single_element import split


def force(q, state):
    k, n, lam = q[0], q[1], q[2]
    return k * signed_power(state[0], n) * (1.0 + lam * state[1])


def bounds(scale):
    return {
        "k": scale.stiffness_force_bounds_n,
        "n": (1.0, 2.5),
        "lambda": (0.0, 3.0 / scale.impact_speed_m_s),
    }


def validate(params):
    check_range("params.k", params["k"], 0.0, low_open=True)
    check_range("params.n", params["n"], 0.5, 5.0)
    check_range("params.lambda", params["lambda"], 0.0)


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


def _residual(z, cor, s):
    """z (1 + e) - ln[(1 + z)/(1 - e z)] with s = -ln(1 - e z) given, so that the root can be
    bracketed in s even where 1 - e z underflows."""
    return z * (1.0 + cor) - np.log1p(z) - s


def hunt_crossley_cor(damping_s_m: float, impact_speed_m_s: float) -> float:
    """COR of a Hunt-Crossley impact: the root e of z (1 + e) = ln[(1 + z)/(1 - e z)], z = lambda v."""
    speed = check_positive("impact_speed_m_s", impact_speed_m_s)
    damping_s_m = check_range("lambda", damping_s_m, 0.0, unit="s/m")
    z = damping_s_m * speed
    if z == 0:
        return 1.0
    cor = lambda s: -np.expm1(-s) / z  # noqa: E731 - e from s = -ln(1 - e z)
    # e < 1 and e z < 1; for z >= 1 the residual falls like z + 1 - ln(1 + z) - s at large s
    s_max = -np.log1p(-z) if z < 1 else z + 2.0
    s = brentq(lambda s: _residual(z, cor(s), s), 1e-12 * min(z, 1.0), s_max, xtol=1e-15,
               rtol=1e-15)
    return float(cor(s))


def hunt_crossley_lambda(cor: float, impact_speed_m_s: float) -> float:
    """The damping factor lambda (s/m) that gives `cor` at `impact_speed_m_s` (for COR near 1,
    lambda -> 3 (1 - e) / (2 v))."""
    speed = check_positive("impact_speed_m_s", impact_speed_m_s)
    cor = check_range("cor", cor, 0.0, 1 - 1e-6, low_open=True)
    z_of = lambda s: -np.expm1(-s) / cor  # noqa: E731 - z from s = -ln(1 - e z)
    # the residual is z^2 (1 - e^2)/2 - O(z^3) > 0 below the root, which is near 1.5 (1 - e)
    s_low = -np.log1p(-cor * 0.15 * (1.0 - cor))
    # at large s, z -> 1/e and the residual falls like (1 + e)/e - ln(1 + 1/e) - s
    s_high = (1.0 + cor) / cor + 1.0
    s = brentq(lambda s: _residual(z_of(s), cor, s), s_low, s_high, xtol=1e-15, rtol=1e-15)
    return float(z_of(s) / speed)
