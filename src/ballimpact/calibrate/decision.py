"""Picking one design from a Pareto front (pymoo's decision-making tools).

Methods, on the front's objectives normalised to [0, 1] between its ideal and nadir points:
- `knee` (default): the point farthest below the hyperplane through the front's extreme points
  (each objective's best design), toward the ideal point: where improving one objective starts
  to cost the most in the others. Two points or fewer, or a degenerate plane: the point nearest
  the ideal point.
- `pseudo-weights`: pymoo's `PseudoWeights` with the user's weights (the design whose relative
  position on the front matches them best).
- `high-tradeoff`: pymoo's `HighTradeoffPoints` (the largest loss-to-gain ratio among
  neighbours); the first found, or the knee if there is none.
- `asf`: compromise programming, pymoo's achievement scalarising function with the user's
  weights (the smallest weighted worst normalised objective).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, SimulationError

METHODS = ("knee", "pseudo-weights", "high-tradeoff", "asf")


@dataclass(frozen=True)
class Decision:
    index: int   # into the front
    method: str
    reason: str


def normalise(front: np.ndarray) -> np.ndarray:
    ideal, nadir = front.min(axis=0), front.max(axis=0)
    return (front - ideal) / np.where(nadir > ideal, nadir - ideal, 1.0)


def knee(front: np.ndarray) -> tuple[int, str]:
    f = normalise(front)
    m = f.shape[1]
    nearest = int(np.argmin(np.linalg.norm(f, axis=1)))
    why_nearest = ("nearest to the ideal point of the normalised front "
                   f"(distance {np.linalg.norm(f[nearest]):.3g})")
    extremes = f[np.argmin(f, axis=0)]
    if len(f) <= 2 or m == 1 or len(np.unique(extremes, axis=0)) < m:
        return nearest, why_nearest
    try:
        normal = np.linalg.solve(extremes, np.ones(m))  # plane: f . normal = 1
    except np.linalg.LinAlgError:
        return nearest, why_nearest
    depth = (1.0 - f @ normal) / np.linalg.norm(normal)
    i = int(np.argmax(depth))
    if depth[i] <= 0:
        return nearest, why_nearest
    return i, (f"knee: farthest below the plane through the front's {m} extreme points "
               f"({depth[i]:.3g} in normalised objectives)")


def decide(front: np.ndarray, method: str = "knee", weights=None) -> Decision:
    """Choose a design of `front` (n, n_objectives), minimised objectives."""
    front = np.asarray(front, np.float64)
    if method not in METHODS:
        raise InputError(f"--decision {method!r}: allowed {', '.join(METHODS)}")
    if len(front) == 0:
        raise SimulationError("decision: the front is empty (every design failed; see the "
                              "failure reasons in evaluations.csv)")
    m = front.shape[1]
    if m == 1 or len(front) == 1:
        i = int(np.argmin(front[:, 0]))
        return Decision(i, method, "the best design (one objective or one non-dominated design)")
    if method in ("pseudo-weights", "asf"):
        if weights is None:
            weights = np.full(m, 1.0 / m)
        weights = np.asarray(weights, np.float64)
        if weights.shape != (m,) or np.any(weights < 0) or not weights.sum() > 0:
            raise InputError(f"--weights: expected {m} non-negative numbers (one per objective), "
                             f"not all zero; got {weights.tolist()}")
        weights = weights / weights.sum()
    if method == "knee":
        i, why = knee(front)
    elif method == "pseudo-weights":
        from pymoo.mcdm.pseudo_weights import PseudoWeights

        i = int(PseudoWeights(weights).do(front))
        why = f"pseudo-weights closest to the weights {np.round(weights, 3).tolist()}"
    elif method == "high-tradeoff":
        from pymoo.mcdm.high_tradeoff import HighTradeoffPoints

        found = HighTradeoffPoints().do(front) if len(front) > m else None
        if found is None or len(found) == 0:
            i, why = knee(front)
            why = "no high trade-off point found; " + why
        else:
            i = int(np.atleast_1d(found)[0])
            why = "a high trade-off point (largest loss of the others per gain in one)"
    else:
        from pymoo.decomposition.asf import ASF

        # pymoo's ASF weights divide: a small weight stands for an important objective, so the
        # user's importance weights enter inverted
        importance = np.where(weights > 0, weights, 1e-9)
        i = int(np.argmin(ASF().do(normalise(front), 1.0 / importance)))
        why = f"compromise programming (ASF) with the weights {np.round(weights, 3).tolist()}"
    return Decision(i, method, why)
