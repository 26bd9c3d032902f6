"""Three-element model (thesis 4.3, fig. 4-3, appendix code): three single-element units in
parallel, each a mass m_i on its own spring k_i y^alpha_i and damper c_i, all arriving at the
impact speed; the masses add up to the ball mass and the contact force is the sum of the unit
forces. Each unit leaves the surface on its own when its force returns to zero.

Its 12 parameters are not unique: different sets give nearly the same total force (units can
swap, and a stiff light unit trades against a soft heavy one), so fit the curve, not the numbers.
"""

from __future__ import annotations

import jax.numpy as jnp

from ..checks import check_range
from ..errors import InputError
from .base import Parameter
from .engine import OdeModel
from .single_element import force

UNITS = 3
PARAMETERS = tuple(
    [Parameter(f"k{i}", f"N/m^alpha{i}", f"unit {i} stiffness", "stiffness", f"alpha{i}")
     for i in range(1, UNITS + 1)]
    + [Parameter(f"alpha{i}", "1", f"unit {i} spring exponent") for i in range(1, UNITS + 1)]
    + [Parameter(f"c{i}", "N s/m", f"unit {i} viscous damping") for i in range(1, UNITS + 1)]
    + [Parameter(f"m{i}", "kg", f"unit {i} mass", "mass_share") for i in range(1, UNITS)]
    + [Parameter(f"m{UNITS}", "kg", f"unit {UNITS} mass: the rest of the ball mass", "mass_rest")]
)


def split(p, mass):
    q = jnp.stack([p[0:3], p[3:6], p[6:9]], axis=1)  # rows (k_i, alpha_i, c_i)
    return q, p[9:12]


def bounds(scale):
    result = {}
    for i in range(1, UNITS + 1):
        result[f"k{i}"] = (0.02 * scale.peak_force_n, 2.0 * scale.peak_force_n)
        result[f"alpha{i}"] = (1.0, 2.5)
        result[f"c{i}"] = (0.0, scale.force_per_speed_n_s_m)
    for i in range(1, UNITS):
        result[f"m{i}"] = (0.05, 0.9)  # share of the mass still to give out
    return result


def validate(params):
    for i in range(1, UNITS + 1):
        check_range(f"params.k{i}", params[f"k{i}"], 0.0, low_open=True)
        check_range(f"params.alpha{i}", params[f"alpha{i}"], 0.5, 5.0)
        check_range(f"params.c{i}", params[f"c{i}"], 0.0)
        check_range(f"params.m{i}", params[f"m{i}"], 0.0, low_open=True, unit="kg",
                    note="a unit mass")


class _ThreeElement(OdeModel):
    def ball_mass_kg(self, params, mass_kg):
        total = sum(float(params[f"m{i}"]) for i in range(1, UNITS + 1))
        if mass_kg is not None and abs(total - mass_kg) > 5e-3 * mass_kg:
            raise InputError(
                f"params.m1..m{UNITS}: unit masses add up to {total:.6g} kg, not the ball mass "
                f"mass_kg = {mass_kg:.6g} kg (allowed 0.5%)"
            )
        return total


MODEL = _ThreeElement(
    name="three_element",
    summary="three nonlinear spring-damper units with their own masses, in parallel (thesis 4.3)",
    parameters=PARAMETERS,
    bounds=bounds,
    split=split,
    force=force,
    validate=validate,
)
