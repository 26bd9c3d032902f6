"""Analytic force pulses with closed-form characteristics, sampled into `ImpactRecord`s.

Used to verify the feature extraction and filters, and as simple stand-ins for measured tests.
Each pulse starts at t = 0 and is sampled at `rate_hz` from `-pre_s` to `duration + post_s`
(the grid may be shifted by `phase` samples, 0 <= phase < 1, to test sampling-phase effects).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..checks import check_positive
from .record import ImpactRecord


def sample_times(duration_s: float, rate_hz: float, pre_s: float, post_s: float, phase: float):
    if not 0 <= phase < 1:
        raise InputError(f"phase: must be in [0, 1), got {phase}")
    step = 1.0 / check_positive("rate_hz", rate_hz)
    first = -int(np.ceil(pre_s / step))
    last = int(np.ceil((duration_s + post_s) / step))
    return (np.arange(first, last + 1) + phase) * step


def half_sine(
    peak_force_n: float,
    duration_s: float,
    rate_hz: float,
    *,
    pre_s: float | None = None,
    post_s: float | None = None,
    phase: float = 0.0,
    **scalars,
) -> ImpactRecord:
    """F = F0 sin(pi t / T) for 0 < t < T, zero elsewhere. `scalars` go to the record
    (mass_kg, impact_speed_m_s, rebound_speed_m_s)."""
    pre = duration_s if pre_s is None else pre_s
    post = duration_s if post_s is None else post_s
    t = sample_times(duration_s, rate_hz, pre, post, phase)
    inside = (t > 0) & (t < duration_s)
    force = np.where(inside, peak_force_n * np.sin(np.pi * t / duration_s), 0.0)
    return ImpactRecord(t, force, metadata={"source": "half_sine"}, **scalars)


def triangle(
    peak_force_n: float,
    rise_s: float,
    fall_s: float,
    rate_hz: float,
    *,
    pre_s: float | None = None,
    post_s: float | None = None,
    phase: float = 0.0,
    **scalars,
) -> ImpactRecord:
    """Linear rise to F0 at t = rise_s, linear fall to zero at rise_s + fall_s."""
    duration = rise_s + fall_s
    pre = duration if pre_s is None else pre_s
    post = duration if post_s is None else post_s
    t = sample_times(duration, rate_hz, pre, post, phase)
    force = peak_force_n * np.clip(np.minimum(t / rise_s, (duration - t) / fall_s), 0.0, None)
    return ImpactRecord(t, force, metadata={"source": "triangle"}, **scalars)


@dataclass(frozen=True)
class KelvinVoigt:
    """Linear spring-dashpot ball on a rigid plane: m x'' + c x' + k x = 0, x(0) = 0,
    x'(0) = v_in. The ball leaves when the contact force k x + c x' returns to zero.

    Closed forms (docs/lumped.md "Verification"): b = c / 2m, w0^2 = k/m, w^2 = w0^2 - b^2,
    x = (v_in / w) e^(-b t) sin(w t), t_c = [pi - atan(2 b w / (w0^2 - 2 b^2))] / w for
    b < w0 / sqrt(2), COR = exp(-b t_c).
    """

    mass_kg: float
    stiffness_n_m: float
    damping_n_s_m: float
    impact_speed_m_s: float

    @property
    def _b_w0_w(self):
        b = self.damping_n_s_m / (2 * self.mass_kg)
        w0 = np.sqrt(self.stiffness_n_m / self.mass_kg)
        if not b < w0 / np.sqrt(2):
            raise InputError("damping_n_s_m: must be below sqrt(2 k m) for a force-based rebound")
        return b, w0, np.sqrt(w0**2 - b**2)

    @property
    def contact_time_s(self) -> float:
        b, w0, w = self._b_w0_w
        return float((np.pi - np.arctan(2 * b * w / (w0**2 - 2 * b**2))) / w)

    @property
    def cor(self) -> float:
        b, _, _ = self._b_w0_w
        return float(np.exp(-b * self.contact_time_s))

    def displacement_m(self, t: np.ndarray) -> np.ndarray:
        b, _, w = self._b_w0_w
        return self.impact_speed_m_s / w * np.exp(-b * t) * np.sin(w * t)

    def velocity_m_s(self, t: np.ndarray) -> np.ndarray:
        b, _, w = self._b_w0_w
        return self.impact_speed_m_s / w * np.exp(-b * t) * (w * np.cos(w * t) - b * np.sin(w * t))

    def force_n(self, t: np.ndarray) -> np.ndarray:
        return self.stiffness_n_m * self.displacement_m(t) + self.damping_n_s_m * self.velocity_m_s(t)

    def record(self, rate_hz: float, *, phase: float = 0.0, measured_rebound: bool = True):
        """The pulse sampled at `rate_hz`, zero outside contact; the record carries the mass, the
        impact speed and (if `measured_rebound`) the exact rebound speed."""
        tc = self.contact_time_s
        t = sample_times(tc, rate_hz, tc, tc, phase)
        inside = (t >= 0) & (t <= tc)
        force = np.where(inside, self.force_n(np.clip(t, 0, tc)), 0.0)
        return ImpactRecord(
            t,
            np.maximum(force, 0.0),
            mass_kg=self.mass_kg,
            impact_speed_m_s=self.impact_speed_m_s,
            rebound_speed_m_s=self.cor * self.impact_speed_m_s if measured_rebound else None,
            metadata={"source": "kelvin_voigt"},
        )


# --------------------------------------------------------------------------- as a rig records them


def hunt_crossley_pulse(cor: float | None, impact_speed_m_s: float, mass_kg: float,
                        stiffness_n_m15: float = 2.06e7):
    """A Hunt-Crossley ball, F = k y^1.5 (1 + lambda y'), on a rigid plane (Hertz for
    `cor` None): `(force(t) N for t s from first contact, contact time s, rebound speed m/s)`,
    integrated to 1e-11 (the sample record's ball, examples/make_sample_record.py)."""
    from scipy.integrate import solve_ivp

    from ..lumped import hunt_crossley_lambda

    lam = 0.0 if cor is None else hunt_crossley_lambda(cor, impact_speed_m_s)

    def force(y, v):
        return stiffness_n_m15 * np.maximum(y, 0.0) ** 1.5 * (1 + lam * v)

    leave = lambda t, s: s[0]  # noqa: E731
    leave.terminal, leave.direction = True, -1
    solution = solve_ivp(lambda t, s: [s[1], -force(s[0], s[1]) / mass_kg], (0, 1.0),
                         [0.0, impact_speed_m_s], events=leave, rtol=1e-11, atol=1e-14,
                         dense_output=True, max_step=1e-6)
    end = float(solution.t_events[0][0])

    def pulse(t):
        t = np.asarray(t, dtype=float)
        out = np.zeros_like(t)
        inside = (t > 0) & (t < end)
        out[inside] = np.maximum(force(*solution.sol(t[inside])), 0.0)
        return out

    # an elastic ball leaves at its impact speed (the integration's round-off above it)
    return pulse, end, min(float(-solution.sol(end)[1]), impact_speed_m_s)


def load_cell_record(pulse, duration_s: float, rate_hz: float, *, noise: float = 0.0,
                     resonance_hz: float | None = None, damping_ratio: float = 0.03,
                     offset: float = 0.0, rng: np.random.Generator | None = None,
                     **scalars) -> ImpactRecord:
    """The force `pulse(t)` (N; contact from t = 0 for `duration_s` s) as a rig records it: through
    a load cell that rings (a second-order system of natural frequency `resonance_hz`, Hz, and
    `damping_ratio`; None: an ideal cell), plus white noise of `noise` x the peak and an offset of
    `offset` x the peak, sampled at `rate_hz` at a random phase from 0.9 contact times before
    contact to 2.4 after. `scalars` go to the record."""
    from scipy.signal import lsim

    rng = rng or np.random.default_rng(0)
    fine_step = min(1 / (50 * rate_hz), duration_s / 5000)
    fine = np.arange(-duration_s, 2.5 * duration_s, fine_step)
    force = pulse(fine)
    peak = float(force.max())
    if resonance_hz is not None:
        w = 2 * np.pi * check_positive("resonance_hz", resonance_hz)
        _, force, _ = lsim(([w * w], [1.0, 2 * damping_ratio * w, w * w]), force, fine - fine[0])
    t = (np.arange(int(3.3 * duration_s * rate_hz)) + rng.uniform(0, 1)) / rate_hz \
        - 0.9 * duration_s
    measured = np.interp(t, fine, force) + peak * (offset + noise * rng.standard_normal(t.size))
    return ImpactRecord(t, measured, metadata={"source": "load_cell_record"}, **scalars)
