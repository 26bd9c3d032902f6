"""Smoothing of force pulses: SAE J211 / ISO 6487 channel frequency classes, Savitzky-Golay,
LOWESS/LOESS, and the thesis' degree-5 polynomial fit.

Every filter is a pure function of (samples, settings) returning new samples; `apply_filter`
applies one by name to an `ImpactRecord`. All but the polynomial need uniform sampling.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from numpy.polynomial import Polynomial

from ..errors import InputError, InputWarning
from ..checks import check_positive
from .record import ImpactRecord, baseline_noise_rms, contact_window, rms, sample_rate_hz

#: SAE J211-1 design frequency of the 2-pole Butterworth stage, as a multiple of the CFC number.
#: Run forwards and backwards, the 4-pole phaseless filter is -3 dB at about 1.65 x CFC (Hz).
CFC_DESIGN_FACTOR = 2.0775
STANDARD_CFC = (60, 180, 600, 1000)


def cfc_filter(force: np.ndarray, rate_hz: float, cfc: float) -> np.ndarray:
    """SAE J211-1 / ISO 6487 channel frequency class filter: a 2-pole Butterworth low-pass with
    design frequency 2.0775 x CFC (bilinear transform with pre-warping, as J211 appendix C), run
    forwards and backwards (phaseless, 4-pole). Standard classes are 60, 180, 600 and 1000; any
    positive class below the Nyquist limit is accepted.

    The classes were made for crash tests (pulses of 10-100 ms). A ball impact lasts about 1 ms, and
    CFC 1000 (-3 dB at 1.65 kHz) then lengthens the contact time by some 20%: choose the class so
    that 1.65 x CFC x contact time >= 12 (`apply_filter` warns otherwise), e.g. cfc10000 for 1 ms.
    """
    cfc = check_positive("cfc", cfc)
    design_hz = CFC_DESIGN_FACTOR * cfc
    if design_hz >= 0.5 * rate_hz:
        raise InputError(
            f"filter: CFC {cfc:g} needs a sampling rate above {2 * design_hz:.0f} Hz, "
            f"the record has {rate_hz:.0f} Hz"
        )
    from scipy.signal import butter, sosfiltfilt  # here: scipy.signal takes 0.3 s to import

    sos = butter(2, design_hz, btype="low", fs=rate_hz, output="sos")
    pad = 3 * (2 * len(sos) + 1)  # sosfiltfilt's default edge padding
    if force.size <= pad:
        raise InputError(f"filter: a CFC filter needs more than {pad} samples, got {force.size}")
    return sosfiltfilt(sos, force)


def savitzky_golay(force: np.ndarray, rate_hz: float, window_s: float, order: int = 3):
    """Savitzky-Golay smoothing: least-squares polynomial of `order` over a moving window of
    `window_s` seconds (rounded to an odd number of samples)."""
    from scipy.signal import savgol_filter

    points = _window_points(window_s, rate_hz, minimum=order + 2, available=force.size)
    return savgol_filter(force, points, order, mode="interp")


def lowess(force: np.ndarray, rate_hz: float, window_s: float, degree: int = 2):
    """Local polynomial regression with tricube weights (Cleveland's LOWESS for `degree` 1,
    LOESS, as MATLAB's `smooth(..., 'loess')` used by the thesis, for `degree` 2).

    Each sample is fitted from the `window_s` seconds of samples around it (shifted inwards at the
    ends, so every window holds the same number of samples), weighted by (1 - (d/d_max)^3)^3 with
    d_max just beyond the farthest sample of the window. Not the robust (re-weighted) variant.
    """
    if degree not in (1, 2):
        raise InputError(f"degree: must be 1 or 2, got {degree}")
    count = force.size
    points = _window_points(window_s, rate_hz, minimum=degree + 3, available=count)
    starts = np.clip(np.arange(count) - points // 2, 0, count - points)
    index = np.arange(count)
    windows = sliding_window_view(index, points)
    smoothed = np.empty(count)
    block_rows = max(1, 1_000_000 // points)  # bound the (rows x window) work arrays
    for block in range(0, count, block_rows):
        rows = slice(block, min(block + block_rows, count))
        neighbours = windows[starts[rows]]
        offset = (neighbours - index[rows, None]).astype(float)
        reach = np.max(np.abs(offset), axis=1, keepdims=True) * (1 + 1e-9)
        offset /= reach  # scaled to (-1, 1): well-conditioned normal equations for any window
        weight = (1 - np.abs(offset) ** 3) ** 3
        powers = offset[..., None] ** np.arange(degree + 1)  # (rows, window, degree+1)
        weighted = powers * weight[..., None]
        normal = np.einsum("rwi,rwj->rij", weighted, powers)
        rhs = np.einsum("rwi,rw->ri", weighted, force[neighbours])
        smoothed[rows] = np.linalg.solve(normal, rhs[..., None])[:, 0, 0]
    return smoothed


def polynomial_fit(time: np.ndarray, force: np.ndarray, first: int, last: int, degree: int = 5):
    """The thesis' least-squares polynomial of the pulse (eq. 3-4, degree 5) over samples
    `first..last`; zero outside them and wherever the polynomial goes negative."""
    inside = slice(first, last + 1)
    if last - first + 1 <= degree:
        raise InputError(f"filter: a degree-{degree} fit needs more than {degree} pulse samples")
    fit = Polynomial.fit(time[inside], force[inside], degree)
    smoothed = np.zeros_like(force)
    smoothed[inside] = np.maximum(fit(time[inside]), 0.0)
    return smoothed


def _window_points(window_s: float, rate_hz: float, minimum: int, available: int) -> int:
    window_s = check_positive("window_s", window_s)
    points = int(round(window_s * rate_hz))
    points += 1 - points % 2  # odd, centred on the sample
    if points < minimum:
        raise InputError(
            f"window_s: {window_s:g} s is {points} samples at {rate_hz:.0f} Hz; "
            f"need at least {minimum} (a longer window or a higher sampling rate)"
        )
    if points > available:
        raise InputError(f"window_s: {points} samples is longer than the record ({available})")
    return points


# --------------------------------------------------------------------------- by name

#: Default window of the moving filters, as a fraction of the contact time of the raw pulse.
DEFAULT_WINDOW_FRACTION = 0.1

FILTER_NAMES = ("none", "cfc60", "cfc180", "cfc600", "cfc1000", "savgol", "lowess", "loess", "poly5")
#: The filters that take a window (`window_s`).
WINDOWED_FILTERS = ("savgol", "lowess", "loess")
#: `cfc<N>`: an SAE J211 filter of any class N
_CFC = re.compile(r"cfc(\d+(?:\.\d+)?)")


def check_filter_name(name: str, flag: str = "filter") -> str:
    """The filter's key (`name` stripped, lower case); `InputError` naming `flag` for a name
    `apply_filter` does not know."""
    key = name.strip().lower()
    if key not in FILTER_NAMES and not _CFC.fullmatch(key):
        raise InputError(
            f"{flag}: unknown name {name!r}; allowed: {', '.join(FILTER_NAMES)} or cfc<N>"
        )
    return key


def apply_filter(
    record: ImpactRecord, name: str, *, window_s: float | None = None
) -> ImpactRecord:
    """`record` with its force (and tangential force) smoothed by the filter called `name`.

    Names: `none`; `cfc<N>` (SAE J211 class N, e.g. `cfc1000`); `savgol` (cubic); `lowess`
    (degree 1) and `loess` (degree 2); `poly5` (the thesis' polynomial fit of the pulse).
    `window_s` sets the window of savgol/lowess/loess, by default 10% of the contact time of the
    unfiltered pulse and at least 5 samples. The filter's name and settings go into the metadata.
    """
    key = check_filter_name(name)
    cfc = _CFC.fullmatch(key)
    if window_s is not None and key not in WINDOWED_FILTERS:
        # a window the filter would ignore: say so rather than run without it
        raise InputError(f"window_s (--filter-window-s): filter {name!r} has no window; the "
                         f"window applies to {', '.join(WINDOWED_FILTERS)}")
    if key == "none":
        return record.with_metadata(filter="none")
    settings: dict[str, float | str] = {"filter": key}
    if key == "poly5":
        window = contact_window(record)
        smooth: Callable[[np.ndarray], np.ndarray] = lambda f: polynomial_fit(
            record.time_s, f, window.first, window.last
        )
        return _smoothed(record, smooth, settings, tangential=False)
    rate = sample_rate_hz(record)
    if cfc:
        settings["cfc"] = float(cfc.group(1))
        _warn_if_cfc_low(settings["cfc"], contact_window(record).duration_s)
        smooth = lambda f: cfc_filter(f, rate, settings["cfc"])
        return _smoothed(record, smooth, settings)
    if window_s is None:  # 10% of the contact time, but never fewer than 5 samples
        window_s = max(DEFAULT_WINDOW_FRACTION * contact_window(record).duration_s, 5 / rate)
    settings["window_s"] = window_s
    if key == "savgol":
        smooth = lambda f: savitzky_golay(f, rate, window_s)
    else:
        degree = 1 if key == "lowess" else 2
        smooth = lambda f: lowess(f, rate, window_s, degree)
    return _smoothed(record, smooth, settings)


#: Fewest cycles of the CFC -3 dB frequency per contact time for which the smoothing changes
#: contact time and peak force by less than about 3% (checked on spring-dashpot pulses).
MIN_CFC_CYCLES_PER_CONTACT = 12.0


def _warn_if_cfc_low(cfc: float, contact_time_s: float) -> None:
    cycles = 1.65 * cfc * contact_time_s
    if cycles < MIN_CFC_CYCLES_PER_CONTACT:
        enough = MIN_CFC_CYCLES_PER_CONTACT / (1.65 * contact_time_s)
        warnings.warn(
            f"filter: CFC {cfc:g} (-3 dB at {1.65 * cfc:.0f} Hz) is low for a "
            f"{contact_time_s * 1e3:.3g} ms pulse; its smoothing lengthens the contact time and "
            f"lowers the peak; a class of at least {enough:.0f} suits it (e.g. cfc{enough:.0f})",
            InputWarning,
            stacklevel=3,
        )


#: A filter whose change of the force is below this fraction of the record's noise (RMS of the
#: pre-impact samples) smoothed nothing: `apply_filter` warns.
NO_EFFECT_FRACTION = 0.1


def _smoothed(record, smooth, settings, *, tangential: bool = True) -> ImpactRecord:
    shear = record.tangential_force_n
    force = smooth(record.force_n)
    change = rms(force - record.force_n)
    noise = baseline_noise_rms(record.time_s, record.force_n)
    settings = {**settings, "filter_change_rms_n": change}
    if noise > 0 and change < NO_EFFECT_FRACTION * noise:
        where = f"{record.metadata['file']}: " if "file" in record.metadata else ""
        window = (f" (window {settings['window_s']:.3g} s)" if "window_s" in settings else "")
        warnings.warn(
            f"{where}filter {settings['filter']}{window} changed the force by {change:.3g} N RMS, "
            f"less than {NO_EFFECT_FRACTION:g} of the record's noise ({noise:.3g} N RMS): it "
            "smoothed nothing at this sampling rate (a longer --filter-window-s or a lower CFC "
            "class; or leave it out: the default processing fits the pulse, docs/features.md)",
            InputWarning, stacklevel=3)
    return record.replace(
        force_n=force,
        tangential_force_n=smooth(shear) if shear is not None and tangential else shear,
        metadata={**record.metadata, **settings},
    )
