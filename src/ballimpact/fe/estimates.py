"""Hertz estimates of a ball's impact that set up a run of either engine: the contact time and
radius expected, and the default time limit (SI)."""

from __future__ import annotations

import numpy as np

from ..closedform import hertz_impact


def hertz_contact_time_s(ball, speed: float) -> float:
    """Contact time of a Hertz sphere with the ball's softest long-term Young's modulus and
    nu = 0.5: longer than the ball's (the longest plausible contact)."""
    e_min = min(9 * m.bulk_modulus_pa(False) * m.shear_modulus_pa(False)
                / (3 * m.bulk_modulus_pa(False) + m.shear_modulus_pa(False))
                for m in (layer.material for layer in ball.layers))
    return hertz_impact(e_min, 0.5, ball.outer_radius_m, ball.mass_kg, speed)[2]


def hertz_contact_radius_m(ball, speed: float) -> float:
    """Contact radius sqrt(R y_max) on a rigid plane of a Hertz sphere with the smallest
    long-term plane-strain modulus E* = E / (1 - nu^2) of the ball's layers (the softest layer
    gives the widest patch; exact for a homogeneous linear ball)."""
    return float(np.sqrt(ball.outer_radius_m * hertz_series_impact(ball, speed)[0]))


def hertz_series_impact(ball, speed: float, target_materials=()) -> tuple[float, float, float]:
    """`hertz_impact` (max compression m, peak force N, contact time s) of the ball's softest
    long-term plane-strain modulus in series with the softest of `target_materials`."""
    def plane_strain_pa(m) -> float:
        k, mu = m.bulk_modulus_pa(False), m.shear_modulus_pa(False)
        return 4.0 * mu * (3.0 * k + mu) / (3.0 * k + 4.0 * mu)  # E / (1 - nu^2)

    compliance = 1.0 / min(plane_strain_pa(layer.material) for layer in ball.layers)
    if target_materials:
        compliance += 1.0 / min(plane_strain_pa(m) for m in target_materials)
    return hertz_impact(1.0 / compliance, 0.0, ball.outer_radius_m, ball.mass_kg, speed)


def time_limit_default(ball, speed: float) -> float:
    """6 times `hertz_contact_time_s`."""
    return 6.0 * hertz_contact_time_s(ball, speed)
