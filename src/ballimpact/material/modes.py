"""Nominal (first Piola-Kirchhoff) stresses of the material-test deformations, from the very strain
energies the FE ball uses (`constitutive`, `MATERIALS[model].energy(C, constants)`).

Rubber laws (neo-Hookean, Mooney-Rivlin, Yeoh, Ogden) are fitted as incompressible, as ABAQUS
fits test data: only their deviatoric energy W(l1, l2, l3) enters, on isochoric principal
stretches, and the pressure is eliminated by the traction-free direction. With l3 = 1 / (l1 l2)
and W~(l1, l2) = W(l1, l2, 1 / (l1 l2)) the nominal stresses are

    uniaxial     (l, l^-1/2, l^-1/2):  P = dW(l, l^-1/2, l^-1/2) / dl
    equibiaxial  (l, l, l^-2):         P = 1/2 dW(l, l, l^-2) / dl
    planar       (l, 1, 1/l):          P = dW(l, 1, 1/l) / dl   (along the stretched axis)
    biaxial      (l1, l2, 1/(l1 l2)):  P1 = dW~/dl1, P2 = dW~/dl2

(derivatives by JAX). A volumetric test gives the pressure p = -dW(J^1/3, J^1/3, J^1/3) / dJ of
the full energy: for the rubber laws their volumetric part K (J - 1)^2 / 2, i.e. p = K (1 - J).

Ogden hyperfoam is compressible: its full energy is used, P_i = dW / dl_i, with the free
stretches from zero stress across them (uniaxial: the two lateral stretches, equal; biaxial and
planar: the thickness stretch) by Newton's method per point in the logarithm of that stretch.

Stresses are in Pa; `constants` are what `Material.hyperelastic_constants()` returns (the
instantaneous constants of the energy, the model's typed `Constants`), or a dict of the same
fields (fits build and differentiate those).
"""

from __future__ import annotations

from functools import partial

import jax
import jax.numpy as jnp
import numpy as np

from ..errors import InputError
from ..constitutive import MATERIALS, Material
from ..constitutive.base import Sym

#: deformations of the stress tests
DEFORMATIONS = ("uniaxial", "equibiaxial", "biaxial", "planar", "volumetric")
#: models whose energies are fitted as incompressible (deviatoric part only; the bulk modulus, if
#: fitted, from volumetric data alone)
INCOMPRESSIBLE = ("neo_hookean", "mooney_rivlin", "yeoh", "ogden")
COMPRESSIBLE = ("ogden_hyperfoam",)
#: Newton iterations for the free stretch of a compressible state (quadratic convergence from
#: ln(stretch) = 0; the step is limited to 0.5 in ln(stretch), so 60 cover stretches e^-30..e^30)
_NEWTON_STEPS = 60
_MAX_LOG_STEP = 0.5


def _diag(l1, l2, l3) -> Sym:
    # principal axes along x, y, z; xy is an array so that every component has the point shape
    return Sym(l1 * l1, l2 * l2, l3 * l3, jnp.zeros_like(l1 * l2 * l3))


def typed_constants(model: str, constants):
    """A model's constants as its `Constants` NamedTuple (a dict of the same keys converted):
    the jitted stresses then see one container type and compile once per model."""
    typed = MATERIALS[model].Constants
    return constants if isinstance(constants, typed) else typed(**constants)


def _point_energy(model: str, constants, l1, l2, l3, full: bool):
    w_dev, w_vol = MATERIALS[model].energy(_diag(l1, l2, l3), constants)
    return w_dev + w_vol if full else w_dev


def _sum_grad(f, argnum):
    """Pointwise derivative of a pointwise function: the gradient of its sum."""
    return jax.grad(lambda *a: jnp.sum(f(*a)), argnums=argnum)


@partial(jax.jit, static_argnames=("model", "deformation"))
def incompressible_stress(model: str, constants, deformation: str, x1, x2=None):
    """Nominal stress (Pa) of an incompressible `deformation` at stretch x1 (and x2 for biaxial:
    returns (P1, P2) stacked on the last axis); volumetric: pressure at volume ratio x1."""
    def w(l1, l2):
        return _point_energy(model, constants, l1, l2, 1.0 / (l1 * l2), False)

    if deformation == "uniaxial":
        return _sum_grad(lambda l: w(l, l ** -0.5), 0)(x1)
    if deformation == "equibiaxial":
        return 0.5 * _sum_grad(lambda l: w(l, l), 0)(x1)
    if deformation == "planar":
        return _sum_grad(lambda l: w(l, jnp.ones_like(l)), 0)(x1)
    if deformation == "biaxial":
        return jnp.stack([_sum_grad(w, 0)(x1, x2), _sum_grad(w, 1)(x1, x2)], axis=-1)
    if deformation == "volumetric":
        return _pressure(model, constants, x1)
    raise ValueError(deformation)


def _pressure(model, constants, j):
    def wj(v):
        s = v ** (1.0 / 3.0)
        return _point_energy(model, constants, s, s, s, True)
    return -_sum_grad(wj, 0)(j)


@partial(jax.jit, static_argnames=("model", "deformation"))
def compressible_stress(model: str, constants, deformation: str, x1, x2=None):
    """Nominal stress (Pa) of a compressible material (full energy), the free stretch from zero
    stress across it; returns (stress, free stretch). Biaxial: stress (P1, P2) on the last axis.
    Volumetric: (pressure, volume ratio^(1/3))."""
    if deformation == "volumetric":
        return _pressure(model, constants, x1), x1 ** (1.0 / 3.0)

    def w(a, b, c):
        return _point_energy(model, constants, a, b, c, True)

    if deformation == "uniaxial":
        def state(t):
            return x1, t, t
        # lateral stress: dW/dl2 at l2 = l3 = t (both lateral faces free, equal by symmetry)
        free_axis = 1
    else:
        other = {"equibiaxial": x1, "planar": jnp.ones_like(x1), "biaxial": x2}[deformation]

        def state(t):
            return x1, other, t
        free_axis = 2

    def free_stress(u):  # nominal stress across the free axis at stretch exp(u)
        return _sum_grad(w, free_axis)(*state(jnp.exp(u)))

    def newton(u, _):
        value, slope = jax.jvp(free_stress, (u,), (jnp.ones_like(u),))
        step = jnp.clip(-value / jnp.where(slope == 0.0, 1.0, slope), -_MAX_LOG_STEP, _MAX_LOG_STEP)
        return u + jnp.where(slope == 0.0, 0.0, step), None

    # differentiable through the iterations: a fit's Jacobian needs d(free stretch)/d(constants)
    u, _ = jax.lax.scan(newton, jnp.zeros_like(x1), None, length=_NEWTON_STEPS)
    t = jnp.exp(u)
    p1 = _sum_grad(w, 0)(*state(t))
    if deformation == "biaxial":
        return jnp.stack([p1, _sum_grad(w, 1)(*state(t))], axis=-1), t
    return p1, t


def deformation_stress(model: str, constants, deformation: str, x1, x2=None) -> np.ndarray:
    """Nominal stress (Pa) of `deformation` for a model's energy and constants (numpy out)."""
    if deformation not in DEFORMATIONS:
        raise InputError(f"deformation = {deformation!r}: allowed {', '.join(DEFORMATIONS)}")
    with jax.enable_x64(True):  # float64 here only, as the rest of the package
        x1 = jnp.asarray(x1, dtype=jnp.float64)
        x2 = None if x2 is None else jnp.asarray(x2, dtype=jnp.float64)
        if model in COMPRESSIBLE or model in INCOMPRESSIBLE:
            constants = typed_constants(model, constants)
        if model in COMPRESSIBLE:
            return np.asarray(compressible_stress(model, constants, deformation, x1, x2)[0])
        if model in INCOMPRESSIBLE:
            return np.asarray(incompressible_stress(model, constants, deformation, x1, x2))
    raise InputError(f"model = {model!r}: test stresses are computed for "
                     f"{', '.join(INCOMPRESSIBLE + COMPRESSIBLE)}")


def free_stretch(material: Material, deformation: str, x1, x2=None) -> np.ndarray:
    """The free stretch of a compressible material's test (uniaxial: lateral; biaxial and planar:
    thickness), from zero stress across it."""
    with jax.enable_x64(True):
        x1 = jnp.asarray(x1, dtype=jnp.float64)
        x2 = None if x2 is None else jnp.asarray(x2, dtype=jnp.float64)
        constants = material.hyperelastic_constants()
        return np.asarray(compressible_stress(material.model, constants, deformation, x1, x2)[1])


def material_stress(material: Material, deformation: str, x1, x2=None, *,
                    long_term: bool = True) -> np.ndarray:
    """Nominal stress (Pa) of a material's test: the long-term (relaxed, quasi-static) response by
    default, the instantaneous one with long_term=False. The energy is linear in the stress, so
    the long-term stress is the instantaneous relaxing part times (1 - sum g) plus the volumetric
    part times (1 - sum k) (hyperfoam: the whole stress times (1 - sum g))."""
    constants = material.hyperelastic_constants()
    if not long_term or not material.prony:
        return deformation_stress(material.model, constants, deformation, x1, x2)
    if material.model in COMPRESSIBLE:
        # the whole energy relaxes with g: the same material with long-term constants
        scaled = constants._replace(mu_pa=np.asarray(constants.mu_pa) * (1.0 - material.sum_g))
        return deformation_stress(material.model, scaled, deformation, x1, x2)
    if deformation == "volumetric":  # only the volumetric part acts (isochoric invariants = 3)
        return deformation_stress(material.model, constants, deformation, x1) \
            * (1.0 - material.sum_bulk_relaxation)
    return deformation_stress(material.model, constants, deformation, x1, x2) \
        * (1.0 - material.sum_g)


def confined_stress(material: Material, stretch) -> np.ndarray:
    """Nominal stress (Pa, along the stretch) of confined compression (uniaxial strain: the
    lateral stretches held at 1, as in a thin bonded layer), from the instantaneous energy of a
    compressible material (`COMPRESSIBLE`). For a hyperfoam whose terms all have nu = 0 it is
    the uniaxial stress as well (no lateral stress arises)."""
    if material.model not in COMPRESSIBLE:
        raise InputError(f"model = {material.model!r}: confined compression is computed for "
                         f"{', '.join(COMPRESSIBLE)}")
    with jax.enable_x64(True):
        x = jnp.asarray(stretch, dtype=jnp.float64)
        constants = material.hyperelastic_constants()
        one = jnp.ones_like(x)
        return np.asarray(_sum_grad(lambda l: _point_energy(material.model, constants, one, one,
                                                            l, True), 0)(x))


__all__ = ["COMPRESSIBLE", "DEFORMATIONS", "INCOMPRESSIBLE", "compressible_stress",
           "confined_stress", "deformation_stress", "free_stretch", "incompressible_stress",
           "material_stress"]


@partial(jax.jit, static_argnames=("model", "deformation"))
def _term_stresses(model, deformation, mu, alpha, beta, x1, x2):
    def one(m, a, b):
        c = typed_constants(model, {"mu_pa": m[None], "alpha": a[None],
                                    **({"k_pa": 0.0} if b is None else {"beta": b[None]})})
        if model in COMPRESSIBLE:
            return jnp.ravel(compressible_stress(model, c, deformation, x1, x2)[0])
        return jnp.ravel(incompressible_stress(model, c, deformation, x1, x2))
    return jax.vmap(one)(mu, alpha, beta)


@partial(jax.jit, static_argnames=("model", "deformations"))
def _all_term_stresses(model, deformations, mu, alpha, beta, xs):
    return jnp.concatenate([_term_stresses(model, d, mu, alpha, beta, x1, x2)
                            for d, (x1, x2) in zip(deformations, xs)], axis=1)


def term_stresses(model: str, deformations: tuple[str, ...], mu, alpha, beta,
                  xs: tuple) -> np.ndarray:
    """Stress of each Ogden (hyperfoam) term alone over several tests, shape (terms, values): the
    columns of the linear problem in mu at fixed exponents (beta None for ogden). `xs` holds each
    test's (x1, x2 or None); one compiled call for all of them (fits call this often)."""
    with jax.enable_x64(True):
        xs = tuple((jnp.asarray(x1, jnp.float64),
                    None if x2 is None else jnp.asarray(x2, jnp.float64)) for x1, x2 in xs)
        mu, alpha = jnp.asarray(mu, jnp.float64), jnp.asarray(alpha, jnp.float64)
        beta = None if beta is None else jnp.asarray(beta, jnp.float64)
        return np.asarray(_all_term_stresses(model, tuple(deformations), mu, alpha, beta, xs))
