"""Hertz model: an elastic sphere (E, nu, radius R) on a rigid plane, F = (4/3) E* sqrt(R) y^1.5
with E* = E / (1 - nu^2). No damping: the COR is 1. Only E* can be identified from a pulse, so a
fit searches E with nu and R fixed (defaults 0.5 and 36 mm, a cricket ball). Its closed form is
`closedform.hertz_impact`."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from ..checks import check_range
from ..closedform import HERTZ_EXPONENT as EXPONENT, hertz_stiffness
from .base import Parameter
from .engine import OdeModel
from .single_element import force as single_element_force

POISSONS_RATIO, RADIUS_M = 0.5, 0.036  # defaults: rubber-like, a cricket ball


def force(q, state):
    return single_element_force(jnp.stack([q[0], EXPONENT, 0.0]), state)


def split(p, mass):
    return jnp.asarray(hertz_stiffness(p[0], p[1], p[2]))[None, None], jnp.atleast_1d(mass)


def bounds(scale):
    # E from F = (4/3) E/(1 - nu^2) sqrt(R) y^1.5 at the measured peak, default nu and R
    e_star = 0.75 * scale.peak_force_n / np.sqrt(RADIUS_M) / scale.max_compression_m**1.5
    estimate = e_star * (1.0 - POISSONS_RATIO**2)
    return {"youngs_modulus_pa": (0.1 * estimate, 10.0 * estimate)}


def validate(params):
    check_range("params.youngs_modulus_pa", params["youngs_modulus_pa"], 0.0, low_open=True)
    check_range("params.poissons_ratio", params["poissons_ratio"], -1.0, 0.5, low_open=True)
    check_range("params.radius_m", params["radius_m"], 0.0, low_open=True)


MODEL = OdeModel(
    name="hertz",
    summary="elastic sphere on a rigid plane, F = (4/3) E/(1-nu^2) sqrt(R) y^1.5",
    parameters=(
        Parameter("youngs_modulus_pa", "Pa", "Young's modulus", "log"),
        Parameter("poissons_ratio", "1", "Poisson's ratio", default=POISSONS_RATIO),
        Parameter("radius_m", "m", "sphere radius", default=RADIUS_M),
    ),
    bounds=bounds,
    split=split,
    force=force,
    validate=validate,
)
