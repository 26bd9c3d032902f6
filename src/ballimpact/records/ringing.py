"""The load cell's own ringing: found in the record and taken out of it.

A load cell under an impact plate is a lightly damped oscillator: what it records is the contact
force passed through H(s) = w^2 / (s^2 + 2 zeta w s + w^2). Its resonance (8-25 kHz for the
rigs of ball tests) is excited by the pulse's kinks and its peak, rings through the contact and
on after it ends, where the force is zero. `find_resonance` asks which resonance, if any, best
explains the record as a smooth force seen through a cell (a Bayesian model comparison over the
contact and the free vibration after it), and `compensate` divides the record's spectrum by H
and cuts what lies above the resonance with a zero-phase 4-pole Butterworth magnitude, so that
the dynamic amplification and the ringing of the peak and the edges are taken out and the noise
is not raised (docs/features.md, "Load-cell ringing").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .reconstruct import discrepancy_weight
from .record import ContactWindow, ImpactRecord, pre_impact_slice, sample_rate_hz

#: Fewest samples in the contact, and after it, that the search needs.
MIN_SAMPLES = 16
#: The contact force is sought from this fraction of the contact time before the contact
#: window to as far after it ...
CONTACT_MARGIN = 0.15
#: ... and the record is explained up to this many contact times after the contact (the free
#: vibration: 1.5 ms of it decays by 5x at 8 kHz and a damping ratio of 0.03).
FREE_SPAN = 1.5
#: A resonance is taken when it lowers the cost by this many noise variances (a likelihood
#: ratio of white noise, 2 parameters searched: chance gives more than 25 about once in 10^5) ...
DETECTION = 25.0
#: ... when its free vibration after the contact lowers the misfit there by this many noise
#: variances (a 3-sigma signal) ...
FREE_DETECTION = 9.0
#: ... and lies between this many cycles per contact time and 0.4 of the sampling rate.
MIN_CYCLES_PER_CONTACT = 5.0
#: A resonance (or damping ratio) found within this factor of the band's ends (of
#: `DAMPING_RANGE`) is the search running into its bound, not a cell.
BAND_EDGE = 1.05
#: The first search's step between resonances (a ratio: finer than the half-power width of a
#: cell of damping ratio 0.02) and its damping ratios.
GRID_STEP = 1.03
GRID_DAMPING = (0.03, 0.1)
#: Nodes of the contact force a contact time, at most.
NODES_PER_CONTACT = 80
#: The cut above the resonance, as a multiple of its frequency.
LOWPASS_FACTOR = 2.0
#: Damping ratios accepted as a load cell's (mounted cells: 0.01-0.1; below 0.01 the cell's
#: gain near its resonance lets it "explain" any pulse: a 3.3 kHz, 0.003 resonance ringing at
#: 70% of the peak was found in an ideal cell's 50 kHz record).
DAMPING_RANGE = (0.01, 0.15)
#: The ringing a resonance may add to the pulse, at most, as a fraction of its peak.
MAX_RINGING = 0.5


@dataclass(frozen=True)
class Resonance:
    """The load cell's resonance: `frequency_hz` (undamped natural frequency, Hz),
    `damping_ratio`, and the largest ringing (N) it adds to the force (nan when given)."""

    frequency_hz: float
    damping_ratio: float
    amplitude_n: float

    def to_dict(self) -> dict[str, float]:
        return {"frequency_hz": self.frequency_hz, "damping_ratio": self.damping_ratio,
                "ringing_amplitude_n": self.amplitude_n}


def find_resonance(record: ImpactRecord, window: ContactWindow) -> Resonance | None:
    """The load-cell resonance that best explains `record`'s ringing (`_find_resonance`), on one
    BLAS thread: its hundreds of small products and factorizations ran 30 times slower when
    OpenBLAS woke its threads for each (2.3 s against 0.08 s on a 100 kHz record, 2 cores)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _find_resonance(record, window)


def _find_resonance(record: ImpactRecord, window: ContactWindow) -> Resonance | None:
    """The load-cell resonance that best explains `record`'s ringing, or None when the record is
    explained no better with one than without (see the module).

    For a resonance (w, zeta), the record y (in units of its noise) is taken as H s plus white
    noise, s the contact force with a smoothness prior (second differences of precision lam,
    lam from the discrepancy principle without a cell) on nodes over the contact, zero outside
    it; the rows run on after the contact over its free vibration. The cost is -2 log of the
    marginal likelihood: the penalized misfit plus log det(H'H + lam D'D), the Occam factor
    that charges a cell for the gain near its resonance (without it, a cell of damping ratio
    0.002 near 3 kHz "explained" ideal records by letting s be smoother). A ringing cell makes
    H s ring where s is smooth; without one, s itself must ring, which its prior charges for.
    The resonance of least cost (a grid of `GRID_STEP`, `GRID_DAMPING`, refined) is taken
    when it lowers the cost by `DETECTION` below the cost without a cell, its free vibration
    after the contact is seen (`FREE_DETECTION`), it lies inside the band (`BAND_EDGE`) and
    `DAMPING_RANGE`, and its ringing stays below `MAX_RINGING` of the peak."""
    from scipy.optimize import minimize

    t, f = record.time_s, record.force_n
    noise = window.noise_rms_n
    step = float(np.median(np.diff(t)))
    samples = window.duration_s / step
    if noise <= 0 or samples < MIN_SAMPLES:
        return None
    margin = max(4, int(CONTACT_MARGIN * samples))
    first = max(0, window.first - margin)
    support = min(t.size, window.last + margin + 1) - first
    rows = min(t.size, window.last + int(FREE_SPAN * samples) + 1) - first
    if rows - support < MIN_SAMPLES:
        return None
    y = f[first : first + rows] / noise  # in units of the noise: the costs are chi-squares
    # the force on nodes every `stride` samples, linear between them (at most NODES_PER_CONTACT
    # a contact: the search's cost grows with the cube of their number)
    stride = max(1, int(round(samples / NODES_PER_CONTACT)))
    nodes = support // stride + 2
    shift = np.arange(rows)[:, None] - stride * np.arange(nodes)[None, :]
    hat = np.clip(1 - np.abs(np.arange(1 - stride, stride)) / stride, 0.0, None)
    roughness = np.diff(np.eye(nodes), 2, axis=0)
    # the force may kink where the contact starts and ends (a damped ball's pulse ends on a
    # slope): a prior that smoothed those kinks had the cell's gain make up their ringing, and
    # the damping ratio ran to its lower bound
    for edge_s in (window.start_s, window.end_s):
        node = int(round((np.searchsorted(t, edge_s) - first) / stride))
        roughness[max(0, node - 2) : node + 1] = 0.0
    # a small ridge: the straight lines that D2 does not see get a proper (wide) prior too
    penalty = roughness.T @ roughness + 1e-9 * np.eye(nodes)
    identity = _shifted(hat, shift, stride)
    lam = _discrepancy_roughness(y, identity, penalty, support)
    size = 1 << int(np.ceil(np.log2(2 * rows)))

    def cost(frequency_hz: float, zeta: float) -> tuple[float, np.ndarray, np.ndarray]:
        h = _impulse_response(frequency_hz, zeta, step, size)[:rows]
        cell = _shifted(np.convolve(h, hat), shift, stride)
        value, s = _evidence(y, cell, lam * penalty)
        return value, s, cell

    without = _evidence(y, identity, lam * penalty)[0]
    low, high = MIN_CYCLES_PER_CONTACT / window.duration_s, 0.4 / step
    if high <= low:
        return None
    frequencies = np.geomspace(low, high, 1 + int(np.log(high / low) / np.log(GRID_STEP)))
    grid = [(fn, zeta) for fn in frequencies for zeta in GRID_DAMPING]
    costs = [cost(fn, zeta)[0] for fn, zeta in grid]
    fn0, zeta0 = grid[int(np.argmin(costs))]

    def objective(q: np.ndarray) -> float:
        fn, zeta = np.exp(q)
        if not (low <= fn <= high and DAMPING_RANGE[0] <= zeta <= DAMPING_RANGE[1]):
            return without + 1.0
        return cost(fn, zeta)[0]

    best = minimize(objective, np.log([fn0, zeta0]), method="Nelder-Mead",
                    options={"xatol": 1e-4, "fatol": 1e-3, "maxiter": 80})
    fn, zeta = (float(v) for v in np.exp(best.x))
    value, s, cell = cost(fn, zeta)
    if (without - value < DETECTION or not low * BAND_EDGE < fn < high / BAND_EDGE
            or not DAMPING_RANGE[0] * BAND_EDGE < zeta < DAMPING_RANGE[1] / BAND_EDGE):
        return None
    # a ball rings too, but only a cell rings on after the contact: its free vibration must be
    # seen there (the FE pulses' own contact ringing explained within the contact was taken
    # for a cell of damping ratio 0.1-0.17 at 17-20 kHz when this was not asked)
    recorded = cell @ s
    free = y[support:]
    seen = float(free @ free - np.sum((free - recorded[support:]) ** 2))
    if seen < FREE_DETECTION:
        return None
    amplitude = float(np.max(np.abs(recorded - identity @ s))) * noise
    if amplitude > MAX_RINGING * float(np.max(f)):
        return None
    return Resonance(fn, zeta, amplitude)


def _evidence(y: np.ndarray, cell: np.ndarray, prior: np.ndarray) -> tuple[float, np.ndarray]:
    """-2 log of the marginal likelihood of `y` (unit-variance noise) for y = cell @ s with s
    drawn from the smoothness prior of precision `prior`, up to a constant; and the most likely
    s. The penalized misfit alone would favour a cell whose high gain near its resonance makes
    any s look smooth; the log-determinant (Occam's factor) charges for that gain."""
    from scipy.linalg import cho_factor, cho_solve

    factor = cho_factor(cell.T @ cell + prior)
    rhs = cell.T @ y
    s = cho_solve(factor, rhs)
    return float(y @ y - rhs @ s + 2 * np.sum(np.log(np.diag(factor[0])))), s


def _impulse_response(frequency_hz: float, zeta: float, step: float, size: int) -> np.ndarray:
    """The cell's response to one unit sample (H of `compensate`, sampled)."""
    ratio = np.fft.rfftfreq(size, step) / frequency_hz
    h = np.fft.irfft(1 / (1 - ratio**2 + 2j * zeta * ratio), n=size)
    # round-off far below the response (its products subnormal) slows the products twentyfold
    return np.where(np.abs(h) > 1e-12 * np.max(np.abs(h)), h, 0.0)


def _shifted(response: np.ndarray, shift: np.ndarray, stride: int) -> np.ndarray:
    """The matrix whose column k is `response` (to a hat of half-width `stride` samples centred
    on node k; its first entry `stride` - 1 samples before the node) at rows `shift` + k stride."""
    index = shift + stride - 1
    padded = np.append(response, 0.0)
    return padded[np.where((index >= 0) & (index < response.size), index, -1)]


def _discrepancy_roughness(y: np.ndarray, basis: np.ndarray, penalty: np.ndarray,
                           rows: int) -> float:
    """The roughness weight whose smoothest curve `basis` @ s leaves residuals of unit
    variance over the first `rows` samples of `y` (in noise units: the discrepancy principle)."""
    y, basis = y[:rows], basis[:rows]
    normal, rhs = basis.T @ basis, basis.T @ y

    def squared_residual(lam: float) -> float:
        residual = y - basis @ np.linalg.solve(normal + lam * penalty, rhs)
        return float(residual @ residual)

    return discrepancy_weight(squared_residual, rows, (1e-6, 1e12), steps=40)


def compensate(record: ImpactRecord, resonance: Resonance) -> ImpactRecord:
    """`record` with the resonance divided out of its force (uniform sampling), above it cut by
    a zero-phase 4-pole Butterworth magnitude at the resonance frequency. The pre-impact
    offset (`records.pre_impact_slice`) is taken off before the zero padding and put back: an
    offset would end in a step there, which the division by H would make ring."""
    step = 1.0 / sample_rate_hz(record)
    n = record.force_n.size
    size = 1 << int(np.ceil(np.log2(2 * n)))  # padded: no wrap-around of the ringing
    padded = np.full(size, 0.0)
    pre = record.force_n[pre_impact_slice(record.force_n, record.time_s)]
    base = float(np.mean(pre)) if pre.size else 0.0
    padded[:n] = record.force_n - base
    ratio = np.fft.rfftfreq(size, step) / resonance.frequency_hz
    inverse = 1 - ratio**2 + 2j * resonance.damping_ratio * ratio  # 1 / H
    lowpass = 1 / (1 + (ratio / LOWPASS_FACTOR) ** 8)  # |Butterworth|^2, 4 poles: zero phase
    force = np.fft.irfft(np.fft.rfft(padded) * inverse * lowpass, n=size)[:n] + base
    return record.replace(force_n=force, metadata={**record.metadata,
                                                   "load_cell_resonance": resonance.to_dict()})
