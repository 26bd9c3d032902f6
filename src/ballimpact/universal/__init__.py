"""The universal FE ball (thesis chapter 6): a design of experiments over the homogeneous ball's
parameters run through the FE engine (`space`, `study`, `dataset`), deep-ensemble surrogates
trained on it (`networks`, `model`, `training`), their held-out figures (`evaluate`), and the
identification of a ball from a measured impact (`identify`)."""

from .identify import Identification, identify
from .model import BUILTIN, UniversalModel, load_model
from .study import make_config, run_study

__all__ = ["BUILTIN", "Identification", "UniversalModel", "identify", "load_model",
           "make_config", "run_study"]
