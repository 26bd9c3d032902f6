"""Plausibility checks: inputs that are well-formed but cannot be a real impact.

One layer that the command line and the Python API both pass through (the loaders, `process`,
`extract_features` and the FE solvers call it), so a check is written once. Each check has a name.
Where an implausible input can still be worth processing, the name is also its override: with
`allow={"clipping"}` (command line `--allow clipping`) the error becomes an `InputWarning` whose
message starts with the name, so it keeps its name in the JSON `warnings` list. docs/features.md
lists the checks, their thresholds and their overrides.
"""

from __future__ import annotations

from collections.abc import Collection

import numpy as np

from ..checks import CHECKS, check_allow, flag  # noqa: F401 - the names records use
from ..errors import InputError

# --------------------------------------------------------------------------- clipping


#: Fewest consecutive samples at the recorder's full scale that count as clipping.
MIN_CLIPPED_SAMPLES = 2
#: Without known full-scale codes (CSV): fewest equal samples at the extreme that make a flat top,
#: and how many resolution steps the signal must jump to reach it (a rounded peak that the
#: resolution flattens is entered by one step).
MIN_FLAT_TOP_SAMPLES = 3
FLAT_TOP_JUMP_STEPS = 4
#: A flat top nearer the baseline than this fraction of the largest excursion is the baseline.
FLAT_TOP_MIN_EXCURSION = 0.05
#: Each end of the record that `baseline_level` reads, as a fraction of the samples (at least 3).
BASELINE_END_FRACTION = 0.05
#: A negative excursion counts as an inverted pulse when it is larger than the positive one and
#: larger than this many times the noise (the noise alone reaches about 5 times its RMS).
POLARITY_NOISE_FACTOR = 8.0


def baseline_level(force_n) -> float:
    """The force level before and after the impact: the median of the first and the last
    `BASELINE_END_FRACTION` of the samples (a record starts and ends off contact; the median
    ignores a few noisy or ringing samples there)."""
    force = np.asarray(force_n, dtype=float)
    n = max(3, int(BASELINE_END_FRACTION * force.size))
    return float(np.median(np.concatenate([force[:n], force[-n:]])))


def _scaled(force_n) -> tuple[np.ndarray, float]:
    """The force divided by its largest magnitude (no overflow for absurd forces), and that
    magnitude (1 for an all-zero record)."""
    force = np.asarray(force_n, dtype=float)
    scale = float(np.max(np.abs(force))) or 1.0
    return force / scale, scale


def _step_noise(signal: np.ndarray) -> float:
    """The noise RMS from the median absolute step between samples: robust to the pulses and to
    an offset."""
    return 1.4826 * float(np.median(np.abs(np.diff(signal)))) / np.sqrt(2)


def check_polarity(record) -> None:
    """`InputError` when the pulse is negative: the largest excursion from the baseline
    (`baseline_level`) is below it, and clearly above the noise. Checked before clipping, whose
    flat-top test would otherwise see the baseline as the top."""
    signal, scale = _scaled(record.force_n)
    base = baseline_level(signal)
    up, down = float(np.max(signal)) - base, base - float(np.min(signal))
    if down > up and down > POLARITY_NOISE_FACTOR * _step_noise(signal):
        at = int(np.argmin(signal))
        raise InputError(
            f"force_n: the pulse is negative ({-down * scale:.4g} N from the baseline at "
            f"{record.time_s[at] * 1e3:.4g} ms; the largest positive excursion is "
            f"{up * scale + 0.0:.4g} N): the load cell's polarity looks inverted (force must be "
            "positive in compression); negate the force column, or for a WAV file give the "
            "sensitivity with a minus sign (e.g. --sensitivity-v-per-n -9.442e-5)")


def clipped_spans(time_s, force_n, full_scale_n=None) -> list[tuple[float, float, float, int]]:
    """Spans of clipped samples as (start s, end s, level N, samples).

    With `full_scale_n` = (low, high), the forces of the recorder's extreme codes (WAV), a span is
    `MIN_CLIPPED_SAMPLES` or more consecutive samples at either. Without it (CSV), a span is a flat
    top: `MIN_FLAT_TOP_SAMPLES` or more consecutive samples equal to the record's maximum (or to
    its minimum, if that is below -5% of the maximum) that the signal reaches by a jump of more
    than `FLAT_TOP_JUMP_STEPS` times the record's resolution (its smallest step between values).
    A flat top must also stand off the baseline (`baseline_level`) by more than
    `FLAT_TOP_MIN_EXCURSION` of the record's largest excursion: a flat baseline is not clipping
    (with an inverted pulse the baseline is the record's maximum).
    """
    force = np.asarray(force_n, dtype=float)
    time = np.asarray(time_s, dtype=float)
    spans = []
    if full_scale_n is not None:
        low, high = sorted(full_scale_n)  # a negative sensitivity swaps the rails
        tolerance = 1e-9 * max(abs(low), abs(high))
        for at_rail in (force >= high - tolerance, force <= low + tolerance):
            spans += [(time[i], time[j], float(force[i]), j - i + 1)
                      for i, j in _runs(at_rail) if j - i + 1 >= MIN_CLIPPED_SAMPLES]
        return spans
    levels = np.unique(force)
    resolution = float(np.min(np.diff(levels))) if levels.size > 1 else 0.0
    top, bottom = float(levels[-1]), float(levels[0])
    extremes = [top] + ([bottom] if bottom < -0.05 * abs(top) else [])
    base = baseline_level(force)
    excursion = max(top - base, base - bottom)
    for level in extremes:
        if abs(level - base) <= FLAT_TOP_MIN_EXCURSION * excursion:
            continue  # the baseline itself
        for i, j in _runs(force == level):
            if j - i + 1 < MIN_FLAT_TOP_SAMPLES:
                continue
            neighbours = force[[k for k in (i - 1, j + 1) if 0 <= k < force.size]]
            jump = float(np.max(np.abs(neighbours - level))) if neighbours.size else 0.0
            if jump > FLAT_TOP_JUMP_STEPS * resolution:
                spans.append((time[i], time[j], level, j - i + 1))
    return spans


def check_clipping(record, allow: Collection[str] = ()) -> None:
    """The `clipping` check on a loaded record (see `clipped_spans`)."""
    spans = clipped_spans(record.time_s, record.force_n, record.metadata.get("full_scale_n"))
    if not spans:
        return
    count = sum(span[3] for span in spans)
    where = "; ".join(f"{n} samples at {level:.6g} N from {start * 1e3:.4g} to {end * 1e3:.4g} ms"
                      for start, end, level, n in spans[:3])
    more = f" and {len(spans) - 3} more spans" if len(spans) > 3 else ""
    flag("clipping", f"force_n: the signal is clipped ({where}{more}; {count} samples in all): "
         "the peak force and the impulse are cut off; record again with more headroom (lower "
         "amplifier gain or a larger full scale)", allow)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index of each run of True in `mask`."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1).tolist(), (np.flatnonzero(edges == -1) - 1).tolist()))


# --------------------------------------------------------------------------- several pulses


#: A pulse is a run of samples above this fraction of the largest force (and above
#: `PULSE_NOISE_FACTOR` times the noise); two runs are separate pulses when the force between them
#: falls below `PULSE_GAP_FRACTION` of the largest force.
PULSE_LEVEL_FRACTION = 0.2
PULSE_GAP_FRACTION = 0.05
PULSE_NOISE_FACTOR = 5.0


def find_pulses(time_s, force_n) -> list[tuple[int, int, int]]:
    """The pulses of a force record as (first, last, peak) sample indices, in time order.

    The baseline is the 10th percentile of the force (a record lies mostly before and after the
    impact) and the noise comes from the median absolute step between samples: both are robust
    to the pulses, and to an offset left in the record.
    """
    signal, _ = _scaled(force_n)
    signal = signal - np.percentile(signal, 10)
    noise = _step_noise(signal)
    peak = float(np.max(signal))
    level = max(PULSE_LEVEL_FRACTION * peak, PULSE_NOISE_FACTOR * noise)
    runs = [run for run in _runs(signal > level) if run[1] > run[0]]
    pulses: list[list[int]] = []
    for first, last in runs:
        if pulses and np.min(signal[pulses[-1][1]:first + 1]) > PULSE_GAP_FRACTION * peak:
            pulses[-1][1] = last  # the force did not come back down: the same pulse
        else:
            pulses.append([first, last])
    return [(first, last, first + int(np.argmax(signal[first:last + 1])))
            for first, last in pulses]


def select_pulse(record, pulse: int | None = None):
    """The record cut to its one pulse, or to pulse number `pulse` (1 = first) of several.

    Several pulses and no `pulse` (a bounce, a double hit) is an `InputError` that lists them.
    The cut runs from halfway between pulses to halfway to the next, so each keeps its baseline.
    """
    pulses = find_pulses(record.time_s, record.force_n)
    if pulse is None:
        if len(pulses) > 1:
            listed = "; ".join(
                f"#{k} peak {record.force_n[p]:.4g} N at {record.time_s[p] * 1e3:.4g} ms"
                for k, (_, _, p) in enumerate(pulses, start=1))
            raise InputError(f"force_n: found {len(pulses)} pulses ({listed}); a record should "
                             "hold one impact: choose one with --pulse N (pulse=N in Python), "
                             "1 for the first")
        return record
    if isinstance(pulse, bool) or not isinstance(pulse, (int, np.integer)) or \
            not 1 <= pulse <= max(len(pulses), 1):
        raise InputError(f"pulse: {pulse} out of range 1..{max(len(pulses), 1)} (the record "
                         f"holds {len(pulses)} pulse{'s' if len(pulses) != 1 else ''})")
    if len(pulses) <= 1:
        return record
    k = int(pulse) - 1
    start = 0 if k == 0 else (pulses[k - 1][1] + pulses[k][0]) // 2
    stop = record.sample_count if k == len(pulses) - 1 else (pulses[k][1] + pulses[k + 1][0]) // 2
    cut = slice(start, stop)

    def part(series):
        return None if series is None else series[cut]

    return record.replace(time_s=record.time_s[cut], force_n=record.force_n[cut],
                          velocity_m_s=part(record.velocity_m_s),
                          tangential_force_n=part(record.tangential_force_n),
                          metadata={**record.metadata, "pulse": int(pulse),
                                    "pulses_found": len(pulses)})


# --------------------------------------------------------------------------- momentum


#: An impulse that misses m (v_in + v_out) by more than this factor (either way) is a unit slip.
UNIT_SLIP_FACTOR = 3.0

#: Factor J / m (v_in + v_out) -> the slips that make it.
_SLIPS = {
    1e3: ("time in ms under a time_s header (name the column time_ms)",
          "force in N under a force_kn header (name the column force_n)"),
    1e6: ("time in us under a time_s header (name the column time_us)",),
    1e-3: ("force in kN under a force_n header (name the column force_kn)",
           "time in s under a time_ms header (name the column time_s)",
           "mass in g given as mass_kg (a cricket ball is 0.16 kg)"),
    1e-6: ("time in s under a time_us header (name the column time_s)",),
    1 / 3.6: ("speeds in km/h given as m/s (divide by 3.6)",),
}
#: The same for a WAV record: no header, but the sensor settings that scale its force.
_WAV_SLIPS = {
    # a sensitivity too large makes the force too small: V/kN typed as V/N is the slip of mV/N
    1e-3: ("sensitivity in mV/N or V/kN given as V/N (9.442e-5 V/N is 0.09442 mV/N)",
           "mass in g given as mass_kg (a cricket ball is 0.16 kg)"),
    1e-6: ("sensitivity in mV/kN given as V/N (94.42 mV/kN is 9.442e-5 V/N)",),
    10.0: ("the amplifier gain not given (--amplifier-gain)",),
    0.1: ("the full scale not given (--full-scale-v: the volts of the largest code)",),
    1 / 3.6: _SLIPS[1 / 3.6],
}


def likely_slips(ratio: float, wav: bool = False) -> str:
    """The unit slips that would make the impulse `ratio` times m (v_in + v_out); `wav`: those
    of a WAV record (its sensor settings) rather than a CSV's (its header)."""
    found = [slip for factor, slips in (_WAV_SLIPS if wav else _SLIPS).items()
             if abs(np.log(ratio / factor)) < np.log(2) for slip in slips]
    if found:
        return "likely " + " or ".join(found)
    return ("no usual unit slip gives this factor; check the force scaling (sensitivity, gain, "
            "full scale), the mass and the speeds")


def check_momentum(impulse_n_s: float, mass_kg: float, impact_speed_m_s: float,
                   rebound_speed_m_s: float | None, allow: Collection[str] = (),
                   wav: bool = False) -> None:
    """The `unit-slip` and `cor-above-one` checks of an impact's impulse and speeds (`wav`: of
    a WAV record, whose likely slips are in its sensor settings).

    The impulse J must match m (v_in + v_out) within `UNIT_SLIP_FACTOR`; without a measured
    rebound speed, it must lie within that factor of m v_in..2 m v_in (COR 0..1). The rebound
    speed, measured or from the impulse, must not exceed the impact speed.
    """
    m, v_in, v_out = mass_kg, impact_speed_m_s, rebound_speed_m_s
    if v_out is None:
        low, high = m * v_in, 2 * m * v_in
        expected = f"m v_in..2 m v_in = {low:.4g}..{high:.4g} N s (COR 0..1)"
    else:
        low = high = m * (v_in + v_out)
        expected = f"m (v_in + v_out) = {low:.4g} N s"
    ratio = impulse_n_s / high if impulse_n_s > high else impulse_n_s / low if impulse_n_s < low \
        else 1.0
    if not 1 / UNIT_SLIP_FACTOR <= ratio <= UNIT_SLIP_FACTOR:
        flag("unit-slip", f"impulse: the integral of F dt = {impulse_n_s:.4g} N s is {ratio:.3g} "
             f"times {expected}, beyond the factor {UNIT_SLIP_FACTOR:g} a measurement can miss "
             f"by: {likely_slips(ratio, wav)}", allow)
    cor = (impulse_n_s / (m * v_in) - 1.0) if v_out is None else v_out / v_in
    if cor > 1.0:
        source = "the impulse gives" if v_out is None else (
            f"the rebound speed {v_out:g} m/s is above the impact speed {v_in:g} m/s:")
        flag("cor-above-one", f"{source} COR {cor:.4g} > 1, impossible for a passive ball: check "
             "the speeds (swapped?), the mass and the force scaling", allow)


# --------------------------------------------------------------------------- noise


#: A contact-window threshold set by the noise above this fraction of the peak cuts the pulse's
#: slow edges enough to shorten the contact time by several per cent.
NOISY_THRESHOLD_FRACTION = 0.02


def noisy_window_note(window, peak_force_n: float, filter_name: str,
                      source: str | None = None) -> str | None:
    """Advice when the noise sets the contact-window threshold high on the pulse (None if not);
    `source` (the record's file) starts the note, so that several files' notes tell apart."""
    fraction = window.threshold_n / peak_force_n
    if fraction <= NOISY_THRESHOLD_FRACTION:
        return None
    if filter_name == "none":
        advice = "filter it (--filter loess)"
    elif filter_name.startswith("cfc"):
        advice = "filter it harder (a lower CFC class, or --filter loess)"
    else:
        advice = "filter it harder (a longer --filter-window-s)"
    where = "" if source is None else f"{source}: "
    return (f"{where}noisy record: the noise ({window.noise_rms_n:.4g} N RMS) sets the contact "
            f"threshold at {fraction:.1%} of the peak, above {NOISY_THRESHOLD_FRACTION:.0%}, so "
            f"the slow ends of the pulse are cut and the contact time may read short; {advice}")
