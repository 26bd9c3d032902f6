"""A bat's rigid-body properties from its profile: mass, centre of mass, and the moment of
inertia about a transverse axis (the swing's) through the knob end and through the centre of
mass.

Exact for the profiles a bat is given by: between breakpoints the radius (or the blade's
thickness) is linear in x, so the mass per length rho A(x) and the section's own rotary inertia
rho I(x) are polynomials of degree 4 at most, and x^2 rho A(x) of degree 6 at most: 4-point
Gauss-Legendre on each segment (exact to degree 7) integrates them exactly.

The moment of inertia includes the sections' own rotary inertia, integral of rho I dx (a solid
cylinder about its end: m (L^2/3 + R^2/4)), as the beam's mass matrix does.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .section import sections
from .spec import BatSpec, load_bat

_GAUSS_POINTS, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(4)


@dataclass(frozen=True)
class BatProperties:
    """Mass (kg), centre of mass from the knob end (m), moments of inertia (kg m^2) about a
    transverse axis through the knob end and through the centre of mass."""

    mass_kg: float
    centre_of_mass_m: float
    moi_knob_kg_m2: float
    moi_cm_kg_m2: float

    def moi_about_kg_m2(self, x_m: float) -> float:
        """Moment of inertia about a transverse axis at x (parallel axis theorem)."""
        return self.moi_cm_kg_m2 + self.mass_kg * (x_m - self.centre_of_mass_m) ** 2

    def to_dict(self) -> dict[str, float]:
        return {"mass_kg": self.mass_kg, "centre_of_mass_m": self.centre_of_mass_m,
                "moi_knob_kg_m2": self.moi_knob_kg_m2, "moi_cm_kg_m2": self.moi_cm_kg_m2}


def quadrature(bat: BatSpec) -> tuple[np.ndarray, np.ndarray]:
    """Points and weights integrating the bat's section properties exactly along x."""
    edges = np.array(bat.breakpoints_m())
    a, b = edges[:-1, None], edges[1:, None]
    x = (a + b) / 2.0 + (b - a) / 2.0 * _GAUSS_POINTS
    w = (b - a) / 2.0 * _GAUSS_WEIGHTS
    return x.ravel(), np.broadcast_to(w, x.shape).ravel()


def bat_properties(bat) -> BatProperties:
    """Mass, centre of mass and moments of inertia of a bat (anything `load_bat` takes)."""
    bat = load_bat(bat)
    x, w = quadrature(bat)
    s = sections(bat, x)
    mu, rot = s.mass_per_length_kg_m, s.rotary_inertia_kg_m
    mass = float(np.sum(w * mu))
    cm = float(np.sum(w * mu * x)) / mass
    knob = float(np.sum(w * (mu * x ** 2 + rot)))
    return BatProperties(mass, cm, knob, knob - mass * cm ** 2)
