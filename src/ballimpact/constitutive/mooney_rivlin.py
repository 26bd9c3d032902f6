"""Mooney-Rivlin: W = C10 (I1bar - 3) + C01 (I2bar - 3) + (J - 1)^2 / D1 (thesis eq. 5-9, 6-1).

D1 = 0 ("incompressible", as in the thesis) is replaced by K0 = 20 mu0, mu0 = 2 (C10 + C01), as
ABAQUS/Explicit does. A negative C01 is allowed (the thesis' sets have one); check such sets with
`stability.mooney_rivlin_drucker`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from ..checks import check_range, spec_number
from .base import Array, Material, bulk_from_d1, register_constants, isochoric_invariants


@register_constants
class MooneyRivlinConstants(NamedTuple):
    """Instantaneous constants of the Mooney-Rivlin energy (Pa)."""

    c01_pa: Array
    c10_pa: Array
    k_pa: Array


@dataclass(frozen=True)
class MooneyRivlin(Material):
    c10_pa: float
    c01_pa: float
    d1_per_pa: float = 0.0

    model = "mooney_rivlin"
    keys = ("c10_pa", "c01_pa", "d1_per_pa")
    Constants = MooneyRivlinConstants

    def __post_init__(self) -> None:
        super().__post_init__()
        check_range(f"{self.model}: c10_pa + c01_pa", self.c10_pa + self.c01_pa, 0.0,
                    low_open=True, unit="Pa", note="initial shear modulus 2 (C10 + C01)")
        check_range(f"{self.model}.d1_per_pa", self.d1_per_pa, 0.0, unit="1/Pa")

    def given_moduli_pa(self) -> tuple[float, float]:
        mu0 = 2.0 * (self.c10_pa + self.c01_pa)
        return mu0, bulk_from_d1(self, self.d1_per_pa, mu0)

    def hyperelastic_constants(self) -> MooneyRivlinConstants:
        f = self.deviatoric_factor()
        return MooneyRivlinConstants(c01_pa=self.c01_pa * f, c10_pa=self.c10_pa * f,
                                     k_pa=self.given_moduli_pa()[1] * self.volumetric_factor())

    @staticmethod
    def energy(C, c):
        i1, i2, J = isochoric_invariants(C)
        return c.c10_pa * (i1 - 3.0) + c.c01_pa * (i2 - 3.0), 0.5 * c.k_pa * (J - 1.0) ** 2

    @classmethod
    def _from_keys(cls, d, where, **common):
        return cls(c10_pa=spec_number(d, "c10_pa", where), c01_pa=spec_number(d, "c01_pa", where),
                   d1_per_pa=spec_number({"d1_per_pa": 0.0, **d}, "d1_per_pa", where, 0.0), **common)

    def _keys_dict(self):
        return {"c10_pa": self.c10_pa, "c01_pa": self.c01_pa, "d1_per_pa": self.d1_per_pa}
