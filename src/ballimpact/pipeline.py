"""From a loaded record to its features: baseline removal, optional resampling, filtering."""

from __future__ import annotations

import warnings
from collections.abc import Collection
from dataclasses import dataclass

from .errors import InputError, InputWarning
from .features import DEFAULT_IMPULSE_TOLERANCE, ImpactFeatures, extract_features
from .filters import apply_filter
from .plausibility import (
    check_allow,
    check_clipping,
    check_polarity,
    noisy_window_note,
    select_pulse,
)
from .checks import check_positive
from .records import ImpactRecord, remove_baseline, resample


@dataclass(frozen=True)
class ProcessedImpact:
    """`raw`: the record with its baseline removed; `filtered`: after the filter;
    `features`: extracted from `filtered`."""

    raw: ImpactRecord
    filtered: ImpactRecord
    features: ImpactFeatures


def process(
    record: ImpactRecord,
    *,
    filter: str = "none",
    window_s: float | None = None,
    resample_hz: float | None = None,
    impulse_tolerance: float = DEFAULT_IMPULSE_TOLERANCE,
    pulse: int | None = None,
    allow: Collection[str] = (),
    warn_noisy: bool | None = None,
    method: str = "fit",
    uncertainty: bool = True,
) -> ProcessedImpact:
    """Check a measured record, remove the load-cell offset, resample to `resample_hz` (Hz) if
    given, apply the filter `filter` (see `apply_filter`) and extract the features.

    The plausibility checks (`plausibility`): the force must be positive in compression (not an
    inverted pulse), the record must not be clipped, must hold one pulse (or `pulse`, 1 = first,
    picks one of several), and its impulse must fit its speeds; `allow` names the checks to turn
    into warnings.

    A noisy record gets a note naming the filter to use, in `features.warnings` and, if
    `warn_noisy`, as an `InputWarning` naming the record's file. `warn_noisy=None` (default)
    warns about the user's records but not about the package's built-in data (its loader marks
    them `builtin`, and the sample is noisy on purpose); pass False for records made to be noisy
    (training on noisy FE pulses, synthetic tests).

    Errors from a record loaded from a file start with the file's name.
    """
    source = record.metadata.get("file")
    if warn_noisy is None:
        warn_noisy = not record.metadata.get("builtin")
    try:
        allow = check_allow(allow)
        if window_s is not None:
            check_positive("window_s (--filter-window-s)", window_s)
        if resample_hz is not None:
            check_positive("resample_hz (--resample-hz)", resample_hz)
        check_polarity(record)
        check_clipping(record, allow)
        raw = remove_baseline(select_pulse(record, pulse))
        if resample_hz is not None:
            raw = resample(raw, resample_hz)
        filtered = apply_filter(raw, filter, window_s=window_s)
        features = extract_features(filtered, impulse_tolerance=impulse_tolerance, allow=allow,
                                    method=method, uncertainty=uncertainty)
    except InputError as error:
        if source is None or str(error).startswith(source):
            raise
        raise InputError(f"{source}: {error}") from None
    # the fitted pulse is not cut by the noise threshold: the note is the sample method's
    note = None if method == "fit" else noisy_window_note(
        features.window, features.values["P6"], filtered.metadata.get("filter", "none"), source)
    if note is not None:
        if warn_noisy:
            warnings.warn(note, InputWarning, stacklevel=2)
        features.warnings.append(note)
    return ProcessedImpact(raw, filtered, features)
