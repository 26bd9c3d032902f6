"""Drucker stability of the FE materials (the check ABAQUS prints for a hyperelastic material).

Drucker's condition, as ABAQUS states it, asks that the change in Kirchhoff stress tau = J sigma
following any change in logarithmic strain do positive work on it: d(tau) : d(eps) > 0. For an
isotropic energy W(e1, e2, e3) of the principal logarithmic strains e_i = ln l_i, coaxial
increments give tau_i = dW/de_i and d(tau_i) = H_ij de_j with the Hessian H_ij = d2W / de_i de_j,
so the condition is that H is positive definite. Only these coaxial (principal) perturbations are
checked, as ABAQUS does.

Incompressible-type rubber laws (neo_hookean, mooney_rivlin, yeoh, ogden): the volume is held
(l3 = 1 / (l1 l2), J = 1, tau = sigma), the pressure drops out of the differences
t_i = sigma_i - sigma_3 = dW/de_i (i = 1, 2, with W the material's own deviatoric energy evaluated
on C = diag(e^2e1, e^2e2, e^-2(e1+e2))), and the condition reads: the 2x2 tangent
D_ij = d t_i / d e_j = d2W / de_i de_j is positive definite. Both come from the material's `energy`
by automatic differentiation (jax, float64), so the check sees exactly the energy the solver uses.
For Mooney-Rivlin it is, in closed form (with A_i = C10 l_i^2 + C01 l_i^-2),

    D11 = 4 (A1 + A3),   D22 = 4 (A2 + A3),   D12 = D21 = 4 A3,

positive definite <=> A1 + A2 + 2 A3 > 0 and A1 A2 + A2 A3 + A3 A1 > 0 (`mooney_rivlin_tangent`,
`mooney_rivlin_drucker`: kept as the independent check of the general path). C10 > 0 and C01 >= 0
make every A_i > 0 (stable for all stretches, neo-Hookean included); a negative C01 makes A_i < 0
for l_i < (-C01 / C10)^(1/4). A Yeoh set with C20, C30 >= 0 and an Ogden set with every mu_i > 0
are stable for all stretches (W is then a convex function of the log strains: sums of
exp(a e_i) with positive weights); a negative C20 or C30, or a term with mu_i, alpha_i < 0, can
fail.

Compressible Ogden hyperfoam: W(e1, e2, e3) is the whole energy; the state of each mode has the
lateral Kirchhoff (and Cauchy) stresses zero, the lateral strain solved per sample (bisection),
and the 3x3 Hessian must be positive definite. (With Cauchy stress instead of Kirchhoff stress the
tangent would be H / J - sigma_i, not symmetric, and would flag every one-term hyperfoam in
moderate uniaxial tension; ABAQUS's criterion is the Kirchhoff one.)

Modes, with stretch = l1: uniaxial (l2 = l3), equibiaxial (l2 = l1) and planar (l2 = 1); for the
incompressible laws l2 = l3 = l1^-1/2, l3 = l1^-2 and l3 = 1 / l1 (`mode_stretches`). Equibiaxial
at l equals uniaxial at l^-2, and planar at l equals planar at 1 / l, for those.

A state is stable when the smallest eigenvalue of the tangent is > -1e-9 times the largest (and
the largest > 0): a set only marginal at an isolated stretch (Mooney-Rivlin C10 = 4.5, C01 = -0.5
in uniaxial tension at exactly 3, where A2 = A3 = 0) is not reported as an unstable interval of
zero width; the edges move by ~1e-9 in log stretch.

Which constants: every checked energy is linear in its moduli (C10, C01, C20, C30, mu_i) at fixed
exponents, so scaling them by one positive factor scales the tangent and leaves the ranges
unchanged. Messages name the long-term constants (the given ones scaled by (1 - sum g_i) when
given as instantaneous); the instantaneous ones give identical ranges. Linear elastic layers are
not checked (`checked` is False).
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING, Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..errors import InputError
from ..checks import check_integer, check_range
from .base import Material, Sym
from .mooney_rivlin import MooneyRivlin
from .neo_hookean import NeoHookean
from .ogden import Ogden
from .ogden_hyperfoam import OgdenHyperfoam
from .yeoh import Yeoh

if TYPE_CHECKING:
    from ..balls.ball import BallModel

MODES = ("uniaxial", "equibiaxial", "planar")
_BISECTIONS = 60
_ROUNDING = 1e-12
#: incompressible-type laws: checked on isochoric states with their deviatoric energy
INCOMPRESSIBLE = (NeoHookean, MooneyRivlin, Yeoh, Ogden)
#: smallest tangent eigenvalue, relative to the largest, still taken as stable (marginal states)
_MARGINAL = 1e-9
#: most Newton (or bisection) steps for the lateral log strain of a hyperfoam state
_LATERAL_ITERATIONS = 100


def mode_stretches(mode: str, stretch) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Principal stretches (l1, l2, l3) of an isochoric deformation mode, l1 = `stretch`."""
    lam = np.asarray(stretch, dtype=np.float64)
    if mode == "uniaxial":
        lat = lam ** -0.5
        return lam, lat, lat
    if mode == "equibiaxial":
        return lam, lam, lam ** -2.0
    if mode == "planar":
        return lam, np.ones_like(lam), 1.0 / lam
    raise InputError(f"mode = {mode!r}: allowed {', '.join(MODES)}")


def mooney_rivlin_stress_differences(c10_pa, c01_pa, e1, e2) -> tuple[np.ndarray, np.ndarray]:
    """(t1, t2) = (sigma_1 - sigma_3, sigma_2 - sigma_3) (Pa) at logarithmic strains e1, e2."""
    e1 = np.asarray(e1, dtype=np.float64)
    e2 = np.asarray(e2, dtype=np.float64)
    x1, x2, x3 = np.exp(2.0 * e1), np.exp(2.0 * e2), np.exp(-2.0 * (e1 + e2))  # l_i^2
    t1 = 2.0 * c10_pa * (x1 - x3) - 2.0 * c01_pa * (1.0 / x1 - 1.0 / x3)
    t2 = 2.0 * c10_pa * (x2 - x3) - 2.0 * c01_pa * (1.0 / x2 - 1.0 / x3)
    return t1, t2


def mooney_rivlin_tangent(c10_pa, c01_pa, l1, l2) -> np.ndarray:
    """Analytic D_ij = d t_i / d e_j (Pa), shape (..., 2, 2), at stretches l1, l2 (l3 = 1/(l1 l2))."""
    l1 = np.asarray(l1, dtype=np.float64)
    l2 = np.asarray(l2, dtype=np.float64)
    x1, x2 = l1 * l1, l2 * l2
    x3 = 1.0 / (x1 * x2)
    a1, a2, a3 = (c10_pa * x + c01_pa / x for x in (x1, x2, x3))
    d = np.empty(np.broadcast(l1, l2).shape + (2, 2))
    d[..., 0, 0] = 4.0 * (a1 + a3)
    d[..., 1, 1] = 4.0 * (a2 + a3)
    d[..., 0, 1] = d[..., 1, 0] = 4.0 * a3
    return d


def _stable(c10_pa: float, c01_pa: float, mode: str, stretch) -> np.ndarray:
    """trace > 0 and det >= 0, each A_i within rounding (1e-12 of its terms) of 0 taken as 0: a set
    that is only marginal at an isolated stretch (C10 = 4.5, C01 = -0.5 in uniaxial tension at
    exactly 3, where A2 = A3 = 0) is not reported as an unstable interval of zero width."""
    l1, l2, l3 = mode_stretches(mode, stretch)
    a = []
    for x in (l1 * l1, l2 * l2, l3 * l3):
        terms = (c10_pa * x, c01_pa / x)
        ai = terms[0] + terms[1]
        a.append(np.where(np.abs(ai) <= _ROUNDING * (np.abs(terms[0]) + np.abs(terms[1])), 0.0, ai))
    trace = a[0] + a[1] + 2.0 * a[2]
    det = a[0] * a[1] + a[1] * a[2] + a[2] * a[0]
    return (trace > 0.0) & (det >= 0.0)


def _edge(c10_pa: float, c01_pa: float, mode: str, lo: float, hi: float) -> float:
    """Stretch between lo and hi at which stability changes (bisection in log stretch)."""
    s_lo = bool(_stable(c10_pa, c01_pa, mode, lo))
    a, b = np.log(lo), np.log(hi)
    for _ in range(_BISECTIONS):
        m = 0.5 * (a + b)
        if bool(_stable(c10_pa, c01_pa, mode, np.exp(m))) == s_lo:
            a = m
        else:
            b = m
    return float(np.exp(0.5 * (a + b)))


def _check_stretches(stretch_min: Any, stretch_max: Any, n: Any) -> int:
    """The stretch interval (0 < stretch_min < stretch_max) and its number of samples `n`
    (returned as an int) checked by `check_range` and `check_integer`."""
    check_range("stretch_min", stretch_min, 0.0, low_open=True)
    check_range("stretch_max", stretch_max, stretch_min, low_open=True, note="above stretch_min")
    return check_integer("n", n, 2)


def mooney_rivlin_drucker(c10_pa: float, c01_pa: float, stretch_min: float, stretch_max: float,
                          n: int = 400) -> list[dict[str, Any]]:
    """Unstable stretch intervals of an incompressible Mooney-Rivlin set (empty list: stable).

    Each mode's principal stretch l1 is sampled at `n` log-spaced points over [stretch_min,
    stretch_max]; each run of unstable samples is one interval, its inner edges refined by
    bisection (to ~1e-15 relative). An interval narrower than the sampling may be missed.
    Returns dicts {"mode", "stretch_from", "stretch_to"} in mode order, then by stretch.
    """
    n = _check_stretches(stretch_min, stretch_max, n)
    for key, value in (("c10_pa", c10_pa), ("c01_pa", c01_pa)):
        check_range(key, value)
    grid = np.geomspace(stretch_min, stretch_max, n)
    grid[0], grid[-1] = stretch_min, stretch_max
    out = []
    for mode in MODES:
        for i, j in unstable_runs(_stable(c10_pa, c01_pa, mode, grid)):
            start = grid[0] if i == 0 else _edge(c10_pa, c01_pa, mode, grid[i - 1], grid[i])
            end = grid[-1] if j == n - 1 else _edge(c10_pa, c01_pa, mode, grid[j], grid[j + 1])
            out.append({"mode": mode, "stretch_from": float(start), "stretch_to": float(end)})
    return out


def unstable_runs(stable: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index of each run of False in a boolean array (the unstable samples)."""
    bad = np.concatenate([[False], ~np.asarray(stable, bool), [False]]).astype(np.int8)
    starts = np.flatnonzero(np.diff(bad) == 1)
    ends = np.flatnonzero(np.diff(bad) == -1) - 1
    return list(zip(starts.tolist(), ends.tolist()))


def long_term_mooney_rivlin(material) -> tuple[float, float] | None:
    """(C10, C01) long-term (Pa) of a Mooney-Rivlin or neo-Hookean material, else None."""
    if isinstance(material, MooneyRivlin):
        c10, c01 = material.c10_pa, material.c01_pa
    elif isinstance(material, NeoHookean):
        c10, c01 = material.c10_pa, 0.0
    else:
        return None
    f = material.deviatoric_factor() * (1.0 - material.sum_g)  # given -> long-term
    return c10 * f, c01 * f


# ---- every material: the tangent from its own energy -----------------------------------------
def checked(material: Any) -> bool:
    """True for the materials the Drucker check covers: every model but linear_elastic."""
    return isinstance(material, (*INCOMPRESSIBLE, OgdenHyperfoam))


def _require_checked(material: Any) -> None:
    if not isinstance(material, Material):
        raise InputError(f"material: expected a Material, got {type(material).__name__}")
    if not checked(material):
        names = ", ".join(m.model for m in (*INCOMPRESSIBLE, OgdenHyperfoam))
        raise InputError(f"{material.model}: not checked for Drucker stability (checked: {names})")


def _check_mode(mode: Any) -> None:
    if mode not in MODES:
        raise InputError(f"mode = {mode!r}: allowed {', '.join(MODES)}")


#: constants of the relaxing energy that are moduli (scaled to long-term); the rest are exponents
_MODULUS_KEYS = ("c10_pa", "c01_pa", "c20_pa", "c30_pa", "mu_pa")


def _long_term_energy_constants(material: Material) -> NamedTuple:
    """The constants `energy` takes, with the moduli long-term (instantaneous x (1 - sum g))."""
    out = material.hyperelastic_constants()
    return out._replace(**{key: getattr(out, key) * (1.0 - material.sum_g)
                           for key in _MODULUS_KEYS if key in out._fields})


def _strain_energy(energy, compressible: bool):
    """W(c, e): the material's relaxing energy at principal logarithmic strains e = (e1, e2) with
    e3 = -e1 - e2 (isochoric), or e = (e1, e2, e3) (compressible)."""
    def w(c, e):
        e3 = e[2] if compressible else -(e[0] + e[1])
        # xy given as the float 0: principal axes, the direct (non-eigenvalue) path of every law
        C = Sym(jnp.exp(2.0 * e[0]), jnp.exp(2.0 * e[1]), jnp.exp(2.0 * e3), 0.0)
        return energy(C, c)[0]
    return w


@functools.lru_cache(maxsize=None)
def _compiled(energy, compressible: bool):
    """Jitted e -> (gradient, Hessian) of an energy in the principal log strains, vectorised over
    samples (one compilation per model)."""
    w = _strain_energy(energy, compressible)

    def derivatives(c, e):
        g = jax.grad(w, argnums=1)
        return g(c, e), jax.jacfwd(g, argnums=1)(c, e)

    return jax.jit(jax.vmap(derivatives, in_axes=(None, 0)))


def _mode_strains(mode: str, e1: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Hyperfoam log strains of a mode: uniaxial (e1, s, s), equibiaxial (e1, e1, s), planar
    (e1, 0, s); s the lateral strain."""
    e2 = {"uniaxial": s, "equibiaxial": e1, "planar": np.zeros_like(e1)}[mode]
    return np.stack([e1, e2, s], axis=-1)


def _lateral_strains(derivatives, constants: NamedTuple, mode: str, e1: np.ndarray) -> np.ndarray:
    """Log strains of a hyperfoam mode with the lateral stress zero. The lateral strain s solves
    tau_lat(s) = 0 (tau_2 in uniaxial, = tau_3; else tau_3) by Newton steps kept inside a bracket
    that starts at [-(2|e1| + 1), 2|e1| + 1] (one term: s = -nu e1, |nu| < 1) and shrinks by
    bisection where a step leaves it; NaN where the root is not bracketed."""
    lat = 1 if mode == "uniaxial" else 2

    def residual(s):
        g, h = _padded_call(derivatives, constants, _mode_strains(mode, e1, s))
        slope = h[:, lat, 1] + h[:, lat, 2] if mode == "uniaxial" else h[:, lat, 2]
        return g[:, lat], slope

    bound = 2.0 * np.abs(e1) + 1.0
    lo, hi = -bound, bound.copy()
    bracketed = (residual(lo)[0] < 0.0) & (residual(hi)[0] > 0.0)
    s = np.zeros_like(e1)
    for _ in range(_LATERAL_ITERATIONS):
        r, slope = residual(s)
        lo, hi = np.where(r < 0.0, s, lo), np.where(r < 0.0, hi, s)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = s - r / slope
        inside = np.isfinite(step) & (step > lo) & (step < hi)
        new = np.where(inside, step, 0.5 * (lo + hi))
        if np.all(np.abs(new - s) <= 1e-15 * (1.0 + np.abs(s))):
            s = new
            break
        s = new
    return np.where(bracketed[:, None], _mode_strains(mode, e1, s), np.nan)


#: samples per call are padded to a multiple of this (the default grid fits in one)
_PAD = 512


def _padded_call(fn, constants: NamedTuple, x: np.ndarray, *args):
    """fn(constants, x, *args) on the rows of x, padded to a multiple of `_PAD` rows (so that
    the grid and the edge bisections share one compilation); outputs as float64 arrays."""
    n = x.shape[0]
    size = _PAD * max(1, -(-n // _PAD))
    padded = np.zeros((size, *x.shape[1:]))
    padded[:n] = x
    with jax.enable_x64(True):
        out = fn(jax.tree_util.tree_map(jnp.asarray, constants), jnp.asarray(padded), *args)
        return jax.tree_util.tree_map(lambda a: np.array(a, dtype=np.float64)[:n], out)


def tangent(material: Material, mode: str, stretch) -> tuple[np.ndarray, np.ndarray]:
    """(t, D) of a checked material along a mode, at the long-term constants (Pa), for each
    stretch l1 (1-D). Incompressible-type laws: t = (sigma_1 - sigma_3, sigma_2 - sigma_3),
    shape (n, 2), and D = dt_i / de_j, (n, 2, 2). Hyperfoam: t = the Kirchhoff principal stresses
    tau_i (lateral ones zero), (n, 3), and D = dtau_i / de_j, (n, 3, 3); NaN where no stress-free
    lateral strain was found."""
    _require_checked(material)
    _check_mode(mode)
    lam = np.atleast_1d(np.asarray(stretch, dtype=np.float64))
    compressible = isinstance(material, OgdenHyperfoam)
    derivatives = _compiled(type(material).energy, compressible)
    c = _long_term_energy_constants(material)
    if compressible:
        e = _lateral_strains(derivatives, c, mode, np.log(lam))
    else:
        l1, l2, _ = mode_stretches(mode, lam)
        e = np.stack([np.log(l1), np.log(l2)], axis=-1)
    ok = np.all(np.isfinite(e), axis=-1)
    e_safe = np.where(ok[:, None], e, 0.0)
    t, d = _padded_call(derivatives, c, e_safe)
    t[~ok] = np.nan
    d[~ok] = np.nan
    return t, d


def _stable_states(material: Material, mode: str, stretch) -> np.ndarray:
    """Drucker-stable samples: the tangent's smallest eigenvalue > -1e-9 x its largest > 0."""
    _, d = tangent(material, mode, stretch)
    ok = np.all(np.isfinite(d), axis=(-2, -1))
    d = np.where(ok[:, None, None], d, 0.0)
    eig = np.linalg.eigvalsh(0.5 * (d + np.swapaxes(d, -1, -2)))
    return ok & (eig[:, -1] > 0.0) & (eig[:, 0] >= -_MARGINAL * eig[:, -1])


def _edges(material: Material, mode: str, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Stretches between lo and hi (arrays) at which stability changes (bisection in log
    stretch, all edges at once)."""
    s_lo = _stable_states(material, mode, lo)
    a, b = np.log(lo), np.log(hi)
    for _ in range(_BISECTIONS):
        m = 0.5 * (a + b)
        same = _stable_states(material, mode, np.exp(m)) == s_lo
        a, b = np.where(same, m, a), np.where(same, b, m)
    return np.exp(0.5 * (a + b))


def drucker_unstable(material: Material, stretch_min: float, stretch_max: float,
                     n: int = 400, modes: tuple[str, ...] = MODES) -> list[dict[str, Any]]:
    """Unstable stretch intervals of a material (neo_hookean, mooney_rivlin, yeoh, ogden,
    ogden_hyperfoam; empty list: stable), from its own energy at the long-term constants (the
    instantaneous ones give identical ranges).

    Each mode's principal stretch l1 is sampled at `n` log-spaced points over [stretch_min,
    stretch_max]; each run of unstable samples is one interval, its inner edges refined by
    bisection (to ~1e-9 relative, the marginal tolerance). An interval narrower than the sampling
    may be missed. Returns dicts {"mode", "stretch_from", "stretch_to"} in mode order, then by
    stretch. `modes`: the modes checked (default all). A linear_elastic material raises
    `InputError` (not checked)."""
    n = _check_stretches(stretch_min, stretch_max, n)
    _require_checked(material)
    grid = np.geomspace(stretch_min, stretch_max, n)
    grid[0], grid[-1] = stretch_min, stretch_max
    out = []
    for mode in modes:
        runs = unstable_runs(_stable_states(material, mode, grid))
        inner = [(grid[i - 1], grid[i]) for i, _ in runs if i > 0] + \
                [(grid[j], grid[j + 1]) for _, j in runs if j < n - 1]
        edges = iter(_edges(material, mode, *map(np.array, zip(*inner))) if inner else [])
        starts = [grid[0] if i == 0 else next(edges) for i, _ in runs]
        ends = [grid[-1] if j == n - 1 else next(edges) for _, j in runs]
        out += [{"mode": mode, "stretch_from": float(a), "stretch_to": float(b)}
                for a, b in zip(starts, ends)]
    return out


def stable_range(material: Material, mode: str, stretch_min: float = 0.05,
                 stretch_max: float = 20.0, n: int = 400) -> tuple[float, float]:
    """(low, high): the widest Drucker-stable stretch interval of `mode` that contains 1, within
    [stretch_min, stretch_max] (a limit is returned as it is when stable up to it). Sampled at
    `n` log-spaced stretches on each side of 1, the edges bisected as in `drucker_unstable`."""
    n = _check_stretches(stretch_min, stretch_max, n)
    if not stretch_min <= 1.0 <= stretch_max:
        raise InputError(f"stretch_min = {stretch_min:g}, stretch_max = {stretch_max:g}: the "
                         "range must contain 1")
    _require_checked(material)
    _check_mode(mode)
    if not _stable_states(material, mode, np.array([1.0]))[0]:
        return 1.0, 1.0
    out = []
    for limit in (stretch_min, stretch_max):
        side = np.geomspace(1.0, limit, n) if limit != 1.0 else np.array([1.0])
        side[-1] = limit
        bad = np.flatnonzero(~_stable_states(material, mode, side))
        if bad.size == 0:
            out.append(float(limit))
        else:
            k = bad[0]
            out.append(float(_edges(material, mode, side[k - 1:k], side[k:k + 1])[0]))
    return out[0], out[1]


def long_term_constants(material: Material) -> str:
    """The long-term constants of a checked material as text ("C10 = 4.248e+06 Pa, ...")."""
    f = material.deviatoric_factor() * (1.0 - material.sum_g)  # given -> long-term
    if isinstance(material, (MooneyRivlin, NeoHookean)):
        c10, c01 = long_term_mooney_rivlin(material)
        return f"C10 = {c10:.4g} Pa, C01 = {c01:.4g} Pa"
    if isinstance(material, Yeoh):
        return ", ".join(f"{name} = {value * f:.4g} Pa" for name, value in (
            ("C10", material.c10_pa), ("C20", material.c20_pa), ("C30", material.c30_pa)))
    if isinstance(material, Ogden):
        return ", ".join(f"mu_{i} = {t.mu_pa * f:.4g} Pa, alpha_{i} = {t.alpha:g}"
                         for i, t in enumerate(material.terms, start=1))
    if isinstance(material, OgdenHyperfoam):
        return ", ".join(f"mu_{i} = {t.mu_pa * f:.4g} Pa, alpha_{i} = {t.alpha:g}, "
                         f"nu_{i} = {t.nu:g}" for i, t in enumerate(material.terms, start=1))
    _require_checked(material)
    raise AssertionError(material.model)  # (a checked model without its text)


def drucker_warnings(ball: BallModel, stretch_min: float, stretch_max: float,
                     n: int = 400) -> list[str]:
    """One message per unstable (layer, mode, stretch range) of every checked layer (all but
    linear_elastic), naming its long-term constants (identical ranges for the instantaneous
    ones)."""
    n = _check_stretches(stretch_min, stretch_max, n)
    messages = []
    for i, layer in enumerate(ball.layers):
        material = layer.material
        if not checked(material):
            continue
        for r in _unstable_after_run(material, stretch_min, stretch_max, n):
            messages.append(
                f"{ball.name}: layer {i} '{layer.name}' ({material.model}, long-term "
                f"{long_term_constants(material)}) is Drucker-unstable in {r['mode']} "
                f"deformation for stretches {r['stretch_from']:.4g} to {r['stretch_to']:.4g} "
                f"(checked {stretch_min:g} to {stretch_max:g})")
    return messages

def _unstable_after_run(material: Material, stretch_min: float, stretch_max: float,
                        n: int) -> list[dict[str, Any]]:
    """`drucker_unstable` as every FE run asks it (after each run of a batch, a search, a
    study): the closed form for Mooney-Rivlin and neo-Hookean (milliseconds, no compilation),
    else the energy's check over the widest range once per material (cached) and clipped to the
    run's stretches."""
    constants = long_term_mooney_rivlin(material)
    if constants is not None:
        return mooney_rivlin_drucker(*constants, stretch_min, stretch_max, n)
    try:
        wide = _unstable_everywhere(material)
    except TypeError:  # a material that cannot be hashed: checked as it is
        return drucker_unstable(material, stretch_min, stretch_max, n)
    return [{"mode": r["mode"], "stretch_from": max(r["stretch_from"], stretch_min),
             "stretch_to": min(r["stretch_to"], stretch_max)} for r in wide
            if r["stretch_to"] > stretch_min and r["stretch_from"] < stretch_max]


#: the range and sampling of the cached check (`_unstable_after_run`): 0.05..20 at 2000 points
#: (0.3% apart in stretch)
WIDE_RANGE, WIDE_SAMPLES = (0.05, 20.0), 2000


@functools.lru_cache(maxsize=64)
def _unstable_everywhere(material: Material) -> tuple[dict[str, Any], ...]:
    return tuple(drucker_unstable(material, *WIDE_RANGE, WIDE_SAMPLES))


__all__ = ["INCOMPRESSIBLE", "MODES", "checked", "drucker_unstable", "drucker_warnings",
           "long_term_constants", "long_term_mooney_rivlin", "mode_stretches",
           "mooney_rivlin_drucker", "mooney_rivlin_stress_differences", "mooney_rivlin_tangent",
           "stable_range", "tangent"]
