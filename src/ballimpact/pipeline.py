"""From a loaded record to its features: baseline removal, optional resampling, filtering."""

from __future__ import annotations

import warnings
from collections.abc import Collection
from dataclasses import dataclass

from .errors import InputWarning
from .features import DEFAULT_IMPULSE_TOLERANCE, ImpactFeatures, extract_features
from .filters import apply_filter
from .plausibility import check_allow, check_clipping, noisy_window_note, select_pulse
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
) -> ProcessedImpact:
    """Check a measured record, remove the load-cell offset, resample to `resample_hz` (Hz) if
    given, apply the filter `filter` (see `apply_filter`) and extract the features.

    The plausibility checks (`plausibility`): the record must not be clipped, must hold one pulse
    (or `pulse`, 1 = first, picks one of several), and its impulse must fit its speeds; `allow`
    names the checks to turn into warnings. A noisy record gets a warning naming the filter to use.
    """
    allow = check_allow(allow)
    check_clipping(record, allow)
    raw = remove_baseline(select_pulse(record, pulse))
    if resample_hz is not None:
        raw = resample(raw, resample_hz)
    filtered = apply_filter(raw, filter, window_s=window_s)
    features = extract_features(filtered, impulse_tolerance=impulse_tolerance, allow=allow)
    note = noisy_window_note(features.window, features.values["P6"],
                             filtered.metadata.get("filter", "none"))
    if note is not None:
        warnings.warn(note, InputWarning, stacklevel=2)
        features.warnings.append(note)
    return ProcessedImpact(raw, filtered, features)
