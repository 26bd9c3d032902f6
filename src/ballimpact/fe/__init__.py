"""Explicit finite-element ball models (thesis chapters 5 and 6): layered hyper-viscoelastic
balls and one explicit engine (`engine`) whose geometry is a plug-in: axisymmetric
(`Axisymmetric`, normal impacts on a rigid plane) or hexahedral 3D (`Hexahedral`, oblique and
spinning impacts with friction, on a rigid plane or a slab)."""

from .ball import (
           PRESETS,
           BallModel,
           Layer,
           describe_presets,
           load_ball,
           universal_parameters,
)
from .compression import CompressionResult, compress
from .engine import Axisymmetric, Hexahedral, estimate, simulate, simulate_batch
from .options import ExplicitOptions, ImpactCondition, Options3D, SolverOptions
from .progress import RunProgress
from .result import FailedRun, ImpactResult
from .solver import FEResult, estimate_run  # one release: FutureWarning

__all__ = ["PRESETS", "Axisymmetric", "BallModel", "CompressionResult", "ExplicitOptions",
           "FailedRun", "FEResult", "Hexahedral", "ImpactCondition", "ImpactResult", "Layer",
           "Options3D", "RunProgress", "SolverOptions", "compress", "describe_presets",
           "estimate", "estimate_run", "load_ball", "simulate", "simulate_batch",
           "universal_parameters"]
