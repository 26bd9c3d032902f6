"""Lieberman and Johnson (1994) five-parameter model, thesis fig. 2-3 and eq. 2-7..2-12:
a spring k1 x1^alpha in parallel with a Maxwell branch (spring k2 x3^beta in series with a damper
c). With x1 the compression, x2 its rate and x3 the branch spring's deflection:
x1' = x2, m x2' = -k1 x1^alpha - k2 x3^beta, c x3' = c x2 - k2 x3^beta; x1 = x3 = 0, x2 = v_in at
first contact. Contact force k1 x1^alpha + k2 x3^beta."""

from __future__ import annotations

from ..checks import check_range
from .base import Parameter
from .engine import OdeModel, signed_power
from .single_element import split


def force(q, state):
    k1, alpha, k2, beta = q[0], q[1], q[2], q[3]
    return k1 * signed_power(state[0], alpha) + k2 * signed_power(state[2], beta)


def internal_rate(q, state):
    k2, beta, c = q[2], q[3], q[4]
    return state[1] - k2 * signed_power(state[2], beta) / c


def bounds(scale):
    return {
        "k1": (0.1 * scale.peak_force_n, 3.0 * scale.peak_force_n),
        "alpha": (1.0, 2.5),
        "k2": (0.03 * scale.peak_force_n, 3.0 * scale.peak_force_n),
        "beta": (1.0, 2.5),
        "c": (0.01 * scale.force_per_speed_n_s_m, 100.0 * scale.force_per_speed_n_s_m),
    }


def validate(params):
    for name in ("k1", "k2"):
        check_range(f"params.{name}", params[name], 0.0, low_open=True)
    for name in ("alpha", "beta"):
        check_range(f"params.{name}", params[name], 0.5, 5.0)
    check_range("params.c", params["c"], 0.0, low_open=True)


MODEL = OdeModel(
    name="lieberman_johnson",
    summary="Lieberman-Johnson: spring k1 x^alpha || (spring k2 x^beta in series with damper c)",
    parameters=(
        Parameter("k1", "N/m^alpha", "parallel spring stiffness", "stiffness", "alpha"),
        Parameter("alpha", "1", "parallel spring exponent"),
        Parameter("k2", "N/m^beta", "Maxwell-branch spring stiffness", "stiffness", "beta"),
        Parameter("beta", "1", "Maxwell-branch spring exponent"),
        Parameter("c", "N s/m", "Maxwell-branch damper", "log"),
    ),
    bounds=bounds,
    split=split,
    force=force,
    state_size=3,
    internal_rate=internal_rate,
    validate=validate,
)
