"""Neo-Hookean: W = C10 (I1bar - 3) + (J - 1)^2 / D1; D1 = 0 means K0 = 20 mu0, mu0 = 2 C10."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from ..checks import spec_number
from .base import Array, Material, bulk_from_d1, register_constants, isochoric_invariants


@register_constants
class NeoHookeanConstants(NamedTuple):
    """Instantaneous constants of the neo-Hookean energy (Pa)."""

    c10_pa: Array
    k_pa: Array


@dataclass(frozen=True)
class NeoHookean(Material):
    c10_pa: float
    d1_per_pa: float = 0.0

    model = "neo_hookean"
    keys = ("c10_pa", "d1_per_pa")
    Constants = NeoHookeanConstants

    def given_moduli_pa(self) -> tuple[float, float]:
        mu0 = 2.0 * self.c10_pa
        return mu0, bulk_from_d1(self, self.d1_per_pa, mu0)

    def hyperelastic_constants(self) -> NeoHookeanConstants:
        return NeoHookeanConstants(c10_pa=self.c10_pa * self.deviatoric_factor(),
                                   k_pa=self.given_moduli_pa()[1] * self.volumetric_factor())

    @staticmethod
    def energy(C, c):
        i1, _, J = isochoric_invariants(C)
        return c.c10_pa * (i1 - 3.0), 0.5 * c.k_pa * (J - 1.0) ** 2

    @classmethod
    def _from_keys(cls, d, where, **common):
        return cls(c10_pa=spec_number(d, "c10_pa", where, 0.0, low_open=True),
                   d1_per_pa=spec_number({"d1_per_pa": 0.0, **d}, "d1_per_pa", where, 0.0), **common)

    def _keys_dict(self):
        return {"c10_pa": self.c10_pa, "d1_per_pa": self.d1_per_pa}
