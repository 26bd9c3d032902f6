"""The pulse of a measured record as one smooth curve, and the features' uncertainty.

`fitted_pulse_curve`: the contact start and end fitted with the shape a contact must have
(`edges.fit_edge`), the samples between them smoothed by a cubic smoothing spline whose smoothing
is chosen from the record itself (the discrepancy principle: no window to pick, and a clean
record is left as it is), both ends pinned at zero force. The curve is returned as a fine
piecewise-linear `pulse_curve.PulseCurve`, so the 19 values come from it exactly as from a
simulated pulse.

`bootstrap_uncertainty`: the standard uncertainty of every value from the record's noise by a
parametric bootstrap: the fitted curve plus white noise of the record's own level (the larger of
the pre-impact noise and the RMS misfit of the curve over the contact, which holds the load
cell's ringing), processed again `draws` times; the standard deviation of each value over the
draws (and the shift of their mean), scaled and combined in quadrature with a floor relative to
the value for the fits' model error (`UNCERTAINTY_MODEL`; docs/features.md, "Uncertainty").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .edges import EdgeFit, fit_edge
from .pulse_curve import PulseCurve
from .record import ContactWindow, ImpactRecord, rms

#: Points of the curve per sample interval between the edges (the curve is piecewise linear
#: through them: a smooth pulse's peak is then within (1/4)^2 / 8 of a sample's curvature).
POINTS_PER_SAMPLE = 4
#: Points of each fitted edge shape.
EDGE_POINTS = 24
#: Bootstrap draws of `bootstrap_uncertainty`.
DRAWS = 40
#: Per value, (scale, floor): the stated standard uncertainty is
#: sqrt((scale x the bootstrap's spread)^2 + (floor x |value|)^2). The draws hold white noise, not
#: the fits' model error (an edge that is not exactly a power, the load cell's ringing), which
#: does not shrink with the noise: a floor relative to the value, in quadrature, stands for it
#: (one factor on the spread alone covered 75-85% at 0.5% noise and up to 99% at 3%). Calibrated
#: so that the 90% intervals cover 90% of the records of
#: `python benchmarks/bench_feature_accuracy.py --calibrate` (seed 7) at each noise level, and
#: checked on other records (its default seed) by the same script (docs/features.md,
#: "Uncertainty"). P14 (a skewness, near 0 for a symmetric pulse) has no relative floor.
UNCERTAINTY_MODEL: dict[str, tuple[float, float]] = {
    "P1": (1.68, 0.007),
    "P2": (1.18, 0.004),
    "P3": (1.30, 0.0011),
    "P4": (1.12, 0.0077),
    "P5": (1.42, 0.031),
    "P6": (0.90, 0.0093),
    "P7": (1.50, 0.018),
    "P8": (1.10, 0.012),
    "P9": (1.26, 0.0077),
    "P10": (1.08, 0.013),
    "P11": (1.48, 0.0033),
    "P12": (2.04, 0.041),
    "P13": (1.26, 0.0023),
    "P14": (1.66, 0.0),
    "P16": (1.62, 0.0),
    "P17": (1.62, 0.0),
    "P18": (1.64, 0.007),
    "P19": (1.18, 0.0027),
    "dynamic_stiffness_n_m": (0.92, 0.018),
    "energy_lost_j": (1.72, 0.0023),
    "impulse_cor": (1.74, 0.00051),
    "impulse_n_s": (1.74, 0.00024),
    "max_compression_m": (0.94, 0.038),
}


@dataclass(frozen=True)
class FittedPulse:
    """What `fitted_pulse_curve` found: the curve (`pulse_curve.PulseCurve`, times from the fitted
    contact start), its two `EdgeFit`s and the spline's smoothing parameter (on the unit
    interval, in units of the peak)."""

    curve: Any
    start: EdgeFit
    end: EdgeFit
    smoothing: float


def fitted_edges(record: ImpactRecord, window: ContactWindow,
                 like: FittedPulse | None = None) -> tuple[EdgeFit, EdgeFit]:
    """The start and end `EdgeFit` of the pulse inside `window` (starting from `like`'s)."""
    peak = int(np.argmax(record.force_n))
    start = fit_edge(record.time_s, record.force_n, peak, window.first, window.last, +1,
                     guess=None if like is None else like.start, noise_n=window.noise_rms_n)
    end = fit_edge(record.time_s, record.force_n, peak, window.first, window.last, -1,
                   guess=None if like is None else like.end, noise_n=window.noise_rms_n)
    return start, end


def fitted_pulse_curve(record: ImpactRecord, window: ContactWindow,
                       like: FittedPulse | None = None,
                       smoothing: float | None = None) -> FittedPulse | None:
    """The smooth pulse of `record` (see the module); None when fewer than 5 samples lie between
    the fitted edges. `like`, the fit of a record of the same pulse (a bootstrap draw's original),
    gives the edges' first guess and the smoothing, so that only the fits run again; `smoothing`
    alone sets the spline's (another record's: a model's pulse smoothed as its test was)."""
    from scipy.interpolate import make_smoothing_spline

    start, end = fitted_edges(record, window, like)
    t, f = record.time_s, record.force_n
    inside = np.flatnonzero((t > start.time_s) & (t < end.time_s))
    if inside.size < 5 or end.time_s <= start.time_s:
        return None
    # the spline through the samples and the zero-force ends (weighted like many samples)
    x = np.concatenate([[start.time_s], t[inside], [end.time_s]])
    y = np.concatenate([[0.0], f[inside], [0.0]])
    keep = np.concatenate([[True], np.diff(x) > 1e-9 * (x[-1] - x[0])])
    x, y = x[keep], y[keep]
    weight = np.ones(x.size)
    weight[[0, -1]] = 100.0
    # on the unit interval and in units of the peak: the smoothing search is ill-conditioned in
    # seconds and newtons
    span, scale = x[-1] - x[0], max(float(np.max(np.abs(y))), 1e-300)
    u, v = (x - x[0]) / span, y / scale
    lam = (like.smoothing if like is not None else smoothing if smoothing is not None
           else discrepancy_smoothing(u, v, weight, window.noise_rms_n / scale))
    unit = make_smoothing_spline(u, v, w=weight, lam=lam)
    spline = lambda time: scale * unit((time - x[0]) / span)  # noqa: E731
    middle = np.linspace(start.top_s, end.top_s,
                         max(3, POINTS_PER_SAMPLE * int(np.sum((t > start.top_s) & (t < end.top_s))) + 1))
    rise = np.linspace(start.time_s, start.top_s, EDGE_POINTS)
    fall = np.linspace(end.top_s, end.time_s, EDGE_POINTS)
    knots_t = np.concatenate([rise[:-1], middle, fall[1:]])
    knots_f = np.concatenate([blended(start, spline, rise[:-1]), spline(middle),
                              blended(end, spline, fall[1:])])
    knots_f[0] = knots_f[-1] = 0.0
    knots_f = np.maximum(knots_f, 0.0)
    order = np.concatenate([[True], np.diff(knots_t) > 0])
    curve = PulseCurve(knots_t[order] - start.time_s, knots_f[order])
    return FittedPulse(curve, start, end, lam)


def blended(edge: EdgeFit, spline, time_s: np.ndarray) -> np.ndarray:
    """The edge's shape near its zero, handed over to the spline towards its top (a smoothstep
    over the upper half of the edge's span): no kink where the two meet."""
    share = np.clip((time_s - edge.time_s) / (edge.top_s - edge.time_s), 0.0, 1.0)
    w = np.clip(2 * share - 1, 0.0, 1.0)
    w = w * w * (3 - 2 * w)  # 0 below the middle of the edge, 1 at its top
    return (1 - w) * edge.force(time_s) + w * spline(time_s)


#: Smoothing parameters `discrepancy_smoothing` searches (on the unit interval, peak units).
SMOOTHING_RANGE = (1e-14, 1e-2)


def discrepancy_smoothing(x: np.ndarray, y: np.ndarray, weight: np.ndarray, noise: float) -> float:
    """The smoothing parameter whose spline leaves residuals of the record's own noise level
    `noise` (Morozov's discrepancy principle: sum of squared residuals = samples x noise^2);
    the least smoothing for a noise-free record."""
    from scipy.interpolate import make_smoothing_spline

    if noise <= 0:
        return SMOOTHING_RANGE[0]

    def squared_residual(lam: float) -> float:
        residual = y - make_smoothing_spline(x, y, w=weight, lam=lam)(x)
        return float(np.sum(residual**2))

    return discrepancy_weight(squared_residual, x.size * noise**2, SMOOTHING_RANGE, steps=30)


def discrepancy_weight(squared_residual, target: float, bounds: tuple[float, float],
                       steps: int) -> float:
    """The weight in `bounds` whose fit leaves `squared_residual(weight)` (growing with the
    weight) at `target` (Morozov's discrepancy principle), by `steps` bisections of its
    logarithm."""
    low, high = np.log(bounds[0]), np.log(bounds[1])
    for _ in range(steps):
        middle = 0.5 * (low + high)
        if squared_residual(float(np.exp(middle))) > target:
            high = middle
        else:
            low = middle
    return float(np.exp(0.5 * (low + high)))


def curve_on(curve, start_s: float, time_s: np.ndarray) -> np.ndarray:
    """The curve (times from `start_s`) at the record's times, zero outside the contact."""
    return np.interp(time_s - start_s, curve.knots_s, curve.knots_n, left=0.0, right=0.0)


def bootstrap_uncertainty(record: ImpactRecord, curve, window: ContactWindow, values_of,
                          draws: int = DRAWS, seed: int = 0) -> dict[str, float]:
    """Standard uncertainty of each value of `values_of(record) -> dict` (see the module);
    `curve`'s times run from the `window`'s start."""
    start_s = window.start_s
    clean = curve_on(curve, start_s, record.time_s)
    contact = (record.time_s >= start_s) & (record.time_s <= start_s + curve.duration_s)
    misfit = rms(record.force_n[contact] - clean[contact]) if contact.any() else 0.0
    noise = max(window.noise_rms_n, misfit)
    if noise <= 0:
        return {}
    rng = np.random.default_rng(seed)
    samples: dict[str, list[float]] = {}
    for _ in range(draws):
        draw = record.replace(force_n=clean + noise * rng.standard_normal(clean.size))
        try:
            values = values_of(draw)
        except Exception:  # a draw without a usable pulse: the others still count
            continue
        for key, value in values.items():
            samples.setdefault(key, []).append(value)
    # the smoothing's bias shows as the draws' mean moving off the value they were drawn from
    # the bias: the draws' mean against the draws' own procedure (one start of the edge fits,
    # the record's smoothing) on the record itself, not against the full fit's values, which
    # may sit in another of the edge fit's minima
    reference = values_of(record)
    return {key: stated_uncertainty(key, float(np.hypot(np.std(v, ddof=1),
                                                        np.mean(v) - reference[key])),
                                    reference[key])
            for key, v in samples.items() if len(v) >= max(3, draws // 2)}


def uncertainty_model(key: str) -> tuple[float, float]:
    """`UNCERTAINTY_MODEL[key]`, or for a value not calibrated the largest scale and no floor (the
    impact speed P15 is given, not measured from the record: its spread and so its uncertainty
    stay 0)."""
    if key in UNCERTAINTY_MODEL:
        return UNCERTAINTY_MODEL[key]
    return max(a for a, _ in UNCERTAINTY_MODEL.values()), 0.0


def stated_uncertainty(key: str, spread: float, value: float) -> float:
    """The standard uncertainty of value `key` from its bootstrap spread (`UNCERTAINTY_MODEL`)."""
    scale, floor = uncertainty_model(key)
    return float(np.hypot(scale * spread, floor * abs(value)))
