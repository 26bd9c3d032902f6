"""tr(C^p) = sum_a lambda_a^p of a general symmetric 3x3 C (3D hyperfoam), with derivatives that
stay finite at equal eigenvalues.

Differentiating an eigendecomposition is singular where eigenvalues coincide (the undeformed
state), so both the function and its gradient p C^(p-1) carry their own derivative rules: the
gradient of a trace function is the matrix function f'(C) (finite at any spectrum), and the
derivative of a matrix function is the Daleckii-Krein formula, whose divided differences of f'
become f'' at (near) equal eigenvalues. The eigendecomposition itself is never differentiated.
Components are (xx, yy, zz, xy, yz, zx), each an array of any shape.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

#: relative eigenvalue gap below which the divided difference is replaced by the derivative
_CLOSE = 1e-6


def _matrix(c):
    xx, yy, zz, xy, yz, zx = c
    return jnp.stack([jnp.stack([xx, xy, zx], -1), jnp.stack([xy, yy, yz], -1),
                      jnp.stack([zx, yz, zz], -1)], -2)


def _components(m):
    return (m[..., 0, 0], m[..., 1, 1], m[..., 2, 2], m[..., 0, 1], m[..., 1, 2], m[..., 2, 0])


def _contract(g, dc):
    """sum_ij G_ij dC_ij for symmetric matrices given by components."""
    return (g[0] * dc[0] + g[1] * dc[1] + g[2] * dc[2]
            + 2.0 * (g[3] * dc[3] + g[4] * dc[4] + g[5] * dc[5]))


def _power(x, p):
    return jnp.exp(p * jnp.log(x))


@jax.custom_jvp
def trace_power(c, p):
    """sum_a lambda_a^p of C (components c), p a scalar."""
    return jnp.sum(_power(jnp.linalg.eigvalsh(_matrix(c)), p), axis=-1)


@trace_power.defjvp
def _trace_power_jvp(primals, tangents):
    c, p = primals
    dc, dp = tangents
    lam = jnp.linalg.eigvalsh(_matrix(c))
    value = jnp.sum(_power(lam, p), axis=-1)
    by_p = jnp.sum(_power(lam, p) * jnp.log(lam), axis=-1)
    return value, _contract(power_gradient(c, p), dc) + by_p * dp


@jax.custom_jvp
def power_gradient(c, p):
    """d tr(C^p) / dC = p C^(p-1), as components."""
    lam, vec = jnp.linalg.eigh(_matrix(c))
    f1 = p * _power(lam, p - 1.0)
    return _components(jnp.einsum("...ia,...a,...ja->...ij", vec, f1, vec))


@power_gradient.defjvp
def _power_gradient_jvp(primals, tangents):
    c, p = primals
    dc, dp = tangents
    lam, vec = jnp.linalg.eigh(_matrix(c))
    f1 = p * _power(lam, p - 1.0)
    value = _components(jnp.einsum("...ia,...a,...ja->...ij", vec, f1, vec))
    li, lj = lam[..., :, None], lam[..., None, :]
    gap = li - lj
    close = jnp.abs(gap) <= _CLOSE * jnp.maximum(li, lj)
    mid = 0.5 * (li + lj)
    f2_mid = p * (p - 1.0) * _power(mid, p - 2.0)
    fi, fj = f1[..., :, None], f1[..., None, :]
    divided = jnp.where(close, f2_mid, (fi - fj) / jnp.where(close, 1.0, gap))
    rotated = jnp.einsum("...ia,...ij,...jb->...ab", vec, _matrix(dc), vec)
    d_f1_dp = _power(lam, p - 1.0) * (1.0 + p * jnp.log(lam))
    inner = divided * rotated + jnp.einsum("...a,ab->...ab", d_f1_dp * dp, jnp.eye(3))
    tangent = _components(jnp.einsum("...ia,...ab,...jb->...ij", vec, inner, vec))
    return value, tangent
