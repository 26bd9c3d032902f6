"""Explicit finite-element ball models (thesis chapters 5 and 6): layered hyper-viscoelastic
balls, an axisymmetric mesh and solver for normal impacts on a rigid plane."""

from .ball import (
           PRESETS,
           BallModel,
           Layer,
           describe_presets,
           load_ball,
           universal_parameters,
)
from .compression import CompressionResult, compress
from .options import ExplicitOptions, ImpactCondition
from .progress import RunProgress
from .solver import FailedRun, FEResult, SolverOptions, estimate_run, simulate, simulate_batch

__all__ = ["PRESETS", "BallModel", "CompressionResult", "ExplicitOptions", "FailedRun", "FEResult",
           "ImpactCondition", "Layer", "RunProgress", "SolverOptions", "compress",
           "describe_presets", "estimate_run", "load_ball", "simulate", "simulate_batch",
           "universal_parameters"]
