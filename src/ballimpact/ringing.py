"""The load cell's own ringing: found in the record and taken out of it.

A load cell under an impact plate is a lightly damped oscillator: what it records is the contact
force passed through H(s) = w^2 / (s^2 + 2 zeta w s + w^2). Its resonance (8-25 kHz for the
rigs of ball tests) is excited by the pulse and rings on after the contact ends, where the force
is zero and the record holds nothing but that free vibration. `find_resonance` fits a damped
sine to the samples after the contact, and `compensate` divides the record's spectrum by H and
cuts what lies above the resonance with a zero-phase 4-pole Butterworth magnitude, so that the
dynamic amplification and the ringing of the peak and the edges are taken out and the noise is
not raised (docs/features.md, "Load-cell ringing").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .records import ContactWindow, ImpactRecord, rms

#: Fewest free-vibration samples the fit needs.
MIN_SAMPLES = 16
#: A resonance is taken when its free vibration stands this many times above the noise ...
MIN_AMPLITUDE_NOISE = 4.0
#: ... explains this fraction of the free samples' variance ...
MIN_EXPLAINED = 0.5
#: ... and lies between this many cycles per contact time and 0.4 of the sampling rate.
MIN_CYCLES_PER_CONTACT = 3.0
#: The cut above the resonance, as a multiple of its frequency.
LOWPASS_FACTOR = 2.0
#: Damping ratios accepted as a load cell's.
DAMPING_RANGE = (0.002, 0.3)


@dataclass(frozen=True)
class Resonance:
    """The load cell's resonance: `frequency_hz` (undamped natural frequency, Hz),
    `damping_ratio`, and the free vibration's amplitude (N) after the contact."""

    frequency_hz: float
    damping_ratio: float
    amplitude_n: float

    def to_dict(self) -> dict[str, float]:
        return {"frequency_hz": self.frequency_hz, "damping_ratio": self.damping_ratio,
                "free_vibration_amplitude_n": self.amplitude_n}


def find_resonance(record: ImpactRecord, window: ContactWindow) -> Resonance | None:
    """The resonance whose free vibration follows the contact in `record`, or None when none
    stands clear of the noise (see the module's constants)."""
    from scipy.optimize import least_squares

    t, f = record.time_s, record.force_n
    step = float(np.median(np.diff(t)))
    after = np.flatnonzero(t > window.end_s + step)
    if after.size < MIN_SAMPLES or window.noise_rms_n <= 0:
        return None
    x, y = t[after] - t[after[0]], f[after] - np.mean(f[after])
    if rms(y) < 0.5 * MIN_AMPLITUDE_NOISE * window.noise_rms_n:
        return None
    low, high = MIN_CYCLES_PER_CONTACT / window.duration_s, 0.4 / step
    spectrum = np.abs(np.fft.rfft(y * np.hanning(y.size), n=8 * y.size))
    freqs = np.fft.rfftfreq(8 * y.size, step)
    band = (freqs >= low) & (freqs <= high)
    if not band.any():
        return None
    guess = float(freqs[band][np.argmax(spectrum[band])])
    amplitude = float(np.max(np.abs(y[: max(4, int(1 / (guess * step)))])))

    def model(q):
        a, decay, w, phase = q
        return a * np.exp(-decay * x) * np.sin(w * x + phase)

    best = None
    for phase in (0.0, np.pi / 2, np.pi, 3 * np.pi / 2):
        fit = least_squares(lambda q: model(q) - y, [amplitude, 0.05 * 2 * np.pi * guess,
                                                     2 * np.pi * guess, phase],
                            bounds=([0, 0, 2 * np.pi * low, -10], [np.inf, np.inf,
                                                                   2 * np.pi * high, 10]),
                            x_scale=[amplitude, 2 * np.pi * guess, 2 * np.pi * guess, 1.0])
        if best is None or fit.cost < best.cost:
            best = fit
    a, decay, w, _ = best.x
    explained = 1 - np.sum(best.fun**2) / np.sum(y**2)
    natural = float(np.hypot(w, decay))
    zeta = float(decay / natural)
    if (a < MIN_AMPLITUDE_NOISE * window.noise_rms_n or explained < MIN_EXPLAINED
            or not DAMPING_RANGE[0] <= zeta <= DAMPING_RANGE[1]):
        return None
    return Resonance(natural / (2 * np.pi), zeta, float(a))


def compensate(record: ImpactRecord, resonance: Resonance) -> ImpactRecord:
    """`record` with the resonance divided out of its force (uniform sampling), above it cut by
    a zero-phase 4-pole Butterworth magnitude at the resonance frequency."""
    step = float(np.median(np.diff(record.time_s)))
    n = record.force_n.size
    size = 1 << int(np.ceil(np.log2(2 * n)))  # padded: no wrap-around of the ringing
    padded = np.full(size, 0.0)
    base = np.mean(record.force_n[: max(1, n // 10)])
    padded[:n] = record.force_n - base
    ratio = np.fft.rfftfreq(size, step) / resonance.frequency_hz
    inverse = 1 - ratio**2 + 2j * resonance.damping_ratio * ratio  # 1 / H
    lowpass = 1 / (1 + (ratio / LOWPASS_FACTOR) ** 8)  # |Butterworth|^2, 4 poles: zero phase
    force = np.fft.irfft(np.fft.rfft(padded) * inverse * lowpass, n=size)[:n] + base
    return record.replace(force_n=force, metadata={**record.metadata,
                                                   "load_cell_resonance": resonance.to_dict()})
