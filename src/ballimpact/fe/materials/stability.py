"""Drucker stability of incompressible Mooney-Rivlin sets (the check ABAQUS prints for a material).

For an incompressible material with principal stretches l1, l2, l3 = 1 / (l1 l2) the Cauchy stresses
are sigma_i = 2 C10 l_i^2 - 2 C01 l_i^-2 - p, and the pressure p drops out of the differences

    t_i = sigma_i - sigma_3 = 2 C10 (l_i^2 - l3^2) - 2 C01 (l_i^-2 - l3^-2),   i = 1, 2.

Drucker's condition d(sigma) : d(eps) > 0 for every isochoric logarithmic strain increment
d(eps) = diag(de1, de2, -de1 - de2) reads dt1 de1 + dt2 de2 > 0, i.e. the tangent
D_ij = d t_i / d e_j (e_i = ln l_i) must be positive definite. Differentiating (d l_i^2 / d e_i =
2 l_i^2, d l3^2 / d e_j = -2 l3^2) with A_i = C10 l_i^2 + C01 l_i^-2:

    D11 = 4 (A1 + A3),   D22 = 4 (A2 + A3),   D12 = D21 = 4 A3,

which is symmetric. Positive definite <=> D11 + D22 > 0 and D11 D22 - D12^2 > 0, i.e.

    A1 + A2 + 2 A3 > 0   and   A1 A2 + A2 A3 + A3 A1 > 0

(the determinant is 16 times the second symmetric function of the A_i, so the check does not depend
on which principal axis is called 3). The modes checked, with stretch = l1:
uniaxial (l2 = l3 = l1^-1/2), equibiaxial (l2 = l1, l3 = l1^-2) and planar (l2 = 1, l3 = 1 / l1).
Equibiaxial at l equals uniaxial at l^-2, and planar at l equals planar at 1 / l.

Some properties: C10 > 0 and C01 >= 0 make every A_i > 0, so the set is stable for all stretches
(neo-Hookean included); a negative C01 makes A_i < 0 for l_i < (-C01 / C10)^(1/4), which fails
the check at large enough tension or compression.

Which constants: the criterion is homogeneous in (C10, C01), so scaling both by the same positive
factor does not change it. `drucker_warnings` uses the long-term constants (the given ones scaled by
(1 - sum g_i) when given as instantaneous); the instantaneous set is the same times 1 / (1 - sum g),
so the two give identical ranges. Only the coaxial (principal) perturbations above are checked, as
ABAQUS does; Ogden hyperfoam and linear elastic layers are not checked.
"""

from __future__ import annotations

import numbers
from typing import TYPE_CHECKING, Any

import numpy as np

from ...errors import InputError
from ..options import shown
from .mooney_rivlin import MooneyRivlin
from .neo_hookean import NeoHookean

if TYPE_CHECKING:
    from ..ball import BallModel

MODES = ("uniaxial", "equibiaxial", "planar")
_BISECTIONS = 60
_ROUNDING = 1e-12


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


def _check_range(stretch_min: Any, stretch_max: Any, n: Any) -> None:
    for key, value in (("stretch_min", stretch_min), ("stretch_max", stretch_max)):
        if isinstance(value, bool) or not isinstance(value, numbers.Real) \
                or not np.isfinite(value) or value <= 0.0:
            raise InputError(f"{key} = {shown(value)}: expected a finite number > 0")
    if not stretch_max > stretch_min:
        raise InputError(f"stretch_max = {stretch_max:g}: must be greater than stretch_min = "
                         f"{stretch_min:g}")
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 2:
        raise InputError(f"n = {shown(n)}: expected an integer >= 2")


def mooney_rivlin_drucker(c10_pa: float, c01_pa: float, stretch_min: float, stretch_max: float,
                          n: int = 400) -> list[dict[str, Any]]:
    """Unstable stretch intervals of an incompressible Mooney-Rivlin set (empty list: stable).

    Each mode's principal stretch l1 is sampled at `n` log-spaced points over [stretch_min,
    stretch_max]; each run of unstable samples is one interval, its inner edges refined by
    bisection (to ~1e-15 relative). An interval narrower than the sampling may be missed.
    Returns dicts {"mode", "stretch_from", "stretch_to"} in mode order, then by stretch.
    """
    _check_range(stretch_min, stretch_max, n)
    for key, value in (("c10_pa", c10_pa), ("c01_pa", c01_pa)):
        if isinstance(value, bool) or not isinstance(value, numbers.Real) or not np.isfinite(value):
            raise InputError(f"{key} = {shown(value)}: expected a finite number")
    grid = np.geomspace(stretch_min, stretch_max, n)
    grid[0], grid[-1] = stretch_min, stretch_max
    out = []
    for mode in MODES:
        stable = _stable(c10_pa, c01_pa, mode, grid)
        i = 0
        while i < n:
            if stable[i]:
                i += 1
                continue
            j = i
            while j + 1 < n and not stable[j + 1]:
                j += 1
            start = grid[0] if i == 0 else _edge(c10_pa, c01_pa, mode, grid[i - 1], grid[i])
            end = grid[-1] if j == n - 1 else _edge(c10_pa, c01_pa, mode, grid[j], grid[j + 1])
            out.append({"mode": mode, "stretch_from": float(start), "stretch_to": float(end)})
            i = j + 1
    return out


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


def drucker_warnings(ball: BallModel, stretch_min: float, stretch_max: float,
                     n: int = 400) -> list[str]:
    """One message per unstable (layer, mode, stretch range) of the Mooney-Rivlin / neo-Hookean
    layers, using their long-term constants (identical ranges for the instantaneous ones)."""
    _check_range(stretch_min, stretch_max, n)
    messages = []
    for i, layer in enumerate(ball.layers):
        constants = long_term_mooney_rivlin(layer.material)
        if constants is None:
            continue
        c10, c01 = constants
        for r in mooney_rivlin_drucker(c10, c01, stretch_min, stretch_max, n):
            messages.append(
                f"{ball.name}: layer {i} '{layer.name}' ({layer.material.model}, long-term "
                f"C10 = {c10:.4g} Pa, C01 = {c01:.4g} Pa) is Drucker-unstable in {r['mode']} "
                f"deformation for stretches {r['stretch_from']:.4g} to {r['stretch_to']:.4g} "
                f"(checked {stretch_min:g} to {stretch_max:g})")
    return messages


__all__ = ["MODES", "drucker_warnings", "long_term_mooney_rivlin", "mode_stretches",
           "mooney_rivlin_drucker", "mooney_rivlin_stress_differences", "mooney_rivlin_tangent"]
