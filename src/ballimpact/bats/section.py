"""A bat's cross-section at any x: area, second moment of area (bending in the plane of the
swing), and the shear coefficient of Timoshenko's beam theory.

Round part (x up to the blade's start, or the whole bat): a solid circle, or a tube of constant
wall. Blade: a rectangle `width_m` wide and `thickness` deep, bending about the width's axis
(the ball hits the face, the deflection is through the thickness).

Shear coefficients (Cowper 1966, "The shear coefficient in Timoshenko's beam theory",
J. Appl. Mech. 33:335-340, table 1), with nu the material's Poisson's ratio (0.3 when only the
shear modulus is given, as for wood):

- hollow circle, m = inner/outer radius:
  k = 6(1+nu)(1+m^2)^2 / [(7+6nu)(1+m^2)^2 + (20+12nu)m^2];
  solid circle (m = 0) 6(1+nu)/(7+6nu) = 0.886 at nu = 0.3 (the 0.9 often quoted), thin tube
  (m -> 1) 2(1+nu)/(4+3nu) = 0.530 at nu = 0.3 (-> 0.5 as nu -> 0);
- rectangle: k = 10(1+nu)/(12+11nu) = 0.850 at nu = 0.3.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .spec import BatSpec

#: Poisson's ratio used in the shear coefficient when the material gives only G (wood)
DEFAULT_NU_FOR_SHEAR = 0.3


@dataclass(frozen=True)
class Sections:
    """Section properties at points x (arrays of x's shape): area A (m^2), second moment I
    (m^4), shear coefficient k; with E, G, density: rho A (kg/m), rho I (kg m), EI, kGA."""

    x_m: np.ndarray
    area_m2: np.ndarray
    second_moment_m4: np.ndarray
    shear_coefficient: np.ndarray
    youngs_modulus_pa: float
    shear_modulus_pa: float
    density_kg_m3: float

    @property
    def mass_per_length_kg_m(self) -> np.ndarray:
        return self.density_kg_m3 * self.area_m2

    @property
    def rotary_inertia_kg_m(self) -> np.ndarray:
        """rho I per unit length (kg m): the section's own moment of inertia per length."""
        return self.density_kg_m3 * self.second_moment_m4

    @property
    def bending_stiffness_n_m2(self) -> np.ndarray:
        return self.youngs_modulus_pa * self.second_moment_m4

    @property
    def shear_stiffness_n(self) -> np.ndarray:
        return self.shear_coefficient * self.shear_modulus_pa * self.area_m2


def poisson_for_shear(bat: BatSpec) -> float:
    nu = bat.material.poissons_ratio
    return DEFAULT_NU_FOR_SHEAR if nu is None else nu


def cowper_circle(nu: float, m: np.ndarray | float = 0.0) -> np.ndarray:
    """Cowper's shear coefficient of a hollow circle (m = inner / outer radius; 0: solid)."""
    m2 = np.asarray(m, dtype=float) ** 2
    a = (1.0 + m2) ** 2
    return 6.0 * (1.0 + nu) * a / ((7.0 + 6.0 * nu) * a + (20.0 + 12.0 * nu) * m2)


def cowper_rectangle(nu: float) -> float:
    """Cowper's shear coefficient of a rectangle."""
    return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)


def outer_radius_m(bat: BatSpec, x_m) -> np.ndarray:
    """The round profile's outer radius at x (linear between points; held past its ends)."""
    xs, rs = np.array(bat.profile).T
    return np.interp(np.asarray(x_m, dtype=float), xs, rs)


def sections(bat: BatSpec, x_m) -> Sections:
    """Section properties at the points `x_m` (the blade's from its first x on)."""
    x = np.atleast_1d(np.asarray(x_m, dtype=float))
    nu = poisson_for_shear(bat)
    r = outer_radius_m(bat, x)
    if bat.wall_thickness_m is None:
        ri = np.zeros_like(r)
    else:
        ri = r - bat.wall_thickness_m
    area = np.pi * (r ** 2 - ri ** 2)
    second = np.pi * (r ** 4 - ri ** 4) / 4.0
    k = cowper_circle(nu, ri / r)
    if bat.blade is not None:
        on_blade = x >= bat.blade.start_m
        xb, tb = np.array(bat.blade.profile_thickness).T
        t = np.interp(x, xb, tb)
        w = bat.blade.width_m
        area = np.where(on_blade, w * t, area)
        second = np.where(on_blade, w * t ** 3 / 12.0, second)
        k = np.where(on_blade, cowper_rectangle(nu), k)
    m = bat.material
    return Sections(x, area, second, np.broadcast_to(k, x.shape).astype(float),
                    m.youngs_modulus_pa, m.shear_modulus_pa, m.density_kg_m3)
