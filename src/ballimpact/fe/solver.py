"""The axisymmetric engine's former entry points, kept for one release: they call `fe.engine`
(the one driver, the geometry a plug-in) and warn (`FutureWarning`). Use `fe.simulate`,
`fe.simulate_batch` and `fe.estimate` with `geometry=fe.Axisymmetric(options)`."""

from __future__ import annotations

import warnings

from .engine import estimate, simulate as _simulate, simulate_batch as _simulate_batch
from .options import SolverOptions
from .result import FailedRun, ImpactResult

__all__ = ["FEResult", "FailedRun", "SolverOptions", "estimate_run", "simulate", "simulate_batch"]

#: the one result type of `fe.engine` (this name: one release)
FEResult = ImpactResult


def _moved(old: str, new: str) -> None:
    warnings.warn(f"fe.solver.{old} is fe.{new} (this alias goes in the next release)",
                  FutureWarning, stacklevel=3)


def estimate_run(ball, impact_speed_m_s, options: SolverOptions = SolverOptions(), *, allow=()):
    """`fe.estimate(ball, speeds, options, allow=allow)`, with a `FutureWarning`."""
    _moved("estimate_run", "estimate")
    return estimate(ball, impact_speed_m_s, options, allow=allow)


def simulate_batch(balls, impact_speeds_m_s, options: SolverOptions = SolverOptions(),
                   progress=None, group_size: int | None = None, on_failure: str = "raise", *,
                   allow=()):
    """`fe.simulate_batch(list(balls), speeds, options, ...)`, with a `FutureWarning`."""
    _moved("simulate_batch", "simulate_batch")
    return _simulate_batch(list(balls), impact_speeds_m_s, options, progress, group_size,
                           on_failure, allow=allow)


def simulate(ball, impact_speed_m_s, options: SolverOptions = SolverOptions(), progress=None, *,
             allow=()) -> ImpactResult:
    """`fe.simulate(ball, speed, options, progress, allow=allow)`, with a `FutureWarning`."""
    _moved("simulate", "simulate")
    return _simulate(ball, impact_speed_m_s, options, progress, allow=allow)
