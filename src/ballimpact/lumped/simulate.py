"""One lumped-model impact as an `ImpactRecord`, so that the feature extraction applies unchanged."""

from __future__ import annotations

import numpy as np

from ..checks import check_integer, check_positive
from ..errors import SimulationError
from ..records.record import ImpactRecord
from .base import BatchResult, LumpedModel
from .registry import get_model

#: integration steps per contact time in `simulate`
STEPS_PER_CONTACT = 500
_PROBE_STEPS = 256
_PROBE_START_S = 1e-4
_PROBE_TRIES = 12
#: zero-force samples kept before and after contact, as a fraction of the contact time
MARGIN_FRACTION = 0.25


def parameter_vector(model: LumpedModel, params: dict[str, float]) -> np.ndarray:
    full = model.full(params)
    return np.array([full[name] for name in model.parameter_names])


def run_one(model: LumpedModel, params: dict[str, float], mass_kg: float,
            impact_speed_m_s: float, steps_per_contact: int = STEPS_PER_CONTACT) -> BatchResult:
    """A single run on a grid of about `steps_per_contact` steps per contact time: a short probe
    finds the contact time (the window grows until the ball leaves), then the run is repeated on
    the fine grid."""
    vector = parameter_vector(model, params)[None, :]
    duration = _PROBE_START_S
    for _ in range(_PROBE_TRIES):
        probe = model.run_batch(vector, mass_kg, impact_speed_m_s, duration / _PROBE_STEPS,
                                _PROBE_STEPS)
        if probe.separated[0]:
            break
        duration *= 4.0
    else:
        raise SimulationError(
            f"model {model.name}: the ball did not leave the surface within {duration:.3g} s")
    contact = float(probe.contact_time_s[0])
    steps = int(np.ceil(steps_per_contact * 1.2))
    result = model.run_batch(vector, mass_kg, impact_speed_m_s, contact / steps_per_contact, steps)
    if not (result.separated[0] and np.all(np.isfinite(result.force_n))):
        raise SimulationError(f"model {model.name}: non-finite state or no separation")
    return result


def sample_on(batch: BatchResult, times_s: np.ndarray, quantity: str = "force_n",
              before: float = 0.0, after: np.ndarray | float = 0.0) -> np.ndarray:
    """Linear interpolation of a batch quantity (B, n) at times (M,) or per run (B, M), with the
    value `before` at t < 0 and `after` (scalar or (B,)) beyond the grid: (B, M)."""
    values = getattr(batch, quantity)
    step = batch.time_s[1] - batch.time_s[0]
    times = np.broadcast_to(times_s, (values.shape[0], np.shape(times_s)[-1]))
    position = times / step
    index = np.clip(np.floor(position).astype(int), 0, values.shape[1] - 2)
    weight = np.clip(position - index, 0.0, 1.0)
    sampled = (np.take_along_axis(values, index, 1) * (1.0 - weight)
               + np.take_along_axis(values, index + 1, 1) * weight)
    sampled = np.where(times < 0, before, sampled)
    after = np.broadcast_to(np.asarray(after, dtype=float).reshape(-1, 1), sampled.shape)
    return np.where(times > batch.time_s[-1], after, sampled)


def simulate(
    model: str | LumpedModel,
    params: dict[str, float],
    *,
    impact_speed_m_s: float,
    mass_kg: float | None = None,
    rate_hz: float | None = None,
    steps_per_contact: int = STEPS_PER_CONTACT,
) -> ImpactRecord:
    """Simulate a normal impact on a rigid plane; contact starts at t = 0.

    `params` in SI (see the model's `units`; fixed parameters may be left out). The record is
    sampled at `rate_hz` (Hz), or on the integration grid, with zero force for a quarter of the
    contact time before and after contact; it carries the force, the centre-of-mass velocity
    (positive towards the surface), the mass, the impact speed and the rebound speed located at
    separation, and `metadata` with the model, its parameters and the exact contact time (s).
    """
    model = get_model(model)
    speed = check_positive("impact_speed_m_s", impact_speed_m_s)
    steps_per_contact = check_integer("steps_per_contact", steps_per_contact, 50)
    model.check(params, mass_kg)
    mass = model.ball_mass_kg(params, mass_kg)
    result = run_one(model, params, mass, speed, steps_per_contact)
    contact = float(result.contact_time_s[0])
    rebound = float(result.rebound_speed_m_s[0])
    margin = MARGIN_FRACTION * contact
    step = result.time_s[1] if rate_hz is None else 1.0 / check_positive("rate_hz", rate_hz)
    times = np.arange(-np.ceil(margin / step), np.ceil((contact + margin) / step) + 1) * step
    force = sample_on(result, times)[0]
    velocity = sample_on(result, times, "velocity_m_s", before=speed, after=-rebound)[0]
    return ImpactRecord(
        times, force, velocity_m_s=velocity, mass_kg=mass, impact_speed_m_s=speed,
        rebound_speed_m_s=max(rebound, 0.0),
        metadata={"source": "lumped", "model": model.name, "params": model.full(params),
                  "units": model.units, "contact_time_s": contact,
                  "reproduction": model.reproduction},
    )
