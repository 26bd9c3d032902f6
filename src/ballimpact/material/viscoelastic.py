"""Prony series from relaxation, creep and DMA tests, with time-temperature shifting.

The series is the FE materials' one (constitutive/base.py): the normalised relaxation modulus
g_R(t) = G(t) / G(0) = 1 - sum g_i (1 - exp(-t / tau_i)), g_i >= 0, sum g_i < 1, tau_i in s.

- Relaxation data give g_R(t) directly.
- Creep data give J(t) / J(0). For a Prony G the Volterra relation int_0-^t G(t - s) dJ(s) = 1
  is solved exactly: in the Laplace domain s G^(s) s J^(s) = 1, and s G^(s) / G(0) =
  1 - sum g_i / (1 + s tau_i) has n real negative zeros -1/T_k, one between each pair of
  neighbouring relaxation rates and one below the slowest, so
  J(t) / J(0) = 1 + sum j_k (1 - exp(-t / T_k)), j_k = 1 / (mu_k sum_i g_i lam_i / (lam_i - mu_k)^2)
  with lam_i = 1 / tau_i, mu_k = 1 / T_k (the residues), and sum j_k = 1 / (1 - sum g_i) - 1.
  The converse (relaxation terms of a retardation series) is the same construction. The zeros are
  bracketed exactly and found by bisection to machine precision.
- DMA data give E'(w) = E0 (1 - sum g_i) + E0 sum g_i w^2 tau_i^2 / (1 + w^2 tau_i^2) and
  E''(w) = E0 sum g_i w tau_i / (1 + w^2 tau_i^2), w = 2 pi f. Tests at several temperatures are
  shifted onto a master curve at the reference temperature: the reduced frequency is f a_T with
  WLF log10 a_T = -C1 (T - Tr) / (C2 + T - Tr) or Arrhenius log10 a_T = Ea / (R ln 10)
  (1/T - 1/Tr) (T in kelvin); there is no vertical shift.

Method: relaxation times on a log grid over the data's span widened by a decade each side (two per
decade); non-negative least squares for the weights; the smallest weights merged into their
neighbours in log tau until `terms` are left (the largest split when fewer are found); then bounded
nonlinear least squares on (g_i, ln tau_i) (and ln E0 and the shift constants for DMA) from that
start and from a few seeded perturbations of it, keeping the best. g_i >= 0 and sum g_i < 1 are
kept by a stick-breaking map: g_i = 0.999 u_i prod_{j<i} (1 - u_j), 0 <= u_i <= 1, so that
sum g <= 0.999. Standard errors
are `identifiability.standard_errors` of the residuals in (g_i, ln tau_i, ...) mapped to g_i and
tau_i (s). See docs/material.md "Prony series".
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import least_squares, nnls

from ..checks import check_integer, check_range
from ..errors import InputError, InputWarning
from ..identifiability import identification_notes, standard_errors
from .data import RATIO_SLACK

MAX_TERMS = 10
GRID_PER_DECADE = 2
WIDEN_DECADES = 1.0  # relaxation times searched this far beyond the data's span, each side
#: sum g is kept at or below this: a long-term modulus of at least 0.1% of the instantaneous one
#: (the solver's `long_term` factor 1 / (1 - sum g) at most 1000)
SUM_G_MAX = 0.999
STARTS = 4  # the NNLS start plus seeded perturbations of it
#: per start: redundant terms drift along flat directions for thousands of steps without
#: changing the fit (5 terms fitted to the tests' 3-term DMA at 1% noise: 3000 instead moved the
#: master curve by ~1e-4 relative and took 6 times as long)
MAX_EVALUATIONS = 400
GAS_CONSTANT = 8.314462618  # J/(mol K)
KELVIN = 273.15
SHIFTS = ("wlf", "arrhenius")
#: relative shifts of neighbouring temperatures are searched over this many decades, and need
#: this much overlap (decades) of their frequency ranges
SHIFT_SEARCH_DECADES = 12.0
MIN_OVERLAP_DECADES = 0.2
_G_FLOOR = 1e-12  # weights below this are no term (interconversion drops them)
_WHY_INFINITE = "the data do not determine it (a term outside the data's span, or one of two " \
                "terms that act together)"


# ---- forward functions ---------------------------------------------------------------------------

def _arrays(terms: Sequence[dict]) -> tuple[np.ndarray, np.ndarray]:
    g = np.array([float(t["g"]) for t in terms], dtype=np.float64)
    tau = np.array([float(t["tau_s"]) for t in terms], dtype=np.float64)
    return g, tau


def _terms(g: np.ndarray, tau: np.ndarray) -> tuple[dict, ...]:
    order = np.argsort(tau)
    return tuple({"g": float(g[i]), "k": 0.0, "tau_s": float(tau[i])} for i in order)


def _relaxation(g: np.ndarray, tau: np.ndarray, t: np.ndarray) -> np.ndarray:
    t = np.asarray(t, dtype=np.float64)
    return 1.0 - np.sum(g * -np.expm1(-t[..., None] / tau), axis=-1)


def relaxation_ratio(terms: Sequence[dict], time_s) -> np.ndarray:
    """g_R(t) = G(t) / G(0) = 1 - sum g_i (1 - exp(-t / tau_i)) at times `time_s` (s); `terms`
    are {"g", "tau_s"} dicts (as a material's `prony` list)."""
    return _relaxation(*_arrays(terms), time_s)


def _merged(g: np.ndarray, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Terms with g above the floor, equal times merged (an interconversion needs distinct rates:
    two terms with one tau are one term), sorted by tau descending (rates ascending)."""
    keep = g > _G_FLOOR
    g, tau = g[keep], tau[keep]
    order = np.argsort(-tau)
    g, tau = g[order], tau[order]
    out_g: list[float] = []
    out_tau: list[float] = []
    for gi, ti in zip(g, tau):
        if out_tau and abs(ti - out_tau[-1]) <= 1e-12 * out_tau[-1]:
            out_g[-1] += gi
        else:
            out_g.append(gi)
            out_tau.append(ti)
    return np.array(out_g), np.array(out_tau)


def _pole_roots(poles: np.ndarray, weights: np.ndarray, offset: float,
                low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """Zeros x of h(x) = offset + sum_i w_i p_i / (p_i - x), one in each bracket [low_k, high_k]
    (positive), where h rises from negative to positive (it rises between neighbouring poles, as
    its derivative sum w_i p_i / (p_i - x)^2 is positive). Bisection in log x for all brackets at
    once: 64 halvings take a bracket of up to 100 in ln x (the widest here: ln 1000^10 = 69) to
    5e-18, below the spacing of float64."""
    lo, hi = np.log(low), np.log(high)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for _ in range(64):
            mid = 0.5 * (lo + hi)
            x = np.exp(mid)
            h = offset + np.sum(weights * poles / (poles - x[:, None]), axis=1)
            below = h < 0.0
            lo = np.where(below, mid, lo)
            hi = np.where(below, hi, mid)
    return np.exp(0.5 * (lo + hi))


def retardation_spectrum(g, tau_s) -> tuple[np.ndarray, np.ndarray]:
    """Creep (retardation) terms (j_k, T_k in s) of a relaxation Prony series (g_i, tau_i):
    J(t) / J(0) = 1 + sum j_k (1 - exp(-t / T_k)), exact (module docstring). Sorted by T."""
    g, tau = _merged(np.asarray(g, float), np.asarray(tau_s, float))
    if g.size == 0:
        return np.zeros(0), np.zeros(0)
    lam = 1.0 / tau  # ascending
    # zeros of 1 - sum g_i lam_i / (lam_i + s) at s = -mu: h(mu) = -1 + sum g_i lam_i/(lam_i - mu)
    # rises from -inf to +inf between neighbouring rates; below the slowest it rises from
    # sum g - 1 < 0 and is negative below lam_0 (1 - sum g), so the slowest zero lies above that
    low = np.concatenate([[lam[0] * (1.0 - g.sum())], lam[:-1]])
    mu = _pole_roots(lam, g, -1.0, low, lam)
    j = 1.0 / (mu * np.sum(g * lam / (lam - mu[:, None]) ** 2, axis=1))
    order = np.argsort(1.0 / mu)
    return j[order], (1.0 / mu)[order]


def relaxation_spectrum(j, retardation_s) -> tuple[np.ndarray, np.ndarray]:
    """Relaxation terms (g_i, tau_i in s) of a retardation series (j_k >= 0, T_k), the converse
    of `retardation_spectrum`: g_R = 1 - sum g_i (1 - exp(-t / tau_i)) has the creep compliance
    J / J(0) = 1 + sum j_k (1 - exp(-t / T_k)). Sorted by tau."""
    j, T = _merged(np.asarray(j, float), np.asarray(retardation_s, float))
    if j.size == 0:
        return np.zeros(0), np.zeros(0)
    nu = 1.0 / T  # ascending
    # poles of s G^ at s = -lam: H(lam) = 1 + sum j_k nu_k / (nu_k - lam) rises from -inf to +inf
    # between neighbouring rates; above the fastest it rises from -inf and is >= 0 from
    # nu_max (1 + sum j) on
    high = np.concatenate([nu[1:], [nu[-1] * (1.0 + j.sum()) * (1.0 + 1e-12)]])
    lam = _pole_roots(nu, j, 1.0, nu, high)
    g = 1.0 / (lam * np.sum(j * nu / (nu - lam[:, None]) ** 2, axis=1))
    order = np.argsort(1.0 / lam)
    return g[order], (1.0 / lam)[order]


def _creep(g: np.ndarray, tau: np.ndarray, t: np.ndarray) -> np.ndarray:
    j, T = retardation_spectrum(g, tau)
    t = np.asarray(t, dtype=np.float64)
    return 1.0 + np.sum(j * -np.expm1(-t[..., None] / T), axis=-1)


def creep_ratio(terms: Sequence[dict], time_s) -> np.ndarray:
    """J(t) / J(0), the creep compliance normalised by its instantaneous value, of the relaxation
    Prony terms {"g", "tau_s"} at times `time_s` (s): the exact solution of the Volterra relation
    (module docstring). It rises from 1 to 1 / (1 - sum g)."""
    return _creep(*_arrays(terms), time_s)


def _dma(g: np.ndarray, tau: np.ndarray, e0: float, f_hz: np.ndarray
         ) -> tuple[np.ndarray, np.ndarray]:
    wt = 2.0 * np.pi * np.asarray(f_hz, dtype=np.float64)[..., None] * tau
    storage = e0 * (1.0 - np.sum(g, axis=-1) + np.sum(g * wt**2 / (1.0 + wt**2), axis=-1))
    loss = e0 * np.sum(g * wt / (1.0 + wt**2), axis=-1)
    return storage, loss


def dma_moduli(terms: Sequence[dict], e0: float, f_hz) -> tuple[np.ndarray, np.ndarray]:
    """Storage and loss moduli (Pa) E'(w), E''(w) at frequencies `f_hz` (Hz, w = 2 pi f) of the
    Prony terms with instantaneous modulus `e0` (Pa)."""
    return _dma(*_arrays(terms), float(e0), f_hz)


def wlf_log10_shift(temperature_c, c1: float, c2_k: float, reference_c: float) -> np.ndarray:
    """WLF log10 a_T = -C1 (T - Tr) / (C2 + T - Tr) (temperatures in C, C2 in K)."""
    d = np.asarray(temperature_c, dtype=np.float64) - reference_c
    return -c1 * d / (c2_k + d)


def arrhenius_log10_shift(temperature_c, activation_energy_j_mol: float,
                          reference_c: float) -> np.ndarray:
    """Arrhenius log10 a_T = Ea / (R ln 10) (1/T - 1/Tr), T and Tr in kelvin (given in C)."""
    t = np.asarray(temperature_c, dtype=np.float64) + KELVIN
    return activation_energy_j_mol / (GAS_CONSTANT * math.log(10.0)) * (
        1.0 / t - 1.0 / (reference_c + KELVIN))


# ---- result --------------------------------------------------------------------------------------

def _finite_or_none(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None


@dataclass(frozen=True)
class PronyFit:
    """A fitted Prony series.

    `terms`: {"g", "k", "tau_s"} dicts sorted by tau (k = 0: a test in shear or tension relaxes
    the deviatoric part; `merge_prony(..., bulk=True)` copies g to k). `r2`: coefficient of
    determination of the fitted quantity (the ratio; for DMA ln E' and ln E'' together, each about
    its own mean). `standard_errors`: "g" and "tau_s" per term (s), and for DMA
    "instantaneous_modulus_pa" and the shift constants; inf where the data do not determine it.
    `instantaneous_modulus_pa`: E0 of a DMA fit (Pa), else None. `shift`: the shift model, its
    constants, reference temperature and per-temperature log10 a_T (DMA at several temperatures),
    else None. `rms_residual`: RMS of the fitted residuals (ratio units; for DMA in ln modulus,
    about the relative error). `notes`: one per parameter the data do not determine."""

    terms: tuple[dict, ...]
    r2: float
    standard_errors: dict[str, Any]
    instantaneous_modulus_pa: float | None = None
    shift: dict[str, Any] | None = None
    test: str = "relaxation"
    rms_residual: float = 0.0
    points: int = 0
    notes: tuple[str, ...] = field(default=())

    @property
    def sum_g(self) -> float:
        return float(sum(t["g"] for t in self.terms))

    @property
    def prony(self) -> list[dict]:
        """The terms as a material's `prony` list."""
        return [dict(t) for t in self.terms]

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe (non-finite numbers as None), SI keys."""
        errors: dict[str, Any] = {}
        for key, value in self.standard_errors.items():
            errors[key] = ([_finite_or_none(v) for v in value] if isinstance(value, (list, tuple))
                           else _finite_or_none(value))
        out: dict[str, Any] = {
            "model": "prony", "test": self.test, "terms": self.prony, "sum_g": self.sum_g,
            "r2": _finite_or_none(self.r2), "rms_residual": _finite_or_none(self.rms_residual),
            "points": self.points, "standard_errors": errors, "notes": list(self.notes),
            "instantaneous_modulus_pa": self.instantaneous_modulus_pa,
            "long_term_modulus_pa": (None if self.instantaneous_modulus_pa is None
                                     else self.instantaneous_modulus_pa * (1.0 - self.sum_g)),
            "shift": self.shift,
        }
        return out


# ---- input checks --------------------------------------------------------------------------------

def _vector(values, name: str, n: int | None = None) -> np.ndarray:
    try:
        a = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected numbers") from None
    if a.ndim != 1:
        raise InputError(f"{name}: expected a 1-D sequence of numbers, got shape {a.shape}")
    if n is not None and a.size != n:
        raise InputError(f"{name}: {a.size} values, expected {n} (one per point)")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise InputError(f"{name}[{bad[0]}] = {a[bad[0]]}: expected a finite number")
    return a


def _check_each(a: np.ndarray, name: str, low: float, high: float, low_open: bool,
                note: str = "") -> None:
    """Every value of `a` in the range, else `check_range`'s `InputError` for the first one
    outside it, named "name[i]"."""
    bad = np.flatnonzero(~((a > low if low_open else a >= low) & (a <= high)))
    if bad.size:
        check_range(f"{name}[{bad[0]}]", a[bad[0]], low, high, low_open=low_open, note=note)


def _check_terms(terms: Any, points: int, span_decades: float, what: str) -> int:
    terms = check_integer("terms", terms, 1, MAX_TERMS)
    if points <= 2 * terms:
        raise InputError(f"{what}: {points} points are too few for {terms} terms "
                         f"(need more than 2 x terms = {2 * terms})")
    if terms > 1 and span_decades < 1.0:
        warnings.warn(f"{what} spans {span_decades:.2g} decades (under one): {terms} Prony terms "
                      "will not be determined by the data; fewer terms or a longer test",
                      InputWarning, stacklevel=3)
    return terms


def _time_data(time_s, ratio, terms, creep: bool) -> tuple[np.ndarray, np.ndarray, int]:
    t = _vector(time_s, "time_s")
    r = _vector(ratio, "ratio", t.size)
    _check_each(t, "time_s", 0.0, math.inf, False)
    positive = t[t > 0]
    if np.unique(positive).size < 2:
        raise InputError("time_s: need at least two distinct positive times")
    if creep:
        _check_each(r, "ratio", 1.0 - RATIO_SLACK, math.inf, False,
                    "give J(t)/J(0), the creep compliance over its instantaneous value")
    else:
        _check_each(r, "ratio", 0.0, 1.0 + RATIO_SLACK, True,
                    "give G(t)/G(0), the modulus over its instantaneous value, not the "
                    "modulus in Pa")
    span = math.log10(positive.max() / positive.min())
    n = _check_terms(terms, t.size, span, "time_s")
    return t, r, n


# ---- fitting machinery ---------------------------------------------------------------------------

def _grid(low: float, high: float) -> np.ndarray:
    """Log grid of times over [low, high] widened by WIDEN_DECADES each side, GRID_PER_DECADE per
    decade."""
    a, b = math.log10(low) - WIDEN_DECADES, math.log10(high) + WIDEN_DECADES
    return np.logspace(a, b, max(2, int(math.ceil((b - a) * GRID_PER_DECADE)) + 1))


def _reduce(weights: np.ndarray, tau: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """`n` terms from a sparse NNLS spectrum: the smallest weight merged into its nearer
    neighbour in log tau (weights added, log tau weight-averaged) until n are left; when fewer
    than n were found, the largest is split into two half-weights a decade apart (the refinement
    moves them; the data may not need them, and their standard errors then say so)."""
    w = list(weights[weights > 0])
    x = list(np.log(tau[weights > 0]))
    if not w:  # nothing relaxes: n small terms spread over the grid
        spread = np.linspace(np.log(tau[0]), np.log(tau[-1]), n + 2)[1:-1]
        return np.full(n, 1e-3), np.exp(spread)
    while len(w) > n:
        i = int(np.argmin(w))
        left = x[i] - x[i - 1] if i > 0 else math.inf
        right = x[i + 1] - x[i] if i + 1 < len(w) else math.inf
        k = i - 1 if left <= right else i + 1
        total = w[i] + w[k]
        x[k] = (w[i] * x[i] + w[k] * x[k]) / total
        w[k] = total
        del w[i], x[i]
    while len(w) < n:
        i = int(np.argmax(w))
        half = 0.5 * math.log(10.0)
        w[i:i + 1] = [w[i] / 2, w[i] / 2]
        x[i:i + 1] = [x[i] - half, x[i] + half]
    return np.array(w), np.exp(np.array(x))


def _stick(u: np.ndarray) -> np.ndarray:
    """g_i = SUM_G_MAX u_i prod_{j<i} (1 - u_j) for u_i in [0, 1]: g_i >= 0 and
    sum g = SUM_G_MAX (1 - prod (1 - u_i)) <= SUM_G_MAX < 1."""
    return SUM_G_MAX * u * np.concatenate([[1.0], np.cumprod(1.0 - u)[:-1]])


def _unstick(g: np.ndarray) -> np.ndarray:
    """The u of `_stick` for weights g (scaled inside the bound if a start reaches it)."""
    g = np.clip(g, 0.0, None) / SUM_G_MAX
    if g.sum() >= 1.0:
        g = g * (0.999 / g.sum())
    before = np.concatenate([[0.0], np.cumsum(g)[:-1]])
    return np.clip(g / (1.0 - before), 0.0, 1.0)


def _polish(residuals: Callable[[np.ndarray], np.ndarray], x0: np.ndarray, lower: np.ndarray,
            upper: np.ndarray, n: int, seed: int) -> np.ndarray:
    """Bounded least squares from x0 and from STARTS - 1 seeded perturbations of it (log tau by
    a normal of half a decade, shares u by a factor e^N(0, 0.3)); the best of them. x = (u (n),
    ln tau (n), extra...)."""
    rng = np.random.default_rng(seed)
    starts = [x0]
    for _ in range(STARTS - 1):
        x = x0.copy()
        x[:n] = x[:n] * np.exp(rng.normal(0.0, 0.3, n))
        x[n:2 * n] = x[n:2 * n] + rng.normal(0.0, 0.5 * math.log(10.0), n)
        starts.append(x)
    best, best_cost = x0, math.inf
    for x in starts:
        x = np.clip(x, lower, upper)
        solution = least_squares(residuals, x, bounds=(lower, upper), method="trf",
                                 x_scale="jac", ftol=1e-12, xtol=1e-12, gtol=1e-12,
                                 max_nfev=MAX_EVALUATIONS)
        if solution.cost < best_cost:
            best, best_cost = solution.x, solution.cost
    return best


def _jacobian(fun: Callable[[np.ndarray], np.ndarray], p: np.ndarray, forward: np.ndarray
              ) -> np.ndarray:
    """Finite-difference Jacobian (central; forward where `forward`, a weight on its bound of
    zero). Steps 1e-6 of max(|p|, 1e-3): exact to ~1e-9 relative, which the rank tolerance of
    `identifiability` assumes."""
    steps = 1e-6 * np.maximum(np.abs(p), 1e-3)
    columns = []
    for i, h in enumerate(steps):
        e = np.zeros_like(p)
        e[i] = h
        if forward[i]:
            columns.append((fun(p + e) - fun(p)) / h)
        else:
            columns.append((fun(p + e) - fun(p - e)) / (2.0 * h))
    return np.stack(columns, axis=1)


def _errors(model: Callable[[np.ndarray], np.ndarray], p: np.ndarray, n: int,
            mapping_diagonal: np.ndarray, names: list[str]) -> tuple[dict[str, float], np.ndarray]:
    """Standard errors of the parameters named `names`, p = (g (n), ln tau (n), extra...) with
    the parameters diag(mapping_diagonal) applied to p's linearisation (tau_i for ln tau_i)."""
    forward = np.zeros(p.size, bool)
    forward[:n] = p[:n] < 1e-5
    jac = _jacobian(model, p, forward)
    err = standard_errors(jac, model(p), np.diag(mapping_diagonal))
    return dict(zip(names, (float(e) for e in err))), err


def r_squared(residual: np.ndarray, data: np.ndarray) -> float:
    """1 - SS_res / SS_tot; NaN when the data do not vary (SS_tot = 0)."""
    total = float(np.sum((data - data.mean()) ** 2))
    return 1.0 - float(residual @ residual) / total if total > 0 else math.nan


def _time_fit(t: np.ndarray, r: np.ndarray, n: int, seed: int, creep: bool,
              reference_time_s: float = 0.0) -> PronyFit:
    positive = t[t > 0]
    t_low, t_high = positive.min(), positive.max()
    if creep:
        # start: a retardation spectrum on the grid (linear in j), converted exactly
        retard = _grid(t_low, t_high)
        basis = -np.expm1(-t[:, None] / retard)
        j, _ = nnls(basis, r - 1.0)
        j0, T0 = _reduce(j, retard, n)
        g0, tau0 = relaxation_spectrum(j0, T0)
        g0 = np.concatenate([g0, np.full(n - g0.size, 1e-3)])
        tau0 = np.concatenate([tau0, np.full(n - tau0.size, math.sqrt(t_low * t_high))])
        # relaxation times are shorter than retardation times, by up to J(inf)/J(0) = 1/(1 - sum g)
        low = t_low / 10.0 ** WIDEN_DECADES / max(1.0, float(r.max())) / 2.0
        forward_fn = _creep
    else:
        grid = _grid(t_low, t_high)
        basis = -np.expm1(-t[:, None] / grid)
        w, _ = nnls(basis, 1.0 - r)
        g0, tau0 = _reduce(w, grid, n)
        low = t_low / 10.0 ** WIDEN_DECADES
        forward_fn = _relaxation
    high = t_high * 10.0 ** WIDEN_DECADES
    tau0 = np.clip(tau0, low * 1.0001, high / 1.0001)

    def model(g, tau):
        """The ratio the data give: to the instantaneous value, or to that at the reference
        time (a modulus normalised by its first measured value)."""
        values = forward_fn(g, tau, t)
        if reference_time_s > 0.0:
            values = values / forward_fn(g, tau, np.array([reference_time_s]))[0]
        return values

    def residual_p(p):
        return model(p[:n], np.exp(p[n:])) - r

    def residual_x(x):
        return residual_p(np.concatenate([_stick(x[:n]), x[n:]]))

    lower = np.concatenate([np.zeros(n), np.full(n, math.log(low))])
    upper = np.concatenate([np.ones(n), np.full(n, math.log(high))])
    x = _polish(residual_x, np.concatenate([_unstick(g0), np.log(tau0)]), lower, upper, n, seed)
    g, tau = _stick(x[:n]), np.exp(x[n:])
    order = np.argsort(tau)
    g, tau = g[order], tau[order]
    p = np.concatenate([g, np.log(tau)])
    names = [f"g[{i}]" for i in range(n)] + [f"tau_s[{i}]" for i in range(n)]
    errors, err = _errors(residual_p, p, n, np.concatenate([np.ones(n), tau]), names)
    res = residual_p(p)
    values = dict(zip(names, np.concatenate([g, tau])))
    notes = identification_notes(values, errors, _WHY_INFINITE)
    return PronyFit(terms=_terms(g, tau), r2=r_squared(res, r),
                    standard_errors={"g": tuple(float(e) for e in err[:n]),
                                     "tau_s": tuple(float(e) for e in err[n:2 * n])},
                    test="creep" if creep else "relaxation",
                    rms_residual=float(np.sqrt(np.mean(res**2))), points=int(t.size),
                    notes=tuple(notes.values()))


# ---- public fits ---------------------------------------------------------------------------------

def fit_relaxation(time_s, ratio, terms: int, *, seed: int = 0,
                   reference_time_s: float = 0.0) -> PronyFit:
    """Prony terms of a stress-relaxation test: `time_s` (s, >= 0) and `ratio` = G(t)/G(0) in
    (0, 1] (up to 1.05 accepted as noise around the instantaneous value), `terms` in 1..10, more
    points than 2 x terms. `reference_time_s` > 0: the ratio is G(t)/G(t_ref) instead, as a
    modulus normalised by its first measured value (a test whose first point comes after its
    loading ramp) gives it; the fit then compares g_R(t)/g_R(t_ref). Seeded and deterministic."""
    t, r, n = _time_data(time_s, ratio, terms, creep=False)
    return _time_fit(t, r, n, seed, creep=False, reference_time_s=_reference(reference_time_s))


def fit_creep(time_s, ratio, terms: int, *, seed: int = 0,
              reference_time_s: float = 0.0) -> PronyFit:
    """Relaxation Prony terms of a creep test: `time_s` (s, >= 0) and `ratio` = J(t)/J(0) >= 1
    (down to 0.95 accepted as noise), the creep compliance over its instantaneous value
    (`reference_time_s` > 0: over its value at that time, as for `fit_relaxation`). The
    terms' exact creep compliance (`creep_ratio`) is fitted to the data. Relaxation times may lie
    up to J(inf)/J(0) times below the data's span (a creep test sees retardation times, which
    are the longer ones)."""
    t, r, n = _time_data(time_s, ratio, terms, creep=True)
    return _time_fit(t, r, n, seed, creep=True, reference_time_s=_reference(reference_time_s))


def _reference(value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value) or value < 0.0:
        raise InputError(f"reference_time_s = {value!r}: expected a finite time >= 0 (s)")
    return float(value)


def _shift_function(shift: str, temperature: np.ndarray, reference: float
                    ) -> Callable[[np.ndarray], np.ndarray]:
    if shift == "wlf":
        return lambda c: wlf_log10_shift(temperature, c[0], c[1], reference)
    return lambda c: arrhenius_log10_shift(temperature, c[0], reference)


def _pair_shift(xa, sa, la, xb, sb, lb) -> float:
    """log10 shift d of curve a (log10 frequency xa, ln storage sa, ln loss la) onto curve b:
    the d minimising the mean squared difference of both ln moduli over the overlap of the
    frequency ranges (a's points interpolated on b and b's on a), searched on a 0.02-decade
    grid over +-SHIFT_SEARCH_DECADES with at least MIN_OVERLAP_DECADES of overlap."""
    ia, ib = np.argsort(xa), np.argsort(xb)
    xa, sa, la = xa[ia], sa[ia], la[ia]
    xb, sb, lb = xb[ib], sb[ib], lb[ib]
    best, best_d = math.inf, 0.0
    for d in np.arange(-SHIFT_SEARCH_DECADES, SHIFT_SEARCH_DECADES + 1e-9, 0.02):
        xs = xa + d
        lo, hi = max(xs[0], xb[0]), min(xs[-1], xb[-1])
        if hi - lo < MIN_OVERLAP_DECADES:
            continue
        ina = (xs >= lo) & (xs <= hi)
        inb = (xb >= lo) & (xb <= hi)
        if ina.sum() + inb.sum() < 3:
            continue
        diffs = np.concatenate([
            sa[ina] - np.interp(xs[ina], xb, sb), la[ina] - np.interp(xs[ina], xb, lb),
            np.interp(xb[inb], xs, sa) - sb[inb], np.interp(xb[inb], xs, la) - lb[inb]])
        cost = float(np.mean(diffs**2))
        if cost < best:
            best, best_d = cost, float(d)
    return best_d


def _free_shifts(temps: np.ndarray, x: np.ndarray, s: np.ndarray, l: np.ndarray,
                 reference: float) -> np.ndarray:
    """log10 a_T per distinct temperature (sorted), from neighbour-to-neighbour shifts, zero at
    the temperature nearest the reference."""
    levels = np.unique(temps)
    shifts = np.zeros(levels.size)
    for k in range(1, levels.size):
        a, b = temps == levels[k], temps == levels[k - 1]
        # a (warmer) shifted onto b: log10 a_T(a) - log10 a_T(b) = d
        shifts[k] = shifts[k - 1] + _pair_shift(x[a], s[a], l[a], x[b], s[b], l[b])
    return shifts - shifts[np.argmin(np.abs(levels - reference))]


def _initial_constants(shift: str, levels: np.ndarray, free: np.ndarray, reference: float,
                       c2_low: float) -> np.ndarray:
    """Shift constants fitted to free per-temperature shifts known up to a common offset (the
    free shifts are zero at the nearest measured temperature, not at the reference): the offset
    is eliminated as the mean residual."""
    if shift == "arrhenius":
        xk = (1.0 / (levels + KELVIN) - 1.0 / (reference + KELVIN)) / (GAS_CONSTANT * math.log(10))
        xc = xk - xk.mean()
        ea = float(xc @ (free - free.mean()) / (xc @ xc)) if xc @ xc > 0 else 1e5
        return np.array([min(max(ea, 1e3), 1e6)])

    def resid(c):
        r = wlf_log10_shift(levels, c[0], c[1], reference) - free
        return r - r.mean()

    start = np.array([8.86, max(101.6, c2_low + 10.0)])
    solution = least_squares(resid, start, bounds=([1e-3, c2_low], [100.0, 5000.0]),
                             x_scale="jac")
    return solution.x


def fit_dma(frequency_hz, storage_pa, loss_pa, terms: int, *, temperature_c=None,
            shift: str = "wlf", reference_c: float | None = None, seed: int = 0) -> PronyFit:
    """Prony terms and instantaneous modulus E0 (Pa) of a DMA test: storage and loss moduli (Pa,
    > 0) at frequencies (Hz, > 0), optionally at temperatures (C, one per point).

    With several temperatures the points are shifted to a master curve at `reference_c` (default
    the median temperature of the points) by `shift` ("wlf" or "arrhenius"), whose constants are
    fitted together with the terms (started from neighbour-to-neighbour shifts over the
    overlapping frequencies); `PronyFit.shift` reports them and log10 a_T per temperature. The
    fitted residuals are ln(model / measured) of E' and E''. A DMA in tension gives the terms of
    E(t); for a nearly incompressible material they are those of G(t) too."""
    f = _vector(frequency_hz, "frequency_hz")
    storage = _vector(storage_pa, "storage_pa", f.size)
    loss = _vector(loss_pa, "loss_pa", f.size)
    _check_each(f, "frequency_hz", 0.0, math.inf, True)
    _check_each(storage, "storage_pa", 0.0, math.inf, True)
    _check_each(loss, "loss_pa", 0.0, math.inf, True)
    if shift not in SHIFTS:
        raise InputError(f"shift = {shift!r}: allowed {', '.join(SHIFTS)}")
    if temperature_c is None:
        temps = np.zeros(f.size)
        several = False
    else:
        temps = _vector(temperature_c, "temperature_c", f.size)
        _check_each(temps, "temperature_c", -KELVIN, math.inf, True)
        several = np.unique(temps).size > 1
    if reference_c is None:
        reference = float(np.median(temps))
    else:
        if isinstance(reference_c, bool) or not isinstance(reference_c, (int, float)) \
                or not math.isfinite(reference_c) or reference_c <= -KELVIN:
            raise InputError(f"reference_c = {reference_c!r}: expected a temperature in C "
                             f"above {-KELVIN:g}")
        reference = float(reference_c)
    n = _check_terms(terms, f.size, math.log10(f.max() / f.min()), "frequency_hz")

    x_log = np.log10(f)
    ls, ll = np.log(storage), np.log(loss)
    data = np.concatenate([ls, ll])
    levels = np.unique(temps)
    if several:
        free = _free_shifts(temps, x_log, ls, ll, reference)
        c2_low = float(max(0.0, np.max(reference - levels))) + 1.0  # C2 + T - Tr > 0 everywhere
        constants0 = _initial_constants(shift, levels, free, reference, c2_low)
        shift_of = _shift_function(shift, temps, reference)
        if shift == "wlf":
            c_lower, c_upper = np.array([1e-3, c2_low]), np.array([100.0, 5000.0])
            constants0 = np.clip(constants0, c_lower, c_upper)
        else:
            c_lower, c_upper = np.array([1e3]), np.array([1e6])
        log_a0 = shift_of(constants0)
    else:
        constants0 = np.zeros(0)
        c_lower = c_upper = np.zeros(0)
        shift_of = None
        log_a0 = np.zeros(f.size)

    # start: E_inf and E0 g_i on a grid of relaxation times over the reduced range, by NNLS on
    # relative residuals (each row divided by its measurement)
    omega = 2.0 * np.pi * f * 10.0 ** log_a0
    grid = _grid(1.0 / omega.max(), 1.0 / omega.min())
    wt = omega[:, None] * grid
    a = np.vstack([np.column_stack([np.ones(f.size), wt**2 / (1.0 + wt**2)]) / storage[:, None],
                   np.column_stack([np.zeros(f.size), wt / (1.0 + wt**2)]) / loss[:, None]])
    e, _ = nnls(a, np.ones(2 * f.size))
    e0_start = float(e.sum()) if e.sum() > 0 else float(storage.max())
    g0, tau0 = _reduce(e[1:] / e0_start, grid, n)
    low, high = grid[0], grid[-1]
    tau0 = np.clip(tau0, low * 1.0001, high / 1.0001)
    nc = constants0.size

    def model(p):
        g, tau, e0 = p[:n], np.exp(p[n:2 * n]), math.exp(p[2 * n])
        log_a = shift_of(p[2 * n + 1:]) if nc else 0.0
        sp, lp = _dma(g, tau, e0, f * 10.0 ** log_a)
        return np.concatenate([np.log(sp), np.log(np.maximum(lp, 1e-300))]) - data

    def residual_x(x):
        return model(np.concatenate([_stick(x[:n]), x[n:]]))

    e0_low, e0_high = float(storage.min()) * 1e-3, float(storage.max()) * 1e3
    lower = np.concatenate([np.zeros(n), np.full(n, math.log(low)), [math.log(e0_low)], c_lower])
    upper = np.concatenate([np.ones(n), np.full(n, math.log(high)), [math.log(e0_high)],
                            c_upper])
    x0 = np.concatenate([_unstick(g0), np.log(tau0), [math.log(e0_start)], constants0])
    x = _polish(residual_x, x0, lower, upper, n, seed)
    g, tau = _stick(x[:n]), np.exp(x[n:2 * n])
    order = np.argsort(tau)
    g, tau = g[order], tau[order]
    e0 = math.exp(x[2 * n])
    constants = x[2 * n + 1:]
    p = np.concatenate([g, np.log(tau), [math.log(e0)], constants])

    constant_names = {"wlf": ["c1", "c2_k"], "arrhenius": ["activation_energy_j_mol"]}[shift] \
        if nc else []
    names = ([f"g[{i}]" for i in range(n)] + [f"tau_s[{i}]" for i in range(n)]
             + ["instantaneous_modulus_pa"] + constant_names)
    errors, err = _errors(model, p, n, np.concatenate([np.ones(n), tau, [e0], np.ones(nc)]),
                          names)
    res = model(p)
    values = dict(zip(names, np.concatenate([g, tau, [e0], constants])))
    notes = identification_notes(values, errors, _WHY_INFINITE)
    r2 = 1.0 - float(res @ res) / float(np.sum((ls - ls.mean()) ** 2)
                                        + np.sum((ll - ll.mean()) ** 2))
    se: dict[str, Any] = {"g": tuple(float(v) for v in err[:n]),
                          "tau_s": tuple(float(v) for v in err[n:2 * n]),
                          "instantaneous_modulus_pa": float(err[2 * n])}
    shift_out = None
    if nc:
        for name, value in zip(constant_names, err[2 * n + 1:]):
            se[name] = float(value)
        per_level = _shift_function(shift, levels, reference)(constants)
        shift_out = {"model": shift, **{k: float(v) for k, v in zip(constant_names, constants)},
                     "reference_c": reference,
                     # + 0.0: the reference's -0.0 reads 0
                     "log10_a_t": [{"temperature_c": float(tl), "log10_a_t": float(v) + 0.0}
                                   for tl, v in zip(levels, per_level)]}
    return PronyFit(terms=_terms(g, tau), r2=r2, standard_errors=se, instantaneous_modulus_pa=e0,
                    shift=shift_out, test="dma", rms_residual=float(np.sqrt(np.mean(res**2))),
                    points=int(f.size), notes=tuple(notes.values()))


# ---- into a material -----------------------------------------------------------------------------

def merge_prony(material: dict, prony: Sequence[dict], *, bulk: bool = False,
                where: str = "material") -> dict:
    """A copy of `material` (a ball file layer's `material` object) with `prony` replaced by the
    given terms ({"g", "tau_s"}; k_i = g_i when `bulk`, so the bulk modulus relaxes alike, else
    0), checked by `constitutive.material_from_dict` (its errors name the key, prefixed by
    `where`).

    The material's constants and `moduli` are kept as they are. With `moduli: long_term` (the
    default) they are the relaxed moduli: the solver scales the deviatoric constants by
    1 / (1 - sum g) (and the bulk one by 1 / (1 - sum k)) to get the instantaneous ones, so adding
    a Prony series makes the ball stiffer at impact -- right for constants from slow (quasi-static)
    tests. Constants measured at impact rates are instantaneous: set `moduli: instantaneous`."""
    from ..constitutive import material_from_dict  # the FE package is heavy: loaded when used

    if not isinstance(material, dict):
        raise InputError(f"{where}: expected an object, got {type(material).__name__}")
    terms = []
    for i, term in enumerate(prony):
        if not isinstance(term, dict) or "g" not in term or "tau_s" not in term:
            raise InputError(f"{where}.prony[{i}]: expected an object with g and tau_s")
        g, tau = (float(v) if isinstance(v, np.generic) else v for v in (term["g"], term["tau_s"]))
        terms.append({"g": g, "k": g if bulk else 0.0, "tau_s": tau})
    out = {**material, "prony": terms}
    material_from_dict(out, where)
    return out
