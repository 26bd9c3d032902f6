"""`ImpactRecord`: one ball impact, measured or simulated, and the operations on its samples.

A record holds the normal contact force sampled in time (SI: s, N), optional histories of the
ball-centre velocity and of the tangential force, and the scalars of the impact (ball mass, impact
and rebound speed). Tests and simulations both produce records, so features, comparisons and plots
never care where a curve came from.

Sign conventions: force is positive in compression (ball pushing on the surface); speeds are
magnitudes (> 0); the velocity history is positive towards the surface, so it starts at
+impact speed and ends near -rebound speed.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..checks import check_positive
from ..errors import InputError

#: Relative spread of the time step above which a record counts as non-uniformly sampled.
UNIFORM_STEP_TOLERANCE = 1e-2


@dataclass(frozen=True, eq=False)
class ImpactRecord:
    """One impact: force history plus the scalars that go with it.

    **Arguments** (SI units):

    - `time_s`: sample times, strictly increasing, shape (n,).
    - `force_n`: normal contact force, positive in compression, shape (n,).
    - `velocity_m_s`: optional ball-centre velocity, positive towards the surface, shape (n,).
    - `tangential_force_n`: optional tangential (friction) force, shape (n,).
    - `mass_kg`, `impact_speed_m_s`, `rebound_speed_m_s`: optional scalars, > 0 where given
      (a rebound speed of 0 is allowed).
    - `metadata`: free-form JSON-able information (source file, filter, offsets removed, ...).
      A record loaded from a file has `file` (its path: errors and warnings about the record
      start with it) and, for the package's own data, `builtin` (see `pipeline.process`).

    Invalid values raise `InputError` naming the field.
    """

    time_s: np.ndarray
    force_n: np.ndarray
    velocity_m_s: np.ndarray | None = None
    tangential_force_n: np.ndarray | None = None
    mass_kg: float | None = None
    impact_speed_m_s: float | None = None
    rebound_speed_m_s: float | None = None
    metadata: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        time = _as_series("time_s", self.time_s)
        object.__setattr__(self, "time_s", time)
        if time.size < 3:
            raise InputError(f"time_s: need at least 3 samples, got {time.size}")
        steps = np.diff(time)
        bad = np.flatnonzero(steps <= 0)
        if bad.size:
            i = int(bad[0]) + 1
            kind = "repeated" if steps[bad[0]] == 0 else "decreasing"
            raise InputError(
                f"time_s: must be strictly increasing; sample {i} ({float(time[i])!r} s) is {kind}"
            )
        for name in ("force_n", "velocity_m_s", "tangential_force_n"):
            value = getattr(self, name)
            if value is None:
                continue
            series = _as_series(name, value)
            if series.shape != time.shape:
                raise InputError(f"{name}: has {series.size} samples, time_s has {time.size}")
            object.__setattr__(self, name, series)
        for name, allow_zero in (
            ("mass_kg", False),
            ("impact_speed_m_s", False),
            ("rebound_speed_m_s", True),
        ):
            value = getattr(self, name)
            if value is None:
                continue
            object.__setattr__(self, name, check_positive(name, value, allow_zero=allow_zero))

    @property
    def sample_count(self) -> int:
        return int(self.time_s.size)

    def replace(self, **changes: Any) -> ImpactRecord:
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def with_metadata(self, **entries: Any) -> ImpactRecord:
        return self.replace(metadata={**self.metadata, **entries})


def _as_series(name: str, value: Any) -> np.ndarray:
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected numbers") from None
    if array.ndim != 1:
        raise InputError(f"{name}: expected a 1-D series, got shape {array.shape}")
    bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        raise InputError(f"{name}: sample {int(bad[0])} is not finite ({float(array[bad[0]])!r})")
    return array


# --------------------------------------------------------------------------- sampling


def sample_rate_hz(record: ImpactRecord) -> float:
    """Sampling rate of a uniformly sampled record; `InputError` if the steps are not uniform."""
    steps = np.diff(record.time_s)
    step = float(np.median(steps))
    spread = float(np.max(np.abs(steps - step))) / step
    if spread > UNIFORM_STEP_TOLERANCE:
        raise InputError(
            f"time_s: not uniformly sampled (steps vary by {spread:.1%}); "
            "resample first (ImpactRecord resample / --resample-hz)"
        )
    return 1.0 / step


#: Most samples `resample` will make (about 0.8 GB per series).
MAX_RESAMPLED_SAMPLES = 100_000_000


def resample(record: ImpactRecord, rate_hz: float, method: str = "cubic") -> ImpactRecord:
    """The record on a uniform time grid at `rate_hz` (Hz) by cubic-spline interpolation, or
    with `method="linear"` by linear interpolation.

    The grid starts at the first sample. Going to a lower rate does not filter: low-pass the record
    first (e.g. a CFC filter) so that nothing aliases. Linear suits a finely sampled model pulse
    that ends in exact zeros (a separation): a spline through its kink rings on into the tail with
    small values of alternating sign, which a coarser grid can sample all positive, so that the
    pulse never returns to zero (`comparison.measured_like`).
    """
    if method not in ("cubic", "linear"):
        raise ValueError(f"resample: method {method!r}: allowed cubic, linear")
    rate_hz = check_positive("rate_hz", rate_hz)
    start, end = record.time_s[0], record.time_s[-1]
    count = int(np.floor((end - start) * rate_hz * (1 + 1e-12))) + 1
    if not 3 <= count <= MAX_RESAMPLED_SAMPLES:
        raise InputError(
            f"rate_hz: {rate_hz:g} Hz gives {count} samples over the record; "
            f"allowed 3..{MAX_RESAMPLED_SAMPLES:.0e}"
        )
    time = start + np.arange(count) / rate_hz

    def on_grid(series: np.ndarray | None) -> np.ndarray | None:
        if series is None:
            return None
        if method == "linear":
            return np.interp(time, record.time_s, series)
        from scipy.interpolate import CubicSpline  # here: SciPy's import is slow, most uses never need it

        return CubicSpline(record.time_s, series)(time)

    return record.replace(
        time_s=time,
        force_n=on_grid(record.force_n),
        velocity_m_s=on_grid(record.velocity_m_s),
        tangential_force_n=on_grid(record.tangential_force_n),
        metadata={**record.metadata, "resampled_hz": rate_hz},
    )


# --------------------------------------------------------------------------- baseline and window


def pre_impact_slice(force_n: np.ndarray, time_s: np.ndarray) -> slice:
    """Samples that are surely before the impact: used for the offset and the noise level.

    The pulse is taken to rise no faster before 20% of its peak than between 20% and the peak, so
    everything earlier than t20 - (t_peak - t20) is baseline. Empty if the record starts too late.
    """
    peak_index = int(np.argmax(force_n))
    rise = np.flatnonzero(force_n[: peak_index + 1] >= 0.2 * force_n[peak_index])
    t20 = time_s[rise[0]] if rise.size else time_s[peak_index]
    cutoff = t20 - (time_s[peak_index] - t20)
    return slice(0, int(np.searchsorted(time_s, cutoff, side="left")))


#: Fewest pre-impact samples needed to estimate an offset and a noise level.
MIN_BASELINE_SAMPLES = 8


def remove_baseline(record: ImpactRecord) -> ImpactRecord:
    """Subtract the mean of the pre-impact force samples (the load-cell offset), if there are
    enough of them (`MIN_BASELINE_SAMPLES`); the offset removed goes into the metadata."""
    window = pre_impact_slice(record.force_n, record.time_s)
    if window.stop < MIN_BASELINE_SAMPLES:
        return record.with_metadata(baseline_offset_n=0.0, baseline_samples=0)
    offset = float(np.mean(record.force_n[window]))
    return record.replace(
        force_n=record.force_n - offset,
        metadata={**record.metadata, "baseline_offset_n": offset, "baseline_samples": window.stop},
    )


@dataclass(frozen=True)
class ContactWindow:
    """Where the ball touches: samples `first..last` (inclusive) are above `threshold_n`;
    `start_s` and `end_s` are where the pulse edges reach zero force (see `contact_window`)."""

    first: int
    last: int
    start_s: float
    end_s: float
    threshold_n: float
    noise_rms_n: float

    @property
    def duration_s(self) -> float:
        return self.end_s - self.start_s


def contact_window(
    record: ImpactRecord,
    *,
    threshold_fraction: float = 1e-3,
    noise_factor: float = 5.0,
    min_snr: float = 8.0,
) -> ContactWindow:
    """Find the contact window of the pulse around the force peak.

    Threshold = max(`threshold_fraction` x peak, `noise_factor` x RMS of the pre-impact samples).
    The window is the run of samples above it that holds the peak. Each end (`start_s`, `end_s`)
    is where the straight line through the two outermost samples of the window reaches zero force,
    clipped so that it lies between the edge sample and the nearest sample outside with a force
    <= 0. Two reasons: the sample outside may lie on the flat baseline before contact starts, so
    interpolating towards it would put the start up to one sample early; and a threshold raised by
    noise would otherwise shorten the contact by the time the pulse takes to reach it.

    Raises `InputError` if there is no pulse: the peak is not positive, the window holds fewer than
    3 samples, or the peak is less than `min_snr` times the RMS of the samples outside the window.
    """
    time, force = record.time_s, record.force_n
    peak_index = int(np.argmax(force))
    peak = float(force[peak_index])
    if peak <= 0:
        if np.min(force) < 0:
            raise InputError("force_n: no positive pulse (is the load-cell polarity inverted?)")
        raise InputError("force_n: no pulse (the force is zero throughout)")
    noise = baseline_noise_rms(time, force)
    threshold = max(threshold_fraction * peak, noise_factor * noise)

    below = force <= threshold
    before = np.flatnonzero(below[:peak_index])
    after = np.flatnonzero(below[peak_index:])
    first = int(before[-1]) + 1 if before.size else 0
    last = peak_index + int(after[0]) - 1 if after.size else force.size - 1
    if last - first + 1 < 3:
        raise InputError(
            f"force_n: no pulse above the noise (only {last - first + 1} samples above "
            f"{threshold:.4g} N around the peak of {peak:.4g} N)"
        )
    outside = np.concatenate([force[:first], force[last + 1 :]])
    if outside.size >= MIN_BASELINE_SAMPLES:
        outside_rms = rms(outside)
        if peak < min_snr * outside_rms:
            raise InputError(
                f"force_n: no pulse above the noise (peak {peak:.4g} N is less than {min_snr:g} "
                f"times the {outside_rms:.4g} N RMS outside the contact window)"
            )
    start = _edge_zero(time, force, first, step=+1)
    end = _edge_zero(time, force, last, step=-1)
    return ContactWindow(first, last, start, end, threshold, noise)


def baseline_noise_rms(time_s: np.ndarray, force_n: np.ndarray) -> float:
    """RMS (N) of the samples surely before the impact (`pre_impact_slice`; the offset removed
    first, `remove_baseline`), 0 when fewer than `MIN_BASELINE_SAMPLES`: the record's noise."""
    pre = force_n[pre_impact_slice(force_n, time_s)]
    return rms(pre) if pre.size >= MIN_BASELINE_SAMPLES else 0.0


def rms(values: np.ndarray) -> float:
    """Root mean square, scaled so that no square overflows (forces near 1e300 N stay finite)."""
    scale = float(np.max(np.abs(values))) if values.size else 0.0
    return scale * float(np.sqrt(np.mean((values / scale) ** 2))) if scale > 0 else 0.0


def _edge_zero(time: np.ndarray, force: np.ndarray, edge: int, *, step: int) -> float:
    """Zero-force time of the pulse edge at sample `edge`; `step` points into the window."""
    if step > 0:
        outside = np.flatnonzero(force[: edge + 1] <= 0)
        nearest = outside[-1] if outside.size else None
    else:
        outside = np.flatnonzero(force[edge:] <= 0)
        nearest = edge + outside[0] if outside.size else None
    if nearest is None:
        where = "starts" if step > 0 else "ends"
        raise InputError(
            f"force_n: no sample at or below zero force where the record {where}: it {where} in "
            "contact (record from before the impact to after the rebound) or keeps an offset"
        )
    bound = time[nearest]
    inner = edge + step
    slope = (force[inner] - force[edge]) / (time[inner] - time[edge])
    zero = time[edge] - force[edge] / slope if slope * step > 0 else bound
    low, high = sorted((bound, time[edge]))
    return float(np.clip(zero, low, high))
