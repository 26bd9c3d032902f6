"""What every FE material has: a strain energy split into a relaxing and a volumetric part, an
optional Prony series, and the convention (`moduli`) in which its constants are given.

The solver works with instantaneous constants. A set given as `long_term` is scaled up: deviatoric
constants by 1 / (1 - sum g_i), the bulk modulus by 1 / (1 - sum k_i) (docs/fe.md "Materials").
Stresses are second Piola-Kirchhoff, S = 2 dW/dC, from the energy by automatic differentiation.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..checks import check_keys, spec_number
from ..errors import InputError
from .fastmath import cube_root

MODULI = ("long_term", "instantaneous")
#: an array of constants: NumPy (float64, built on the host) or JAX (in a kernel's precision)
Array = jax.Array | np.ndarray
INCOMPRESSIBLE_BULK_TO_SHEAR = 20.0  # D1 = 0: K0 = 20 mu0 (instantaneous), as ABAQUS/Explicit (nu 0.475)


@dataclass(frozen=True)
class PronyTerm:
    """One term of g_R(t) = 1 - sum g_i (1 - exp(-t / tau_i)) (and k_R likewise for the bulk)."""

    g: float
    k: float
    tau_s: float


def _prony_from(d: dict, where: str) -> tuple[PronyTerm, ...]:
    terms = d.get("prony", [])
    if not isinstance(terms, list):
        raise InputError(f"{where}.prony: expected a list of {{g, k, tau_s}}")
    out = []
    for i, t in enumerate(terms):
        w = f"{where}.prony[{i}]"
        check_keys(t, {"g", "k", "tau_s"}, w)
        out.append(PronyTerm(g=spec_number(t, "g", w, 0.0, 1.0, high_open=True),
                             k=spec_number({"k": 0.0, **t}, "k", w, 0.0, 1.0, high_open=True),
                             tau_s=spec_number(t, "tau_s", w, 0.0, low_open=True)))
    if sum(t.g for t in out) >= 1.0:
        raise InputError(f"{where}.prony: sum of g must be < 1, got {sum(t.g for t in out):g}")
    if sum(t.k for t in out) >= 1.0:
        raise InputError(f"{where}.prony: sum of k must be < 1, got {sum(t.k for t in out):g}")
    return tuple(out)


def register_constants(cls: type) -> type:
    """Register a model's typed constants (a NamedTuple with its fields in alphabetical order,
    as the dict it replaced flattened) with `jax.export`: the FE programs kept on disk
    (`fe.programs`) serialize their arguments' structure."""
    jax.export.register_namedtuple_serialization(cls, serialized_name=f"ballimpact.{cls.__name__}")
    return cls


@register_constants
class MaterialConstants(NamedTuple):
    """What the FE kernels need of one material (SI, instantaneous moduli): the constants of its
    energy (`hyperelastic`, the model's own `Material.Constants`), its Prony terms (`prony_g`,
    `prony_k`, `prony_tau_s` in s; one entry per term) and its initial shear and bulk moduli
    (Pa; the energy held in the Maxwell branches is measured against them). A pytree that
    stacks for vmap (balls of one model)."""

    bulk_modulus_pa: Array
    hyperelastic: NamedTuple
    prony_g: Array
    prony_k: Array
    prony_tau_s: Array
    shear_modulus_pa: Array

    def flat(self) -> dict[str, Array]:
        """Every constant by name (the energy's first), as written to result files."""
        out = dict(self._asdict())
        return {**out.pop("hyperelastic")._asdict(), **out}


@dataclass(frozen=True)
class Material(ABC):
    """A hyperelastic material with optional Prony viscoelasticity (constants in SI)."""

    prony: tuple[PronyTerm, ...] = field(default=(), kw_only=True)
    moduli: str = field(default="long_term", kw_only=True)

    model: ClassVar[str]
    keys: ClassVar[tuple[str, ...]]  # the model's own keys in the ball specification
    #: the typed constants of `energy` (a NamedTuple registered with `register_constants`)
    Constants: ClassVar[type]
    # Hyperfoam has no deviatoric/volumetric split: its whole stress relaxes with g_i.
    relax_whole_stress: ClassVar[bool] = False

    def __post_init__(self) -> None:
        if self.moduli not in MODULI:
            raise InputError(f"{self.model}.moduli = {self.moduli!r}: allowed {', '.join(MODULI)}")
        if self.relax_whole_stress and any(t.k for t in self.prony):
            raise InputError(f"{self.model}.prony.k: must be 0 (the whole stress relaxes with g)")

    # ---- constants -------------------------------------------------------------------------
    @property
    def sum_g(self) -> float:
        return float(sum(t.g for t in self.prony))

    @property
    def sum_k(self) -> float:
        return float(sum(t.k for t in self.prony))

    @property
    def sum_bulk_relaxation(self) -> float:
        """Fraction of the bulk modulus that relaxes: sum k_i, or sum g_i for a material whose
        whole stress relaxes (hyperfoam)."""
        return self.sum_g if self.relax_whole_stress else self.sum_k

    def deviatoric_factor(self) -> float:
        """Factor from the constants as given to instantaneous deviatoric constants."""
        return 1.0 / (1.0 - self.sum_g) if self.moduli == "long_term" else 1.0

    def volumetric_factor(self) -> float:
        """Factor from the bulk modulus as given to the instantaneous one."""
        return 1.0 / (1.0 - self.sum_bulk_relaxation) if self.moduli == "long_term" else 1.0

    @abstractmethod
    def given_moduli_pa(self) -> tuple[float, float]:
        """Initial shear and bulk moduli (Pa) of the constants as given."""

    @abstractmethod
    def hyperelastic_constants(self) -> NamedTuple:
        """Instantaneous constants of `energy` (SI; arrays for multi-term models), as the
        model's `Constants`."""

    def shear_modulus_pa(self, instantaneous: bool = True) -> float:
        mu, _ = self.given_moduli_pa()
        inst = mu * self.deviatoric_factor()
        return inst if instantaneous else inst * (1.0 - self.sum_g)

    def bulk_modulus_pa(self, instantaneous: bool = True) -> float:
        _, k = self.given_moduli_pa()
        inst = k * self.volumetric_factor()
        return inst if instantaneous else inst * (1.0 - self.sum_bulk_relaxation)

    def wave_modulus_pa(self) -> float:
        """Instantaneous dilatational (P-wave) modulus K + 4/3 mu, for the stable increment."""
        return self.bulk_modulus_pa() + 4.0 / 3.0 * self.shear_modulus_pa()

    def constants(self) -> MaterialConstants:
        """Everything the solver needs, as float64 arrays: a pytree that can be stacked for vmap."""
        n = len(self.prony)
        g = np.array([t.g for t in self.prony], dtype=np.float64).reshape(n)
        k = np.zeros(n) if self.relax_whole_stress else np.array(
            [t.k for t in self.prony], dtype=np.float64).reshape(n)
        hyperelastic = self.hyperelastic_constants()
        return MaterialConstants(
            bulk_modulus_pa=np.float64(self.bulk_modulus_pa()),
            hyperelastic=type(hyperelastic)(*(np.asarray(v, dtype=np.float64)
                                              for v in hyperelastic)),
            prony_g=g, prony_k=k,
            prony_tau_s=np.array([t.tau_s for t in self.prony], dtype=np.float64).reshape(n),
            shear_modulus_pa=np.float64(self.shear_modulus_pa()))

    # ---- energy (pure, jnp) ----------------------------------------------------------------
    energy: ClassVar[Callable[[jax.Array, NamedTuple], tuple[jax.Array, jax.Array]]]
    """energy(C: Sym, constants: Constants) -> (W_relaxing, W_volumetric) per unit reference
    volume (J/m^3), at the instantaneous constants, for right Cauchy-Green tensors given by
    components."""

    # ---- specification ---------------------------------------------------------------------
    @classmethod
    def from_dict(cls, d: dict, where: str = "material") -> Material:
        check_keys(d, {"model", *cls.keys, "prony", "moduli"}, where)
        moduli = d.get("moduli", "long_term")
        if moduli not in MODULI:
            raise InputError(f"{where}.moduli = {moduli!r}: allowed {', '.join(MODULI)}")
        try:
            return cls._from_keys(d, where, prony=_prony_from(d, where), moduli=moduli)
        except InputError as error:  # checks in __post_init__ do not know the key's path
            if str(error).startswith(where):
                raise
            raise InputError(f"{where}: {error}") from None

    @classmethod
    @abstractmethod
    def _from_keys(cls, d: dict, where: str, **common: Any) -> Material: ...

    @abstractmethod
    def _keys_dict(self) -> dict[str, Any]: ...

    def to_dict(self) -> dict[str, Any]:
        out = {"model": self.model, **self._keys_dict(), "moduli": self.moduli}
        if self.prony:
            out["prony"] = [{"g": t.g, "k": t.k, "tau_s": t.tau_s} for t in self.prony]
        return out


class Sym(NamedTuple):
    """Components of a symmetric 3x3 tensor, each an array of any shape (or the float 0.0).

    Materials take C in this form: per-component arrays keep every operation a fused loop over
    points, and the axisymmetric solver passes yz = zx = 0.0, which XLA folds away.
    """

    xx: Any
    yy: Any
    zz: Any
    xy: Any
    yz: Any = 0.0
    zx: Any = 0.0

    @classmethod
    def from_matrix(cls, m) -> Sym:
        return cls(m[0, 0], m[1, 1], m[2, 2], m[0, 1], m[1, 2], m[2, 0])

    def trace(self):
        return self.xx + self.yy + self.zz

    def det(self):
        return (self.xx * (self.yy * self.zz - self.yz * self.yz)
                - self.xy * (self.xy * self.zz - self.yz * self.zx)
                + self.zx * (self.xy * self.yz - self.yy * self.zx))

    def second_invariant(self):
        return (self.xx * self.yy + self.yy * self.zz + self.zz * self.xx
                - self.xy * self.xy - self.yz * self.yz - self.zx * self.zx)

    def double_dot(self, other: Sym):
        return (self.xx * other.xx + self.yy * other.yy + self.zz * other.zz
                + 2.0 * (self.xy * other.xy + self.yz * other.yz + self.zx * other.zx))


def energy_and_stress(energy, C: Sym, constants: NamedTuple) -> tuple[tuple, tuple]:
    """Energy parts (J/m^3) and second Piola-Kirchhoff stress parts S = 2 dW/dC, as
    ((W_relaxing, S_relaxing), (W_volumetric, S_volumetric)). For C with zero yz and zx
    components (floats: axisymmetric and material-point states) S = (S_xx, S_yy, S_zz, S_xy);
    for a general C (3D) S = (S_xx, S_yy, S_zz, S_xy, S_yz, S_zx).

    Each point's energy depends only on its own C, so the gradient of the summed energy is the
    pointwise stress. An off-diagonal entry of C stands for both C_ij and C_ji, so dW/dC_ij (the
    sum of both partial derivatives) is already S_ij."""
    general = not isinstance(C.yz, float)
    comps = tuple(C) if general else (C.xx, C.yy, C.zz, C.xy)

    def part_with_energy(i):
        def total(c):
            w = energy(Sym(*c), constants)[i]
            return jnp.sum(w), w
        grad, w = jax.grad(total, has_aux=True)(comps)
        return w, tuple(2.0 * g if k < 3 else g for k, g in enumerate(grad))

    return part_with_energy(0), part_with_energy(1)


def stress_parts(energy, C: Sym, constants: NamedTuple) -> tuple[tuple, tuple]:
    """(S_relaxing, S_volumetric), each (S_xx, S_yy, S_zz, S_xy); see `energy_and_stress`."""
    (_, s_dev), (_, s_vol) = energy_and_stress(energy, C, constants)
    return s_dev, s_vol


def isochoric_invariants(C: Sym) -> tuple[Any, Any, Any]:
    """(I1bar, I2bar, J) of a right Cauchy-Green tensor."""
    det = C.det()
    scale = 1.0 / cube_root(det)  # J^(-2/3)
    return scale * C.trace(), scale * scale * C.second_invariant(), jnp.sqrt(det)


def bulk_from_d1(material: Material, d1_per_pa: float, mu0_pa: float) -> float:
    """Bulk modulus (as given) K = 2 / D1. D1 = 0 means ABAQUS/Explicit's substitute K0 = 20 mu0
    between the instantaneous moduli (Poisson ratio 0.475 at the instant of loading), whatever
    convention the constants are given in."""
    if d1_per_pa != 0.0:
        return 2.0 / d1_per_pa
    return (INCOMPRESSIBLE_BULK_TO_SHEAR * mu0_pa * material.deviatoric_factor()
            / material.volumetric_factor())
