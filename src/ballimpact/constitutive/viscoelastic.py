"""Prony-series viscoelasticity, Simo's recursive update (docs/fe.md "Materials").

Each term i carries an overstress Q_i (second Piola-Kirchhoff) driven by the instantaneous elastic
stress S0 of the part it relaxes:  dQ_i/dt = (g_i S0 - Q_i) / tau_i,  S = S0 - sum_i Q_i.
Held at constant strain, S(t) = S0 g_R(t) with g_R = 1 - sum g_i (1 - exp(-t / tau_i)). Over a step
the update is exact when S0 varies linearly in time.
"""

from __future__ import annotations

import jax.numpy as jnp


def prony_update(q_old, s0_old, s0_new, g, tau_s, dt_s):
    """Overstresses after a step of dt_s seconds.

    q_old: (n_terms, ...) overstresses; s0_old, s0_new: (...) instantaneous stresses at the start
    and end of the step; g, tau_s: (n_terms,) Prony constants. Returns (n_terms, ...).
    """
    shape = (-1,) + (1,) * s0_new.ndim
    x = (dt_s / tau_s).reshape(shape)
    decay = jnp.exp(-x)
    ramp = -jnp.expm1(-x) / x  # (1 - exp(-x)) / x, accurate for small x
    gg = g.reshape(shape)
    return decay * q_old + gg * ((ramp - decay) * s0_old + (1.0 - ramp) * s0_new)


def relaxation_function(t_s, g, tau_s):
    """g_R(t) = 1 - sum g_i (1 - exp(-t / tau_i)) for an array of times (s)."""
    t = jnp.asarray(t_s)[..., None]
    return 1.0 - jnp.sum(g * -jnp.expm1(-t / tau_s), axis=-1)
