"""Ogden rubber (nearly incompressible; ABAQUS's and CalculiX's `*HYPERELASTIC, OGDEN`):

    W = sum_i 2 mu_i / alpha_i^2 (lbar1^a_i + lbar2^a_i + lbar3^a_i - 3) + K/2 (J - 1)^2,

with the isochoric stretches lbar = J^(-1/3) lambda, 1 to 6 terms. mu0 = sum mu_i > 0 and every
alpha_i != 0; as in ABAQUS, a term may have a negative mu_i (as Mooney-Rivlin's C01 may be
negative): such sets can be Drucker-unstable at large stretches, which `stability` reports. In
this form (2 mu_i / alpha_i^2, i.e. Ogden's mu_p / alpha_p with mu_p = 2 mu_i / alpha_i) Ogden's
sufficient condition for stability, mu_p alpha_p > 0, is mu_i > 0 for every term: the condition
`material fit` keeps. D1 = 0 means K0 = 20 mu0 (`base.bulk_from_d1`). One term with alpha = 2
is neo-Hookean with C10 = mu / 2.

The sum of lbar^a is the hyperfoam's `principal_power_sum` of Cbar = J^(-2/3) C: the direct
(axisymmetric, material-point) and eigenvalue (3D, custom derivative) paths are shared with it,
so the stress is finite at the undeformed state in both.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from ..errors import InputError
from .fastmath import cube_root
from ..checks import check_keys, check_range, spec_number
from .base import Array, Material, Sym, bulk_from_d1, register_constants
from .ogden_hyperfoam import principal_power_sum

MAX_TERMS = 6  # as ABAQUS's N


@dataclass(frozen=True)
class OgdenTerm:
    mu_pa: float
    alpha: float


@register_constants
class OgdenConstants(NamedTuple):
    """Instantaneous constants of the Ogden energy: the terms' exponents `alpha` and moduli
    `mu_pa` (Pa), one entry per term, and the bulk modulus `k_pa` (Pa)."""

    alpha: Array
    k_pa: Array
    mu_pa: Array


@dataclass(frozen=True)
class Ogden(Material):
    terms: tuple[OgdenTerm, ...]
    d1_per_pa: float = 0.0

    model = "ogden"
    keys = ("terms", "d1_per_pa")
    Constants = OgdenConstants

    def __post_init__(self) -> None:
        super().__post_init__()
        object.__setattr__(self, "terms", tuple(self.terms))
        if not 1 <= len(self.terms) <= MAX_TERMS:
            raise InputError(f"{self.model}.terms: 1 to {MAX_TERMS} terms, got {len(self.terms)}")
        for i, t in enumerate(self.terms):
            if t.alpha == 0.0:
                raise InputError(f"{self.model}.terms[{i}].alpha: must not be 0")
        check_range(f"{self.model}.terms: sum of mu_pa", sum(t.mu_pa for t in self.terms), 0.0,
                    low_open=True, unit="Pa", note="initial shear modulus")
        check_range(f"{self.model}.d1_per_pa", self.d1_per_pa, 0.0, unit="1/Pa")

    def given_moduli_pa(self) -> tuple[float, float]:
        mu0 = sum(t.mu_pa for t in self.terms)
        return mu0, bulk_from_d1(self, self.d1_per_pa, mu0)

    def hyperelastic_constants(self) -> OgdenConstants:
        f = self.deviatoric_factor()
        return OgdenConstants(alpha=np.array([t.alpha for t in self.terms]),
                              k_pa=self.given_moduli_pa()[1] * self.volumetric_factor(),
                              mu_pa=np.array([t.mu_pa * f for t in self.terms]))

    @staticmethod
    def energy(C, c):
        det = C.det()
        scale = 1.0 / cube_root(det)  # J^(-2/3)
        # Cbar keeps the float zeros of an axisymmetric C (so the direct path is taken)
        cbar = Sym(*(v if isinstance(v, float) else scale * v for v in C))
        mu, alpha = c.mu_pa, c.alpha
        w = 0.0
        for i in range(alpha.shape[0]):  # terms (a static count)
            a = alpha[i]
            w = w + 2.0 * mu[i] / a ** 2 * (principal_power_sum(cbar, a / 2.0) - 3.0)
        return w, 0.5 * c.k_pa * (jnp.sqrt(det) - 1.0) ** 2

    @classmethod
    def _from_keys(cls, d, where, **common):
        raw = d.get("terms")
        if not isinstance(raw, list) or not 1 <= len(raw) <= MAX_TERMS:
            raise InputError(f"{where}.terms: expected a list of 1 to {MAX_TERMS} {{mu_pa, alpha}}")
        terms = []
        for i, t in enumerate(raw):
            w = f"{where}.terms[{i}]"
            check_keys(t, {"mu_pa", "alpha"}, w)
            mu = spec_number(t, "mu_pa", w)
            alpha = spec_number(t, "alpha", w)
            if alpha == 0.0:
                raise InputError(f"{w}.alpha: must not be 0")
            terms.append(OgdenTerm(mu_pa=mu, alpha=alpha))
        return cls(terms=tuple(terms),
                   d1_per_pa=spec_number({"d1_per_pa": 0.0, **d}, "d1_per_pa", where, 0.0), **common)

    def _keys_dict(self):
        return {"terms": [{"mu_pa": t.mu_pa, "alpha": t.alpha} for t in self.terms],
                "d1_per_pa": self.d1_per_pa}
