"""Simon (1967) golf-ball model, thesis eq. 2-5, 2-6: y1' = y2, y2' = -(k/m) y1^(3/2) (1 + alpha y2),
with y1 the compression and y2 its rate. It is the Hunt-Crossley law with the Hertzian exponent 3/2
fixed; Johnson and Lieberman (1996) note its force vanishes only with the compression."""

from __future__ import annotations

import jax.numpy as jnp

from ..checks import check_range
from .base import Parameter
from .engine import OdeModel
from .hunt_crossley import force as hunt_crossley_force
from .single_element import split

EXPONENT = 1.5


def force(q, state):
    return hunt_crossley_force(jnp.stack([q[0], EXPONENT, q[1]]), state)


def bounds(scale):
    return {"k": scale.stiffness_force_bounds_n,
            "alpha": (0.0, 3.0 / scale.impact_speed_m_s)}


def validate(params):
    check_range("params.k", params["k"], 0.0, low_open=True)
    check_range("params.alpha", params["alpha"], 0.0)


MODEL = OdeModel(
    name="simon",
    summary="Simon (1967), F = k y^1.5 (1 + alpha y') (thesis eq. 2-5, 2-6)",
    parameters=(
        Parameter("k", "N/m^1.5", "stiffness", "stiffness", EXPONENT),
        Parameter("alpha", "s/m", "damping factor"),
    ),
    bounds=bounds,
    split=split,
    force=force,
    validate=validate,
)
