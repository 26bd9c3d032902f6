"""Ogden hyperfoam (thesis eq. 5-11):

    W = sum_i 2 mu_i / alpha_i^2 [ l1^a_i + l2^a_i + l3^a_i - 3 + (J^(-a_i b_i) - 1) / b_i ],

b_i = nu_i / (1 - 2 nu_i), mu0 = sum mu_i, K0 = sum 2 mu_i (1/3 + b_i). For b_i = 0 the last term is
its limit -a_i ln J. The whole stress relaxes with the Prony g_i (no deviatoric split exists).

Principal stretches: for states in which the third axis is principal (C13 = C23 = 0 given as
floats: axisymmetric and material-point states) the sum of l^a is computed from C directly; for a
general C (3D) from its eigenvalues (`spectral.trace_power`). In the first case the in-plane
pair enters through an expression that is even in the eigenvalue gap, with its Taylor series near
equal stretches, so that the stress and its derivatives are finite at the undeformed state (where
differentiating an eigendecomposition is singular).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from ..errors import InputError
from .fastmath import power
from ..checks import check_keys, check_range, spec_number
from .base import Array, Material, register_constants
from .spectral import trace_power

_SERIES_BELOW = 1e-3  # (gap / mean)^2 below which the 4-term series is exact to ~1e-12


@dataclass(frozen=True)
class HyperfoamTerm:
    mu_pa: float
    alpha: float
    beta: float

    @property
    def nu(self) -> float:
        return self.beta / (1.0 + 2.0 * self.beta)


def _pair_power_sum(m, d2, p):
    """(m + d)^p + (m - d)^p with d = sqrt(d2), smooth in d2 >= 0."""
    x = d2 / (m * m)
    series = 1.0 + x * (p * (p - 1) / 2 + x * (p * (p - 1) * (p - 2) * (p - 3) / 24
                        + x * p * (p - 1) * (p - 2) * (p - 3) * (p - 4) * (p - 5) / 720))
    x_safe = jnp.where(x < _SERIES_BELOW, _SERIES_BELOW, x)  # keep the unused branch's grad finite
    root = jnp.sqrt(x_safe)
    closed = 0.5 * (power(1.0 + root, p) + power(jnp.abs(1.0 - root) + 1e-300, p))
    return 2.0 * power(m, p) * jnp.where(x < _SERIES_BELOW, series, closed)


def principal_power_sum(C, p):
    """sum_a lambda_a^(2 p) for a right Cauchy-Green C (`Sym`)."""
    if not isinstance(C.yz, float):
        return trace_power(tuple(C), p)
    m = 0.5 * (C.xx + C.yy)
    d2 = 0.25 * (C.xx - C.yy) ** 2 + C.xy * C.xy
    return _pair_power_sum(m, d2, p) + power(C.zz, p)


@register_constants
class OgdenHyperfoamConstants(NamedTuple):
    """Instantaneous constants of the hyperfoam energy, one entry per term: exponents `alpha`,
    compressibility `beta` and moduli `mu_pa` (Pa)."""

    alpha: Array
    beta: Array
    mu_pa: Array


@dataclass(frozen=True)
class OgdenHyperfoam(Material):
    terms: tuple[HyperfoamTerm, ...]

    model = "ogden_hyperfoam"
    keys = ("terms",)
    Constants = OgdenHyperfoamConstants
    relax_whole_stress = True

    def __post_init__(self) -> None:
        super().__post_init__()
        if not self.terms:
            raise InputError("ogden_hyperfoam.terms: at least one term is needed")
        check_range("ogden_hyperfoam.terms: sum of mu_pa", sum(t.mu_pa for t in self.terms), 0.0,
                    low_open=True, unit="Pa", note="initial shear modulus")

    def given_moduli_pa(self) -> tuple[float, float]:
        mu0 = sum(t.mu_pa for t in self.terms)
        return mu0, sum(2.0 * t.mu_pa * (1.0 / 3.0 + t.beta) for t in self.terms)

    def hyperelastic_constants(self) -> OgdenHyperfoamConstants:
        f = self.deviatoric_factor()
        return OgdenHyperfoamConstants(alpha=np.array([t.alpha for t in self.terms]),
                                       beta=np.array([t.beta for t in self.terms]),
                                       mu_pa=np.array([t.mu_pa * f for t in self.terms]))

    @staticmethod
    def energy(C, c):
        J = jnp.sqrt(C.det())
        log_j = jnp.log(J)
        mu, alpha, beta = c.mu_pa, c.alpha, c.beta
        w = 0.0
        for i in range(alpha.shape[0]):  # terms (a static count)
            a, b = alpha[i], beta[i]
            stretch = principal_power_sum(C, a / 2.0)
            b_safe = jnp.where(b == 0.0, 1.0, b)
            volume = jnp.where(b == 0.0, -a * log_j, jnp.expm1(-a * b_safe * log_j) / b_safe)
            w = w + 2.0 * mu[i] / a ** 2 * (stretch - 3.0 + volume)
        return w, jnp.zeros_like(w)

    @classmethod
    def _from_keys(cls, d, where, **common):
        raw = d.get("terms")
        if not isinstance(raw, list) or not raw:
            raise InputError(f"{where}.terms: expected a non-empty list of {{mu_pa, alpha, nu|beta}}")
        terms = []
        for i, t in enumerate(raw):
            w = f"{where}.terms[{i}]"
            check_keys(t, {"mu_pa", "alpha", "nu", "beta"}, w)
            mu = spec_number(t, "mu_pa", w)
            alpha = spec_number(t, "alpha", w)
            if alpha == 0.0 or mu * alpha <= 0.0:
                raise InputError(f"{w}: need alpha != 0 and mu_pa * alpha > 0")
            if ("nu" in t) == ("beta" in t):
                raise InputError(f"{w}: give exactly one of 'nu' or 'beta'")
            if "nu" in t:
                nu = spec_number(t, "nu", w, -1.0, 0.5, True, True)
                beta = nu / (1.0 - 2.0 * nu)
            else:
                beta = spec_number(t, "beta", w, -1.0 / 3.0, low_open=True)
            terms.append(HyperfoamTerm(mu_pa=mu, alpha=alpha, beta=beta))
        return cls(terms=tuple(terms), **common)

    def _keys_dict(self):
        return {"terms": [{"mu_pa": t.mu_pa, "alpha": t.alpha, "nu": t.nu} for t in self.terms]}
