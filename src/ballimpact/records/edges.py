"""Contact start and end of a measured pulse, fitted with the shape a contact must have.

A force pulse leaves zero as a power of the time since contact: a sphere pressed into a plane at
a nearly constant speed carries F ~ y^1.5 ~ (t - t0)^1.5 (Hertz, and Hunt-Crossley damping keeps
the power), a linear spring F ~ (t - t0) (a half-sine), a damper a step. Near each end the pulse is
therefore fitted by least squares with

    F(t) = a ((t - t0) / (t_top - t0))^p   for t > t0, 0 before,

over the baseline samples just outside the contact and the samples up to the first one that
reaches `EDGE_FRACTION` of the peak (`t_top`); the power p lies in `EXPONENT_RANGE`, drawn
towards 1.5 by a prior (`POWER_PRIOR`) that a well-sampled edge overrules. The zero
crossing t0 then comes from the whole edge, not from the two samples nearest the noise threshold,
so that neither the noise (which raises the threshold) nor the sampling rate (which sets where
the samples fall) moves it. The end is the same fit mirrored in time. docs/features.md says how
the fraction and the range were chosen.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: The edge fit covers the pulse up to the first sample at this fraction of the peak ...
EDGE_FRACTION = 0.15
#: ... or further, until it holds this many samples above the baseline.
MIN_EDGE_SAMPLES = 5
#: ... but never beyond this fraction of the peak.
MAX_EDGE_FRACTION = 0.6
#: Samples outside the threshold that the fit takes, as a multiple of those inside it: the zero
#: crossing of a slow edge may lie far outside the noise threshold.
OUTSIDE_FACTOR = 2
#: ... and at least this fraction of the samples above the threshold.
OUTSIDE_SPAN = 0.5
#: Allowed powers p of the edge shape: 0.5 (steeper than a spring) to 3 (a very soft start).
EXPONENT_RANGE = (0.5, 3.0)
#: The power's prior, mean and standard deviation: a sphere's Hertzian contact (1.5), weak
#: enough that a pulse with many samples above the noise sets its own power (a half-sine's 1).
POWER_PRIOR = (1.5, 0.25)


@dataclass(frozen=True)
class EdgeFit:
    """One edge of the pulse: zero-force time `time_s` (s), shape `amplitude_n` (N) times
    ((t - time_s) / (top_s - time_s))^`exponent`, fitted up to `top_s` (s)."""

    time_s: float
    top_s: float
    amplitude_n: float
    exponent: float

    def force(self, time_s: np.ndarray) -> np.ndarray:
        """The fitted edge shape at `time_s` (N): zero outside the contact."""
        s = np.clip((np.asarray(time_s) - self.time_s) / (self.top_s - self.time_s), 0.0, None)
        return self.amplitude_n * s**self.exponent


def fit_edge(time_s: np.ndarray, force_n: np.ndarray, peak_index: int, first: int, last: int,
             side: int, guess: EdgeFit | None = None, noise_n: float = 0.0) -> EdgeFit:
    """The edge (`side` +1: start, -1: end) of the pulse whose largest sample is `peak_index` and
    whose samples `first..last` stand above the noise threshold (`records.contact_window`), in a
    record of noise `noise_n` (N RMS: the misfit's unit, against which the power's prior
    weighs). Three first guesses of the power (1, 1.5, 2.5), or the one of `guess`, an earlier
    fit of the same edge."""
    from scipy.optimize import least_squares  # here: SciPy's import is slow

    if side > 0:
        t, f, edge, top_limit = time_s, force_n, first, peak_index
    else:  # mirror the end into a start: time reversed and negated
        t, f = -time_s[::-1], force_n[::-1]
        edge, top_limit = time_s.size - 1 - last, time_s.size - 1 - peak_index
    peak = float(force_n[peak_index])
    top = _top_index(f, edge, top_limit, peak)
    rising = top - edge + 1
    # outside the threshold: a slow edge (a damped ball's tail) may reach zero a third of the
    # contact beyond it, when noise sets the threshold high
    outside = max(OUTSIDE_FACTOR * rising, int(OUTSIDE_SPAN * (last - first)), MIN_EDGE_SAMPLES)
    begin = max(0, edge - outside)
    x, y = t[begin : top + 1], f[begin : top + 1]
    t_top = float(x[-1])
    span = t_top - float(x[0])

    def shape(q: np.ndarray) -> np.ndarray:
        t0, amplitude, power = q
        return amplitude * np.clip((x - t0) / (t_top - t0), 0.0, None) ** power

    # the misfit in units of the noise, and the prior on the power in units of its spread
    noise = max(noise_n, 1e-9 * peak)

    def residual(q: np.ndarray) -> np.ndarray:
        return np.append((shape(q) - y) / noise, (q[2] - POWER_PRIOR[0]) / POWER_PRIOR[1])

    lower = [float(x[0]), 0.0, EXPONENT_RANGE[0]]
    upper = [t_top - 1e-3 * span, 4.0 * max(peak, float(y[-1])), EXPONENT_RANGE[1]]
    guesses = [(t[max(edge - 1, 0)], 1.5), (t[edge], 1.0), (t[max(edge - 1, 0)], 2.5)]
    if guess is not None:
        guesses = [(guess.time_s * side, guess.exponent)]
    best = None
    for start_guess, power in guesses:
        q0 = np.clip([float(start_guess), max(float(y[-1]), 1e-300), power], lower, upper)
        q0[0] = min(max(q0[0], lower[0]), upper[0] - 1e-6 * span)
        fit = least_squares(residual, q0, bounds=(lower, upper),
                            x_scale=[span, max(peak, 1e-300), 1.0], xtol=1e-10, ftol=1e-10)
        if best is None or fit.cost < best.cost:
            best = fit
    t0, amplitude, power = (float(v) for v in best.x)
    if side < 0:
        t0, t_top = -t0, -t_top
    return EdgeFit(t0, t_top, amplitude, power)


def _top_index(f: np.ndarray, edge: int, limit: int, peak: float) -> int:
    """Last sample of the edge fit: the first at `EDGE_FRACTION` of the peak, moved on until
    `MIN_EDGE_SAMPLES` samples lie from `edge` to it, never past `MAX_EDGE_FRACTION` or `limit`."""
    reach = np.flatnonzero(f[edge : limit + 1] >= EDGE_FRACTION * peak)
    top = edge + int(reach[0]) if reach.size else limit
    while top - edge + 1 < MIN_EDGE_SAMPLES and top < limit and f[top + 1] < MAX_EDGE_FRACTION * peak:
        top += 1
    return max(top, min(edge + 1, limit))
