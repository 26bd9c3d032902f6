"""From a loaded record to its features: baseline removal, optional resampling, filtering."""

from __future__ import annotations

import math
import warnings
from collections.abc import Collection
from dataclasses import dataclass

from ..errors import InputError, InputWarning
from .features import DEFAULT_IMPULSE_TOLERANCE, ImpactFeatures, extract_features
from .filters import apply_filter
from ..checks import check_allow
from .plausibility import check_clipping, check_polarity, noisy_window_note, select_pulse
from ..checks import check_fraction, check_positive

#: Damping ratio of a load cell whose resonance is given without one (`--load-cell-hz`).
DEFAULT_DAMPING_RATIO = 0.03
from .record import ImpactRecord, remove_baseline, resample


@dataclass(frozen=True)
class ProcessedImpact:
    """`raw`: the record with its baseline removed; `filtered`: after the filter;
    `features`: extracted from `filtered`."""

    raw: ImpactRecord
    filtered: ImpactRecord
    features: ImpactFeatures


#: Load-cell resonances below this (Hz) are taken for kHz typed as Hz: no ball rig's cell rings
#: that slowly (8-25 kHz for the rigs of ball tests; docs/features.md "Load-cell ringing").
MIN_RESONANCE_HZ = 500.0


def check_resonance(resonance_hz: float, damping_ratio: float, record: ImpactRecord) -> None:
    """A load-cell resonance given by the user (`--load-cell-hz`, `--load-cell-damping`):
    `InputError` naming the flag for a resonance in kHz, one above the record's Nyquist
    frequency, or a damping ratio outside (0, 1) (a percentage named as such)."""
    from .record import sample_rate_hz

    check_positive("resonance_hz (--load-cell-hz)", resonance_hz)
    if resonance_hz < MIN_RESONANCE_HZ:
        raise InputError(f"resonance_hz (--load-cell-hz) = {resonance_hz:g}: allowed range "
                         f"[{MIN_RESONANCE_HZ:g}, Nyquist) Hz; {resonance_hz:g} looks like kHz "
                         f"given as Hz (use {resonance_hz * 1e3:g})")
    nyquist = 0.5 * sample_rate_hz(record)
    if resonance_hz >= nyquist:
        raise InputError(f"resonance_hz (--load-cell-hz) = {resonance_hz:g}: at or above the "
                         f"record's Nyquist frequency {nyquist:g} Hz, where nothing of it can be "
                         "seen or divided out")
    check_fraction("damping_ratio (--load-cell-damping)", damping_ratio, high_open=True)


def without_ringing(record: ImpactRecord, resonance_hz: float | None = None,
                    damping_ratio: float = DEFAULT_DAMPING_RATIO) -> ImpactRecord:
    """`record` with the load cell's resonance divided out (`ringing.compensate`): the one
    given (`resonance_hz`, Hz, and `damping_ratio`), or the one found ringing on after the
    contact (`ringing.find_resonance`); as it is when none is given or found, or when it is not
    uniformly sampled."""
    from .record import contact_window, sample_rate_hz
    from .ringing import Resonance, compensate, find_resonance

    try:
        sample_rate_hz(record)
        resonance = (Resonance(resonance_hz, damping_ratio, math.nan) if resonance_hz
                     else find_resonance(record, contact_window(record)))
    except InputError:
        if resonance_hz:
            raise
        return record
    return record if resonance is None else compensate(record, resonance)


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
    ringing: bool = True,
    resonance_hz: float | None = None,
    damping_ratio: float = DEFAULT_DAMPING_RATIO,
) -> ProcessedImpact:
    """Check a measured record, remove the load-cell offset, resample to `resample_hz` (Hz) if
    given, divide out the load cell's resonance (`ringing`: the one given, `resonance_hz` Hz and
    `damping_ratio`, or the one the record shows; `without_ringing`), apply the filter `filter`
    (see `apply_filter`) and extract the features: by default (`method="fit"`) from the pulse
    with fitted edges, with the standard `uncertainty` of every value (`extract_features`;
    docs/features.md).

    The plausibility checks (`plausibility`): the force must be positive in compression (not an
    inverted pulse), the record must not be clipped, must hold one pulse (or `pulse`, 1 = first,
    picks one of several), and its impulse must fit its speeds; `allow` names the checks to turn
    into warnings.

    With `method="samples"`, a noisy record gets a note naming the filter to use, in
    `features.warnings` and, if
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
        if resonance_hz is not None:
            check_resonance(resonance_hz, damping_ratio, raw)
        compensated = without_ringing(raw, resonance_hz, damping_ratio) if ringing else raw
        filtered = apply_filter(compensated, filter, window_s=window_s)
        features = extract_features(filtered, impulse_tolerance=impulse_tolerance, allow=allow,
                                    method=method, uncertainty=uncertainty, checked=True)
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
