"""Closed-form impacts that the models are checked against (docs/lumped.md "Verification"):
the undamped power-law spring m y'' = -k y^a and Hertz's elastic sphere on a rigid plane,
F = (4/3) E* sqrt(R) y^1.5 with E* = E / (1 - nu^2). Plain arithmetic: the lumped models, the
FE engines' increment and time-limit estimates and the oblique reference all use them."""

from __future__ import annotations

import math

from .checks import check_positive

#: Hertz's force exponent
HERTZ_EXPONENT = 1.5


def power_law_contact_constant(exponent: float) -> float:
    """C(a) = 2 sqrt(pi) Gamma(1 + 1/(a+1)) / Gamma(1/2 + 1/(a+1)): t_c = C(a) y_max / v
    (C(1) = pi, C(1.5) = 2.94328)."""
    b = 1.0 / (exponent + 1.0)
    return 2.0 * math.sqrt(math.pi) * math.gamma(1.0 + b) / math.gamma(0.5 + b)


def undamped_power_law(stiffness: float, exponent: float, mass_kg: float, speed_m_s: float):
    """Closed form of m y'' = -k y^a, y(0) = 0, y'(0) = v (docs/lumped.md "Verification"):
    returns (y_max in m, F_max in N, contact time in s)."""
    y_max = ((exponent + 1.0) * mass_kg * speed_m_s**2 / (2.0 * stiffness)) ** (1.0 / (exponent + 1.0))
    return y_max, stiffness * y_max**exponent, power_law_contact_constant(exponent) * y_max / speed_m_s


def hertz_stiffness(youngs_modulus, poissons_ratio, radius):
    """k in F = k y^1.5 (N/m^1.5): (4/3) E / (1 - nu^2) sqrt(R). Plain arithmetic, so that it
    takes floats, NumPy arrays and traced JAX values alike."""
    return 4.0 / 3.0 * youngs_modulus / (1.0 - poissons_ratio**2) * radius**0.5


def hertz_impact(youngs_modulus_pa: float, poissons_ratio: float, radius_m: float,
                 mass_kg: float, speed_m_s: float) -> tuple[float, float, float]:
    """Hertz closed form (docs/lumped.md "Verification"): (max compression m, peak force N,
    contact time s), with t_c = C(1.5) y_max / v, C(1.5) = 2.94328."""
    check_positive("youngs_modulus_pa", youngs_modulus_pa)
    check_positive("radius_m", radius_m)
    stiffness = float(hertz_stiffness(youngs_modulus_pa, poissons_ratio, radius_m))
    return undamped_power_law(stiffness, HERTZ_EXPONENT, mass_kg, speed_m_s)
