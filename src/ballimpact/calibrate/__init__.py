"""Calibration of layered FE balls against impact tests (thesis chapter 5): free parameters by
path in the ball specification, multi-objective search (pymoo), decision making on the Pareto
front, Levenberg-Marquardt refinement with gradients through the explicit solver (JAX), and stages that
calibrate component by component."""

from .calibration import METHODS, Stage, calibrate, parse_stage
from .decision import decide
from .gradient import SmoothMisfit, refine, smooth_misfits, standard_runs
from .problem import OBJECTIVES, CalibrationProblem, CalibrationTest, free_parameter
from .search import search

__all__ = ["METHODS", "OBJECTIVES", "CalibrationProblem", "CalibrationTest", "SmoothMisfit",
           "Stage", "calibrate", "decide", "free_parameter", "parse_stage", "refine", "search",
           "smooth_misfits", "standard_runs"]
