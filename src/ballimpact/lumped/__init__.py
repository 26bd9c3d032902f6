"""Lumped ball models (thesis chapters 2 and 4), their batched simulation and their identification.

Models (`MODELS`, see `describe_models`): `single_element`, `three_element`, `hunt_crossley`,
`kelvin_voigt`, `hertz`, `lieberman_johnson`, `simon`, and two reproductions of the thesis'
appendix code, `single_element_thesis` and `three_element_thesis`. `simulate` returns an
`ImpactRecord`; `fit` identifies a model from a measured record by a genetic algorithm or
differential evolution with a local polish; `fit_speed_table` and `SpeedTable` make parameters
functions of the impact speed (thesis tables 7-1, 7-2; `thesis_tables`); `fit_records` does
either for test records, with each fit's model check (`ballimpact fit`).
"""

from .hunt_crossley import hunt_crossley_cor as hunt_crossley_cor
from .hunt_crossley import hunt_crossley_lambda as hunt_crossley_lambda
from .kelvin_voigt import kelvin_voigt_from_test as kelvin_voigt_from_test
from .registry import MODELS as MODELS, describe_models as describe_models, get_model as get_model
from .simulate import simulate as simulate
from .fit import FitResult as FitResult, fit as fit
from .speed_table import SpeedTable as SpeedTable, fit_speed_table as fit_speed_table
from .speed_table import thesis_tables as thesis_tables
from .fit_records import RecordFits as RecordFits, fit_records as fit_records
