"""REPRODUCTION, not a recommended model: the thesis' appendix function `Sim1` exactly as
published, and its three-element use (three `Sim1` runs with their own masses, forces added).
They exist so that tables 7-1 and 7-2 can be replayed and compared with the `single_element` and
`three_element` models.

What `Sim1` does, step by step (dt = 2e-5 s, position y <= 0 in compression, v > 0 towards the
surface): y_new = y - v dt; spring force k |y_new|^alpha; *only while rebounding* (y_new >= y) a
"damping" force -c |y_new - y|, i.e. c times the displacement increment of the step; v -= F/m dt;
it stops when y_new >= 0 (displacement-based end of contact). The first force sample F1 = k (v dt)^alpha
is then subtracted from the whole pulse and only the samples at or above it are kept.

Consequences, worth knowing before using tables 7-1 and 7-2: the damping force is c |v| dt, so the
table's c (labelled N m/s, in fact N per m of increment) acts like a viscous coefficient of
c dt = c x 2e-5 N s/m during rebound only (500 -> 0.01 N s/m): the model is practically elastic,
with a COR near 1, and its results change with dt.
"""

from __future__ import annotations

import numpy as np

from ..checks import check_range
from .base import BatchResult, LumpedModel, Parameter
from .three_element import UNITS
from .three_element import MODEL as THREE_ELEMENT

THESIS_STEP_S = 2e-5
MAX_STEPS = 200_000


def sim1(stiffness, exponent, c, mass, speed, dt=THESIS_STEP_S, y0=0.0):
    """`Sim1(k, a, c, m, v, dt, y0)` for arrays of parameter sets (B,): returns the per-set
    force pulses (list of arrays, after the code's offset and trimming), velocity histories
    (positive towards the surface, same samples), the untrimmed forces and the final velocities."""
    k, a, c, m = (np.asarray(x, dtype=float) for x in (stiffness, exponent, c, mass))
    v = np.broadcast_to(np.asarray(speed, dtype=float), k.shape).copy()
    y1 = np.full(k.shape, y0)
    y2 = y1 - v * dt
    f = -np.sign(y2 - y0) * k * np.abs(y2 - y0) ** a
    v = v - f / m * dt
    forces, velocities = [f], [v.copy()]
    active = y2 < y0
    while active.any() and len(forces) < MAX_STEPS:
        y1_new = y2
        y2_new = y1_new - v * dt
        spring = -np.sign(y2_new - y0) * k * np.abs(y2_new - y0) ** a
        damping = np.where(y2_new >= y1_new, -c * np.abs(y2_new - y1_new), 0.0)
        f = spring + damping
        v_new = v - f / m * dt
        y1 = np.where(active, y1_new, y1)
        y2 = np.where(active, y2_new, y2)
        v = np.where(active, v_new, v)
        forces.append(np.where(active, f, np.nan))
        velocities.append(v.copy())
        active &= y2 < y0
    forces, velocities = np.array(forces), np.array(velocities)
    pulses, pulse_velocities, raw = [], [], []
    for j in range(k.size):
        series = forces[:, j][~np.isnan(forces[:, j])]
        offset = max(series[0], series[-1])
        keep = series >= offset
        pulses.append(series[keep] - offset)
        pulse_velocities.append(velocities[: series.size, j][keep])
        raw.append(series - offset)
    return pulses, pulse_velocities, raw, v


def _contact_time(raw: np.ndarray, kept: int, dt: float) -> float:
    """Where the trimmed pulse returns to zero, interpolated after its last kept sample."""
    if kept >= raw.size:
        return (kept - 1) * dt
    before, after = raw[kept - 1], raw[kept]
    return (kept - 1 + before / (before - after)) * dt


class _ThesisModel(LumpedModel):
    reproduction = True

    def __init__(self, name, summary, parameters, units, bounds):
        self.name, self.summary, self.parameters = name, summary, parameters
        self._units, self._bounds = units, bounds

    def default_bounds(self, scale):
        return self._bounds(scale)

    def check(self, params, mass_kg):
        super().check(params, mass_kg)
        full = self.full(params)
        for name, value in full.items():
            if name.startswith("c"):
                check_range(f"params.{name}", value, 0.0)
            elif name.startswith("alpha"):
                check_range(f"params.{name}", value, 0.5, 5.0)
            else:  # stiffnesses and unit masses
                check_range(f"params.{name}", value, 0.0, low_open=True)

    def ball_mass_kg(self, params, mass_kg):
        if self._units == 1:
            return super().ball_mass_kg(params, mass_kg)
        return THREE_ELEMENT.ball_mass_kg(params, mass_kg)

    def run_batch(self, params, mass_kg, impact_speed_m_s, step_s=None, steps=None):
        params = np.atleast_2d(np.asarray(params, dtype=float))
        n = self._units
        k, a, c = params[:, 0:n], params[:, n:2 * n], params[:, 2 * n:3 * n]
        m = np.full_like(k, mass_kg) if n == 1 else params[:, 3 * n:4 * n]
        pulses, velocities, raw, final = sim1(k.ravel(), a.ravel(), c.ravel(), m.ravel(),
                                              impact_speed_m_s)
        length = max(p.size for p in pulses) + 1
        count = params.shape[0]
        force = np.zeros((count, length))
        momentum = np.zeros((count, length))
        contact = np.zeros(count)
        for i in range(count):
            for u in range(n):
                j = i * n + u
                size = pulses[j].size
                force[i, :size] += pulses[j]
                momentum[i, :size] += m[i, u] * velocities[j]
                momentum[i, size:] += m[i, u] * final[j]
                contact[i] = max(contact[i], _contact_time(raw[j], size, THESIS_STEP_S))
        total = m.sum(axis=1)
        velocity = momentum / total[:, None]
        rebound = -(m * final.reshape(count, n)).sum(axis=1) / total
        time = np.arange(length) * THESIS_STEP_S
        return BatchResult(time, force, velocity, contact, rebound, np.ones(count, bool))


def _single_bounds(scale):
    return {"k": scale.stiffness_force_bounds_n, "alpha": (1.0, 2.5),
            "c": (0.0, 5000.0)}


def _three_bounds(scale):
    bounds = THREE_ELEMENT.default_bounds(scale)
    for i in range(1, UNITS + 1):
        bounds[f"c{i}"] = (0.0, 5000.0)
    return bounds


_C_NOTE = "N/m, Sim1 sense: force c |dy| per step while rebounding (about c dt N s/m)"

SINGLE_ELEMENT_THESIS = _ThesisModel(
    "single_element_thesis",
    "REPRODUCTION of the appendix Sim1 (dt = 2e-5 s), for replaying table 7-1",
    (Parameter("k", "N/m^alpha", "spring stiffness", "stiffness", "alpha"),
     Parameter("alpha", "1", "spring exponent"),
     Parameter("c", "N/m", f"Sim1 damping ({_C_NOTE})")),
    1, _single_bounds)

THREE_ELEMENT_THESIS = _ThesisModel(
    "three_element_thesis",
    "REPRODUCTION of the appendix three-element code (3 x Sim1), for replaying table 7-2",
    tuple(Parameter(p.name, "N/m" if p.name.startswith("c") else p.unit,
                    f"unit {p.name[-1]} Sim1 damping ({_C_NOTE})" if p.name.startswith("c")
                    else p.description, p.search, p.exponent)
          for p in THREE_ELEMENT.parameters),
    UNITS, _three_bounds)
