"""Calibration of layered FE balls against impact tests and compression tests (force-deflection
curves between two platens; thesis chapter 5 and 5.2): free parameters by
path in the ball specification, multi-objective search (pymoo), decision making on the Pareto
front, Levenberg-Marquardt refinement with gradients through the explicit solver (JAX), and stages that
calibrate component by component."""

from .calibration import METHODS, Stage, calibrate, parse_stage
from .compression import CompressionTest, read_compression_csv, refine_compression
from .decision import decide
from .gradient import SmoothMisfit, refine, smooth_misfits, standard_runs
from .problem import OBJECTIVES, CalibrationProblem, CalibrationTest, free_parameter
from .search import search

__all__ = ["METHODS", "OBJECTIVES", "CalibrationProblem", "CalibrationTest", "CompressionTest",
           "SmoothMisfit", "read_compression_csv", "refine_compression",
           "Stage", "calibrate", "decide", "free_parameter", "parse_stage", "refine", "search",
           "smooth_misfits", "standard_runs"]
