"""Yeoh: W = C10 (I1bar - 3) + C20 (I1bar - 3)^2 + C30 (I1bar - 3)^3 + K/2 (J - 1)^2.

The reduced polynomial of order 3 (ABAQUS's `*HYPERELASTIC, YEOH`); C20 = C30 = 0 is neo-Hookean.
mu0 = 2 C10 must be > 0; C20 and C30 may be negative (a negative C20 gives the softening at
moderate stretch seen in filled rubbers; check such sets with `stability.drucker_unstable`).
D1 = 0 means K0 = 20 mu0, as for the other rubber laws (`base.bulk_from_d1`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from ..checks import check_range, spec_number
from .base import Array, Material, bulk_from_d1, register_constants, isochoric_invariants


@register_constants
class YeohConstants(NamedTuple):
    """Instantaneous constants of the Yeoh energy (Pa)."""

    c10_pa: Array
    c20_pa: Array
    c30_pa: Array
    k_pa: Array


@dataclass(frozen=True)
class Yeoh(Material):
    c10_pa: float
    c20_pa: float = 0.0
    c30_pa: float = 0.0
    d1_per_pa: float = 0.0

    model = "yeoh"
    keys = ("c10_pa", "c20_pa", "c30_pa", "d1_per_pa")
    Constants = YeohConstants

    def __post_init__(self) -> None:
        super().__post_init__()
        check_range(f"{self.model}.c10_pa", self.c10_pa, 0.0, low_open=True, unit="Pa",
                    note="initial shear modulus 2 C10")
        check_range(f"{self.model}.d1_per_pa", self.d1_per_pa, 0.0, unit="1/Pa")

    def given_moduli_pa(self) -> tuple[float, float]:
        mu0 = 2.0 * self.c10_pa
        return mu0, bulk_from_d1(self, self.d1_per_pa, mu0)

    def hyperelastic_constants(self) -> YeohConstants:
        f = self.deviatoric_factor()
        return YeohConstants(c10_pa=self.c10_pa * f, c20_pa=self.c20_pa * f,
                             c30_pa=self.c30_pa * f,
                             k_pa=self.given_moduli_pa()[1] * self.volumetric_factor())

    @staticmethod
    def energy(C, c):
        i1, _, J = isochoric_invariants(C)
        x = i1 - 3.0
        w = x * (c.c10_pa + x * (c.c20_pa + x * c.c30_pa))  # Horner
        return w, 0.5 * c.k_pa * (J - 1.0) ** 2

    @classmethod
    def _from_keys(cls, d, where, **common):
        d0 = {"c20_pa": 0.0, "c30_pa": 0.0, "d1_per_pa": 0.0, **d}
        return cls(c10_pa=spec_number(d, "c10_pa", where, 0.0, low_open=True),
                   c20_pa=spec_number(d0, "c20_pa", where), c30_pa=spec_number(d0, "c30_pa", where),
                   d1_per_pa=spec_number(d0, "d1_per_pa", where, 0.0), **common)

    def _keys_dict(self):
        return {"c10_pa": self.c10_pa, "c20_pa": self.c20_pa, "c30_pa": self.c30_pa,
                "d1_per_pa": self.d1_per_pa}
