"""The pulse between the contact's edges as a piecewise-linear curve (`PulseCurve`), with the
exact integrals the features are built on: crossings of a level, impulse, mean powers, the
ball centre's velocity and compression, and the loop work."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PulseCurve:
    """Piecewise-linear force through `knots_s`, `knots_n` (time from contact start, s; N)."""

    knots_s: np.ndarray
    knots_n: np.ndarray

    @property
    def duration_s(self) -> float:
        return float(self.knots_s[-1] - self.knots_s[0])

    def span(self, level_n: float) -> tuple[float, float]:
        """First up-crossing and last down-crossing of `level_n` (s)."""
        t, f = self.knots_s, self.knots_n
        above = np.flatnonzero(f >= level_n)
        i, j = above[0], above[-1]
        up = t[i] if i == 0 else linear_crossing(t[i - 1], f[i - 1], t[i], f[i], level_n)
        down = t[j] if j == t.size - 1 else linear_crossing(t[j], f[j], t[j + 1], f[j + 1], level_n)
        return float(up), float(down)

    def integral(self, start_s: float, end_s: float) -> float:
        """Exact integral of the curve over [start_s, end_s] (N s)."""
        inside = (self.knots_s > start_s) & (self.knots_s < end_s)
        t = np.concatenate([[start_s], self.knots_s[inside], [end_s]])
        return float(np.trapezoid(np.interp(t, self.knots_s, self.knots_n), t))

    def mean_power(self, power: int, scale_n: float) -> float:
        """Time average of (F / scale_n)^power over the curve, exact for a piecewise-linear F."""
        a, b = self.knots_n[:-1] / scale_n, self.knots_n[1:] / scale_n
        # integral of a linear segment's power: h/(p+1) * sum_j a^j b^(p-j) (stable when a ~ b)
        segment = sum(a**j * b ** (power - j) for j in range(power + 1)) / (power + 1)
        return float(np.sum(segment * np.diff(self.knots_s)) / self.duration_s)

    def velocity(self, impact_speed_m_s: float, mass_kg: float) -> np.ndarray:
        """Ball-centre velocity at the knots, v = v_in - (1/m) integral of F (m/s)."""
        h = np.diff(self.knots_s)
        impulse = np.concatenate([[0.0], np.cumsum(h * (self.knots_n[:-1] + self.knots_n[1:]) / 2)])
        return impact_speed_m_s - impulse / mass_kg

    def displacement(self, velocity_m_s: np.ndarray, mass_kg: float) -> np.ndarray:
        """Ball-centre compression at the knots (m), the exact integral of the velocity (which is
        piecewise quadratic): over a step h, v0 h - h^2 (2 f0 + f1) / (6 m)."""
        h = np.diff(self.knots_s)
        f0, f1 = self.knots_n[:-1], self.knots_n[1:]
        steps = velocity_m_s[:-1] * h - h**2 * (2 * f0 + f1) / (6 * mass_kg)
        return np.concatenate([[0.0], np.cumsum(steps)])

    def work(self, velocity_m_s: np.ndarray, mass_kg: float) -> float:
        """Loop integral of F dy = integral of F v dt (J); F v is cubic on each step, so Simpson's
        rule per step is exact."""
        h = np.diff(self.knots_s)
        f0, f1 = self.knots_n[:-1], self.knots_n[1:]
        v0, v1 = velocity_m_s[:-1], velocity_m_s[1:]
        v_mid = v0 - h * (3 * f0 + f1) / (8 * mass_kg)
        return float(np.sum(h / 6 * (f0 * v0 + 4 * (f0 + f1) / 2 * v_mid + f1 * v1)))


def linear_crossing(t0: float, f0: float, t1: float, f1: float, level: float) -> float:
    return t0 + (level - f0) * (t1 - t0) / (f1 - f0)
