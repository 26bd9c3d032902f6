"""Hertz model: an elastic sphere (E, nu, radius R) on a rigid plane, F = (4/3) E* sqrt(R) y^1.5
with E* = E / (1 - nu^2). No damping: the COR is 1. Only E* can be identified from a pulse, so a
fit searches E with nu and R fixed (defaults 0.5 and 36 mm, a cricket ball)."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from ..records import check_positive
from .base import Parameter, check_range
from .engine import OdeModel
from .single_element import force as single_element_force, undamped_power_law

EXPONENT = 1.5
POISSONS_RATIO, RADIUS_M = 0.5, 0.036  # defaults: rubber-like, a cricket ball


def _stiffness(youngs_modulus, poissons_ratio, radius):
    return 4.0 / 3.0 * youngs_modulus / (1.0 - poissons_ratio**2) * jnp.sqrt(radius)


def force(q, state):
    return single_element_force(jnp.stack([q[0], EXPONENT, 0.0]), state)


def split(p, mass):
    return _stiffness(p[0], p[1], p[2])[None, None], jnp.atleast_1d(mass)


def bounds(scale):
    # E from F = (4/3) E/(1 - nu^2) sqrt(R) y^1.5 at the measured peak, default nu and R
    e_star = 0.75 * scale.peak_force_n / np.sqrt(RADIUS_M) / scale.max_compression_m**1.5
    estimate = e_star * (1.0 - POISSONS_RATIO**2)
    return {"youngs_modulus_pa": (0.1 * estimate, 10.0 * estimate)}


def validate(params):
    check_range("youngs_modulus_pa", params["youngs_modulus_pa"], 0.0, strict=True)
    check_range("poissons_ratio", params["poissons_ratio"], -1.0, 0.5, strict=True)
    check_range("radius_m", params["radius_m"], 0.0, strict=True)


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


def hertz_impact(youngs_modulus_pa: float, poissons_ratio: float, radius_m: float,
                 mass_kg: float, speed_m_s: float) -> tuple[float, float, float]:
    """Hertz closed form (docs/lumped.md "Verification"): (max compression m, peak force N,
    contact time s), with t_c = C(1.5) y_max / v, C(1.5) = 2.94328."""
    check_positive("youngs_modulus_pa", youngs_modulus_pa)
    check_positive("radius_m", radius_m)
    stiffness = float(_stiffness(youngs_modulus_pa, poissons_ratio, radius_m))
    return undamped_power_law(stiffness, EXPONENT, mass_kg, speed_m_s)
