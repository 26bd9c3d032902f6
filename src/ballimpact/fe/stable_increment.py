"""The stable time increment of the assembled system (pure JAX, vmappable).

Central difference is stable for dt <= 2 / omega_max, omega_max^2 the largest eigenvalue of
M^-1 K. Element-by-element estimates (L_e / c_d) bound it from below and are pessimistic for
distorted elements; here omega_max^2 is found from the assembled stiffness by Lanczos iteration on
the symmetric M^-1/2 K M^-1/2, with K applied as a Jacobian-vector product of the internal forces.
The largest Ritz value approaches omega_max^2 from below, so the estimate adds the residual bound
|beta_m s_m| (an eigenvalue lies within it of the Ritz value), which makes it safe once the Ritz
value has settled on the top of the spectrum.

The ball stiffens as it is compressed (omega_max^2 grew 1.06x in the universal ball at 25 m/s and
1.68x in the 3-layer ball at 45 m/s), so the solver re-estimates omega_max at the current state
before every chunk of steps, with a few Lanczos steps started from the previous top Ritz vector,
and shrinks the increment when needed (it never grows back during a run).
"""

from __future__ import annotations

import math
from functools import partial

import jax
import jax.numpy as jnp


def lanczos_largest(apply, x0: jax.Array, steps: int, first_steps: int | None = None,
                    first=None) -> tuple[jax.Array, jax.Array, jax.Array]:
    """Largest Ritz value of the symmetric operator `apply` after `steps` Lanczos steps (full
    reorthogonalisation) from the start vector x0 (flat), its residual bound and its Ritz vector
    (a good start vector for the next estimate).

    With `first_steps` and a traced boolean `first`: `first_steps` steps where `first` holds,
    `steps` elsewhere, in one loop, so that the operator (a Jacobian-vector product of the
    internal forces, most of a kernel's compilation) is compiled once for the start estimate
    and the refreshes."""
    n = x0.shape[0]
    size = steps if first_steps is None else first_steps
    basis = jnp.zeros((size, n), x0.dtype)
    alpha = jnp.zeros(size, x0.dtype)
    beta = jnp.zeros(size, x0.dtype)

    def orthogonalized(w, basis, rows):
        return w - basis[:rows].T @ (basis[:rows] @ w)  # rows not yet filled are zero

    def ritz(alpha, beta, basis, rows):
        alpha, beta, basis = alpha[:rows], beta[:rows], basis[:rows]
        tridiagonal = jnp.diag(alpha) + jnp.diag(beta[:-1], 1) + jnp.diag(beta[:-1], -1)
        values, vectors = jnp.linalg.eigh(tridiagonal)
        return values[-1], jnp.abs(beta[-1] * vectors[-1, -1]), basis.T @ vectors[:, -1]

    def body(j, carry):
        basis, alpha, beta, v, v_prev, b = carry
        basis = basis.at[j].set(v)
        w = apply(v) - b * v_prev
        a = jnp.vdot(w, v)
        w = w - a * v
        if first_steps is None:
            w = orthogonalized(w, basis, steps)
        else:
            w = jax.lax.cond(first, partial(orthogonalized, rows=first_steps),
                             partial(orthogonalized, rows=steps), w, basis)
        b_new = jnp.linalg.norm(w)
        v_new = w / jnp.where(b_new > 0, b_new, 1.0)
        return basis, alpha.at[j].set(a), beta.at[j].set(b_new), v_new, v, b_new

    v0 = x0 / jnp.linalg.norm(x0)
    carry = (basis, alpha, beta, v0, jnp.zeros_like(v0), jnp.zeros((), x0.dtype))
    if first_steps is None:
        basis, alpha, beta, *_ = jax.lax.fori_loop(0, steps, body, carry)
        return ritz(alpha, beta, basis, steps)
    count = jnp.where(first, first_steps, steps)
    basis, alpha, beta, *_ = jax.lax.fori_loop(0, count, body, carry)
    return jax.lax.cond(first, partial(ritz, rows=first_steps), partial(ritz, rows=steps),
                        alpha, beta, basis)


#: the increment shrinks in steps of 2^(-1/INCREMENT_LEVELS) below its start value
INCREMENT_LEVELS = 32
#: a re-estimate this close to a level (in levels: 2e-6 in omega_max) counts as on it: at the
#: undeformed state the refresh equals the start estimate up to round-off, which must not decide
#: whether the increment shrinks (it did in one of two similar balls: tests/universal/test_similarity.py)
LEVEL_ROUNDOFF = 1e-4


def shrunk_increment(dt, dt0, omega2, factor):
    """The increment for the next chunk: factor / omega_max rounded down to a level 2^(-k/32) of
    the start value dt0 (so that round-off in the estimate, vmapped or not, does not change it),
    and never larger than the current dt."""
    level = jnp.ceil(INCREMENT_LEVELS * jnp.log2(dt0 * jnp.sqrt(omega2) / factor)
                     - LEVEL_ROUNDOFF)
    return jnp.minimum(dt, dt0 * jnp.exp2(-level / INCREMENT_LEVELS))


def alternating_start(mask: jax.Array, dtype) -> jax.Array:
    """A fixed Lanczos start vector (flat) for the free entries of `mask` (n_components, n):
    random magnitudes with signs alternating between nodes, which weights the top of the
    spectrum (neighbours out of phase)."""
    start = mask * jax.random.uniform(jax.random.PRNGKey(0), mask.shape, dtype, 0.5, 1.5)
    return (start * jnp.where(jnp.arange(mask.shape[1]) % 2 == 0, 1.0, -1.0)).reshape(-1)


def increment_factor(time_step_scale: float, bulk_viscosity_linear: float) -> float:
    """f in dt = f / omega_max: 2 x scale x (sqrt(1 + xi^2) - xi), xi the linear bulk
    viscosity's fraction of critical damping in the highest mode (as ABAQUS/Explicit)."""
    xi = bulk_viscosity_linear
    return 2.0 * time_step_scale * (math.sqrt(1.0 + xi * xi) - xi)
