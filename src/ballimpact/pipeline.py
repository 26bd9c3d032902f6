"""From a loaded record to its features: baseline removal, optional resampling, filtering."""

from __future__ import annotations

from dataclasses import dataclass

from .features import DEFAULT_IMPULSE_TOLERANCE, ImpactFeatures, extract_features
from .filters import apply_filter
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
) -> ProcessedImpact:
    """Remove the load-cell offset, resample to `resample_hz` (Hz) if given, apply the filter
    `filter` (see `apply_filter`) and extract the features."""
    raw = remove_baseline(record)
    if resample_hz is not None:
        raw = resample(raw, resample_hz)
    filtered = apply_filter(raw, filter, window_s=window_s)
    features = extract_features(filtered, impulse_tolerance=impulse_tolerance)
    return ProcessedImpact(raw, filtered, features)
