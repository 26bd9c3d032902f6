"""Linear elastic, extended to finite rotations (Saint Venant-Kirchhoff): S = lambda tr(E) I + 2 mu E.

Meant for small-strain checks (Hertz). Its relaxing part is the deviatoric 2 mu dev(E), its
volumetric part K tr(E) I.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from ..checks import spec_number
from .base import Array, Material, Sym, register_constants


@register_constants
class LinearElasticConstants(NamedTuple):
    """Instantaneous shear and bulk moduli of the linear elastic energy (Pa)."""

    k_pa: Array
    mu_pa: Array


@dataclass(frozen=True)
class LinearElastic(Material):
    youngs_modulus_pa: float
    poissons_ratio: float

    model = "linear_elastic"
    keys = ("youngs_modulus_pa", "poissons_ratio")
    Constants = LinearElasticConstants

    def given_moduli_pa(self) -> tuple[float, float]:
        e, nu = self.youngs_modulus_pa, self.poissons_ratio
        return e / (2.0 * (1.0 + nu)), e / (3.0 * (1.0 - 2.0 * nu))

    def hyperelastic_constants(self) -> LinearElasticConstants:
        mu, k = self.given_moduli_pa()
        return LinearElasticConstants(k_pa=k * self.volumetric_factor(),
                                      mu_pa=mu * self.deviatoric_factor())

    @staticmethod
    def energy(C, c):
        E = Sym(0.5 * (C.xx - 1.0), 0.5 * (C.yy - 1.0), 0.5 * (C.zz - 1.0),
                0.5 * C.xy, 0.5 * C.yz, 0.5 * C.zx)
        tr = E.trace()
        dev = E._replace(xx=E.xx - tr / 3.0, yy=E.yy - tr / 3.0, zz=E.zz - tr / 3.0)
        return c.mu_pa * dev.double_dot(dev), 0.5 * c.k_pa * tr * tr

    @classmethod
    def _from_keys(cls, d, where, **common):
        return cls(youngs_modulus_pa=spec_number(d, "youngs_modulus_pa", where, 0.0, low_open=True),
                   poissons_ratio=spec_number(d, "poissons_ratio", where, -1.0, 0.5, True, True),
                   **common)

    def _keys_dict(self):
        return {"youngs_modulus_pa": self.youngs_modulus_pa, "poissons_ratio": self.poissons_ratio}
