"""What a least-squares fit determines: linearised standard errors from the Jacobian at the
optimum, inf where the data do not determine a parameter, and the "not identified" rule with its
note. One rule for every fit that reports standard errors (the lumped `fit`, the calibration's
gradient refinement), so that their numbers and notes mean the same.
"""

from __future__ import annotations

import math

import numpy as np

#: singular values of the Jacobian (columns scaled to unit length, so that no unit decides) below
#: this fraction of the largest are directions the data do not determine: the fits' Jacobians are
#: finite differences exact to ~1e-9 relative, so smaller ones are round-off
RANK_TOLERANCE = 1e-8
#: a parameter whose gradient has a component (relative) above this along such a direction is
#: undetermined
NULL_COMPONENT = 1e-6


def standard_errors(jacobian: np.ndarray, residuals: np.ndarray,
                    mapping: np.ndarray | None = None, correlation: float = 1.0) -> np.ndarray:
    """Linearised standard errors of parameters p = mapping @ x, for a least-squares fit in the
    coordinates x with `jacobian` (M, d) of the residuals and `residuals` (M,) at the optimum:
    s^2 (J^T J)^-1 with s^2 = RSS / (M - d), mapped by `mapping` (P, d; default the identity,
    the coordinates themselves).

    A parameter that the data do not determine -- it depends on a coordinate with no effect on
    the residuals (a zero column), or on a combination of coordinates whose effects cancel (two
    that only act together) -- gets inf: its variance is unbounded (a pseudo-inverse would give
    it 0, the most certain value of all). The others get the variance of their determined part,
    from the singular value decomposition restricted to the determined directions. A parameter
    that depends on no coordinate (fixed) gets 0; all the rest inf when M <= d (no degrees of
    freedom for s^2). `correlation` (>= 1, see `correlation_factor`) multiplies the variances:
    residuals that are correlated carry fewer independent pieces of information than their
    number."""
    m, d = jacobian.shape
    mapping = np.eye(d) if mapping is None else np.asarray(mapping, float)
    depends = np.any(mapping != 0, axis=1)
    if m <= d:
        return np.where(depends, np.inf, 0.0)
    norms = np.linalg.norm(jacobian, axis=0)
    safe = np.where(norms > 0, norms, 1.0)  # columns scaled to unit length: no unit decides
    _, singular, vt = np.linalg.svd(jacobian / safe, full_matrices=False)
    determined = (singular > RANK_TOLERANCE * singular[0]) if singular[0] > 0 \
        else np.zeros(singular.size, bool)
    gradient = mapping / safe  # d p / d (scaled coordinate)
    along = gradient @ vt[determined].T / singular[determined]
    variance = correlation * residuals @ residuals / (m - d) * np.sum(along**2, axis=1)
    null = np.linalg.norm(gradient @ vt[~determined].T, axis=1)
    variance[null > NULL_COMPONENT * np.linalg.norm(gradient, axis=1)] = np.inf
    return np.sqrt(np.where(depends, variance, 0.0))


def identification_notes(values: dict[str, float], errors: dict[str, float],
                         why_infinite: str) -> dict[str, str]:
    """Parameter -> note, for each parameter whose standard error is infinite or larger than its
    value: the data do not determine it, and its value is one of many that fit as well
    ("k1: not identified (standard error 9.01e+09 > value 4.8e+08)"; an infinite one says
    `why_infinite`). A parameter missing from `errors` is fixed (standard error 0)."""
    notes = {}
    for name, value in values.items():
        error = errors.get(name, 0.0)
        if error <= abs(value):
            continue
        why = f"inf: {why_infinite}" if math.isinf(error) else f"{error:.3g} > value {value:.3g}"
        notes[name] = f"{name}: not identified (standard error {why})"
    return notes


#: lags of the residuals' autocorrelation summed at most (a pulse of a few hundred samples)
MAX_LAG = 200


def correlation_factor(series: list[np.ndarray]) -> float:
    """The integrated autocorrelation time of residual series (each in its order: a pulse's
    samples in time, a curve's in deflection), pooled by length; at least 1.

    s^2 (J^T J)^-1 assumes independent residuals. The residuals of a model against a sampled
    pulse are not: where the model misses the curve's shape, or the FE run's contact force rings
    at another phase than the test was sampled at, neighbouring residuals share their sign, and
    the data hold about n / tau_int independent pieces of information, so the variance is
    tau_int times larger. tau_int = 1 + 2 sum_k rho_k, summed over Geyer's initial positive
    sequence (pairs rho_2j-1 + rho_2j while positive), which stops at the noise and is 1 for
    white residuals up to sampling error."""
    weights, times = [], []
    for r in series:
        r = np.asarray(r, dtype=np.float64)
        r = r - r.mean()
        n = r.size
        power = float(r @ r)
        if n < 4 or power == 0.0:
            continue
        lags = min(MAX_LAG, n // 2)
        rho = np.array([r[:n - k] @ r[k:] / power for k in range(lags + 1)])
        total = 0.0
        for k in range(1, lags - 1, 2):
            pair = rho[k] + rho[k + 1]
            if pair <= 0.0:
                break
            total += pair
        weights.append(n)
        times.append(1.0 + 2.0 * total)
    if not weights:
        return 1.0
    return max(1.0, float(np.average(times, weights=weights)))
