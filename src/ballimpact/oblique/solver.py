"""The 3D engine's former entry points, kept for one release: they call `fe.engine` (the one
driver, the geometry a plug-in) and warn (`FutureWarning`). Use `fe.simulate`,
`fe.simulate_batch` and `fe.estimate` with `geometry=fe.Hexahedral(options)` and `target=`."""

from __future__ import annotations

import warnings

from ..fe.engine import estimate, simulate_batch
from ..fe.hex.geometry import Hexahedral
from ..fe.options import Options3D
from ..fe.result import ImpactResult

__all__ = ["ObliqueResult", "estimate_oblique", "simulate_oblique", "simulate_oblique_batch"]

#: the one result type of `fe.engine` (this name: one release)
ObliqueResult = ImpactResult


def _moved(old: str, new: str) -> None:
    warnings.warn(f"oblique.{old} is fe.{new}(..., geometry=fe.Hexahedral(options), "
                  "target=...) (this alias goes in the next release)", FutureWarning,
                  stacklevel=3)


def simulate_oblique(ball, condition, options: Options3D = Options3D(), target=None,
                     progress=None, *, allow=()) -> ImpactResult:
    """`fe.simulate` on the hexahedral geometry, with a `FutureWarning`."""
    _moved("simulate_oblique", "simulate")
    return simulate_batch(ball, [condition], geometry=Hexahedral(options), target=target,
                          progress=progress, allow=allow)[0]


def simulate_oblique_batch(ball, conditions, options: Options3D = Options3D(), target=None,
                           progress=None, *, allow=()) -> list[ImpactResult]:
    """`fe.simulate_batch` of one ball on the hexahedral geometry, with a `FutureWarning`."""
    _moved("simulate_oblique_batch", "simulate_batch")
    return simulate_batch(ball, list(conditions), geometry=Hexahedral(options), target=target,
                          progress=progress, allow=allow)


def estimate_oblique(ball, conditions, options: Options3D = Options3D(), target=None, *,
                     allow=()):
    """`fe.estimate` on the hexahedral geometry, with a `FutureWarning`."""
    _moved("estimate_oblique", "estimate")
    return estimate(ball, list(conditions), geometry=Hexahedral(options), target=target,
                    allow=allow)
