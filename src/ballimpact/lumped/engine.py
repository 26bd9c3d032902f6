"""Batched integration of lumped ball models with JAX: fixed-step RK4, separation located exactly.

A model is one or more *units*, each a mass on the rigid plane with its own contact law (the
three-element model has three, the others one). A unit's state is (y, y', internal...) with y the
compression (m), positive into the surface. Each unit leaves the surface when its contact force
returns to zero, which is when the ball physically loses contact; models whose force can turn
tensile (a linear damper pulls while the spring still holds) therefore end contact *before* y
returns to zero. (The thesis' appendix code and the classic Kelvin-Voigt solution end contact at
y = 0 instead; see `thesis` and `kelvin_voigt`.)

After a unit separates it flies freely at its separation velocity and adds no force. The step in
which the force changes sign is refined by bisection on the RK4 step length, so contact time and
rebound speed carry the integrator's accuracy, not the grid's.

Everything here is a pure function jitted per (model, steps, batch size); runs use float64
(`jax.enable_x64`) without changing JAX's global configuration.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np

from .base import BatchResult, LumpedModel, Parameter, Scale

#: bisection iterations locating the separation inside one step (2^-48 of a step)
SEPARATION_BISECTIONS = 48


def signed_power(y, exponent):
    """sign(y) |y|^exponent: a power law that stays smooth in sign through y = 0, so that the
    force of an undamped spring changes sign exactly where y does."""
    return jnp.sign(y) * jnp.abs(y) ** exponent


@dataclass(frozen=True, eq=False)
class OdeModel(LumpedModel):
    """A lumped model given by its unit contact law.

    - `split(p, ball_mass)`: the parameter vector (P,) -> per-unit law parameters (U, Q) and unit
      masses (U,) in kg;
    - `force(q, state)`: contact force (N) of a unit with law parameters q;
    - `internal_rate(q, state)`: d/dt of the internal states (models with `state_size` > 2).
    """

    name: str
    summary: str
    parameters: tuple[Parameter, ...]
    bounds: Callable[[Scale], dict[str, tuple[float, float]]]
    split: Callable
    force: Callable
    state_size: int = 2
    internal_rate: Callable | None = None
    validate: Callable[[dict[str, float]], None] | None = None
    reproduction: bool = False

    def default_bounds(self, scale: Scale) -> dict[str, tuple[float, float]]:
        return self.bounds(scale)

    def check(self, params, mass_kg):
        super().check(params, mass_kg)
        if self.validate is not None:
            self.validate(self.full(params))

    def run_batch(self, params, mass_kg, impact_speed_m_s, step_s, steps) -> BatchResult:
        params = np.atleast_2d(np.asarray(params, dtype=float))
        count = params.shape[0]
        padded = _pad_to_bucket(params)
        with jax.enable_x64(True):
            out = _run(self, int(steps), jnp.asarray(padded), float(mass_kg),
                       float(impact_speed_m_s), float(step_s))
            force, velocity, contact, rebound, separated = (np.asarray(a)[:count] for a in out)
        time = np.arange(steps + 1) * step_s
        return BatchResult(time, force, velocity, contact, rebound, separated)


def _pad_to_bucket(params: np.ndarray) -> np.ndarray:
    """Pad the batch to a power of two up to 16, then to a multiple of 16, so that a few compiled
    shapes serve every call."""
    count = params.shape[0]
    bucket = 1 << max(0, (count - 1).bit_length()) if count <= 16 else -(-count // 16) * 16
    if bucket == count:
        return params
    return np.concatenate([params, np.repeat(params[:1], bucket - count, axis=0)])


def _rk4_step(model: OdeModel, q, mass, state, h):
    def rate(s):
        acceleration = -model.force(q, s) / mass
        derivative = [s[1], acceleration]
        if model.internal_rate is not None:
            derivative.append(jnp.atleast_1d(model.internal_rate(q, s)))
        return jnp.concatenate([jnp.atleast_1d(d) for d in derivative])

    k1 = rate(state)
    k2 = rate(state + 0.5 * h * k1)
    k3 = rate(state + 0.5 * h * k2)
    k4 = rate(state + h * k3)
    return state + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def _run_unit(model: OdeModel, steps: int, q, mass, speed, h):
    """One unit from first contact: force and velocity on the grid, separation time and velocity."""
    start = jnp.zeros(model.state_size).at[1].set(speed)

    def advance(carry, index):
        state, done, before, before_index = carry
        new = _rk4_step(model, q, mass, state, h)
        new_force = model.force(q, new)
        leaving = (~done) & (new_force <= 0.0)
        before = jnp.where(leaving, state, before)
        before_index = jnp.where(leaving, index, before_index)
        # max(F, 0) at the first point past separation keeps the sampled force continuous in the
        # parameters (a fit's finite differences see no jump when separation crosses a grid point)
        force = jnp.where(done, 0.0, jnp.maximum(new_force, 0.0))
        done_now = done | leaving
        new = jnp.where(done_now, state, new)
        return (new, done_now, before, before_index), (force, new[1])

    carry = (start, jnp.asarray(False), start, jnp.asarray(0))
    (_, done, before, before_index), (force, velocity) = jax.lax.scan(
        advance, carry, jnp.arange(steps))
    force = jnp.concatenate([jnp.atleast_1d(model.force(q, start)), force])
    velocity = jnp.concatenate([jnp.atleast_1d(speed), velocity])

    def bisect(_, bracket):
        low, high = bracket
        middle = 0.5 * (low + high)
        inside = model.force(q, _rk4_step(model, q, mass, before, middle * h)) > 0.0
        return jnp.where(inside, middle, low), jnp.where(inside, high, middle)

    _, fraction = jax.lax.fori_loop(0, SEPARATION_BISECTIONS, bisect, (0.0, 1.0))
    contact = (before_index + fraction) * h
    leave_velocity = _rk4_step(model, q, mass, before, fraction * h)[1]
    time = jnp.arange(steps + 1) * h
    velocity = jnp.where(done & (time > contact), leave_velocity, velocity)
    nan = jnp.nan
    return (force, velocity, jnp.where(done, contact, nan), jnp.where(done, leave_velocity, nan),
            done)


@partial(jax.jit, static_argnums=(0, 1))
def _run(model: OdeModel, steps: int, params, mass, speed, h):
    def one(p):
        q, masses = model.split(p, mass)
        force, velocity, contact, leave_velocity, done = jax.vmap(
            lambda qu, mu: _run_unit(model, steps, qu, mu, speed, h))(q, masses)
        total = jnp.sum(masses)
        return (jnp.sum(force, axis=0),
                jnp.sum(masses[:, None] * velocity, axis=0) / total,
                jnp.max(contact),
                -jnp.sum(masses * leave_velocity) / total,
                jnp.all(done))

    return jax.vmap(one)(params)
