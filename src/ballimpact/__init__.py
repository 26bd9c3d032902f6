"""ballimpact: sports-ball impact modelling.

Impact tests become `ImpactRecord`s (`load_record`), are smoothed (`apply_filter`) and reduced to
the thesis' 19 characteristic values and the load-cell identities (`extract_features`, or all at
once with `process`). All quantities are SI.
"""

from .errors import InputError as InputError, InputWarning as InputWarning
from .records.features import (
    FEATURE_NAMES as FEATURE_NAMES,
    ImpactFeatures as ImpactFeatures,
    extract_features as extract_features,
)
from .records.filters import apply_filter as apply_filter
from .records.loaders import load_record as load_record
from .records.pipeline import ProcessedImpact as ProcessedImpact, process as process
from .records.record import (
    ContactWindow as ContactWindow,
    ImpactRecord as ImpactRecord,
    contact_window as contact_window,
    remove_baseline as remove_baseline,
    resample as resample,
)

__version__ = "0.1.0"
