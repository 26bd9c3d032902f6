"""Deep ensembles of Gaussian multilayer perceptrons (equinox + optax).

Each member maps standardised inputs to a mean and a log standard deviation per output and is
trained on the Gaussian negative log-likelihood (Lakshminarayanan et al. 2017, "Simple and
scalable predictive uncertainty estimation using deep ensembles"). Members differ in their
initial weights and minibatch order; they are vmapped, so an ensemble trains as one program.
The prediction is the members' mixture: its mean, and its variance (the members' own variances
plus their disagreement). Early stopping keeps each member's weights at its best validation loss.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optax

from ..progress import end_line, redraw_line

LOG_SIGMA_RANGE = (-7.0, 3.0)


@dataclass(frozen=True)
class Architecture:
    n_in: int
    n_out: int
    width: int = 128
    depth: int = 3
    members: int = 5

    def to_dict(self) -> dict:
        return dict(self.__dict__)


def make_ensemble(arch: Architecture, seed: int):
    keys = jax.random.split(jax.random.PRNGKey(seed), arch.members)

    def member(key):
        return eqx.nn.MLP(arch.n_in, 2 * arch.n_out, arch.width, arch.depth,
                          activation=jax.nn.silu, key=key)

    return eqx.filter_vmap(member)(keys)


def _member_outputs(member, x):
    out = jax.vmap(member)(x)
    mean, log_sigma = jnp.split(out, 2, axis=-1)
    return mean, jnp.clip(log_sigma, *LOG_SIGMA_RANGE)


def member_outputs(ensemble, x):
    """(means, log sigmas) of every member: arrays (members, n, n_out)."""
    return eqx.filter_vmap(_member_outputs, in_axes=(eqx.if_array(0), None))(ensemble, x)


@eqx.filter_jit
def predict(ensemble, x):
    """Mixture mean and standard deviation of the ensemble at standardised inputs x (n, n_in)."""
    means, log_sigmas = member_outputs(ensemble, x)
    mean = means.mean(axis=0)
    variance = (jnp.exp(2 * log_sigmas) + means ** 2).mean(axis=0) - mean ** 2
    return mean, jnp.sqrt(jnp.maximum(variance, 0.0))


def _nll(member, x, y):
    mean, log_sigma = _member_outputs(member, x)
    return jnp.mean(0.5 * ((y - mean) * jnp.exp(-log_sigma)) ** 2 + log_sigma)


def train_ensemble(arch: Architecture, x_train, y_train, x_val, y_val, *, seed: int = 0,
                   steps: int = 4000, batch: int = 256, learning_rate: float = 3e-3,
                   check_every: int = 100, label: str = "ensemble"):
    """Train an ensemble; returns (best ensemble, figures). Inputs and targets standardised."""
    x_train, y_train, x_val, y_val = (jnp.asarray(a, jnp.float32)
                                      for a in (x_train, y_train, x_val, y_val))
    ensemble = make_ensemble(arch, seed)
    schedule = optax.cosine_decay_schedule(learning_rate, steps, alpha=0.02)
    optimiser = optax.adamw(schedule, weight_decay=1e-5)
    params, static = eqx.partition(ensemble, eqx.is_array)
    opt_state = jax.vmap(optimiser.init)(params)
    n = x_train.shape[0]
    batch = min(batch, n)

    # `static` (activations, sizes) holds no arrays: it completes one member's parameters too
    def member_step(p, state, key):
        idx = jax.random.choice(key, n, (batch,), replace=False)
        loss, grads = jax.value_and_grad(
            lambda q: _nll(eqx.combine(q, static), x_train[idx], y_train[idx]))(p)
        updates, state = optimiser.update(grads, state, p)
        return optax.apply_updates(p, updates), state, loss

    @jax.jit
    def run(p, state, keys):
        def body(carry, step_keys):
            p, state = carry
            p, state, loss = jax.vmap(member_step)(p, state, step_keys)
            return (p, state), loss
        (p, state), losses = jax.lax.scan(body, (p, state), keys)
        return p, state, losses[-1]

    @jax.jit
    def validation_loss(p):
        return jax.vmap(lambda q: _nll(eqx.combine(q, static), x_val, y_val))(p)

    key = jax.random.PRNGKey(seed + 1)
    best_params, best_loss = params, validation_loss(params)
    best_step = np.zeros(arch.members, dtype=int)
    for start in range(0, steps, check_every):
        key, sub = jax.random.split(key)
        keys = jax.random.split(sub, check_every * arch.members).reshape(
            check_every, arch.members, 2)
        params, opt_state, train_loss = run(params, opt_state, keys)
        loss = validation_loss(params)
        better = loss < best_loss
        best_params = jax.tree_util.tree_map(
            lambda new, old: jnp.where(better.reshape((-1,) + (1,) * (new.ndim - 1)), new, old),
            params, best_params)
        best_loss = jnp.where(better, loss, best_loss)
        best_step = np.where(np.asarray(better), start + check_every, best_step)
        redraw_line(f"{label}: step {start + check_every}/{steps}, train NLL "
                    f"{float(train_loss.mean()):.3f}, validation NLL {float(loss.mean()):.3f}   ")
    end_line()
    figures = {"validation_nll": [float(v) for v in best_loss], "best_step": best_step.tolist(),
               "steps": steps, "train_rows": int(n), "validation_rows": int(x_val.shape[0])}
    return eqx.combine(best_params, static), figures


def leaves(ensemble) -> list[np.ndarray]:
    """The ensemble's arrays, in a fixed order (for NPZ files)."""
    return [np.asarray(a) for a in jax.tree_util.tree_leaves(eqx.filter(ensemble, eqx.is_array))]


def leaf_shapes(arch: Architecture) -> list[tuple[int, ...]]:
    """The shapes `leaves` gives for an ensemble of `arch`, without building one: per layer of
    each member's MLP (`depth` hidden layers), its weight (out, in) then its bias (out,), the
    members stacked first. For checking a model file before anything is built from it."""
    m, w = arch.members, arch.width
    sizes = [arch.n_in] + [w] * arch.depth + [2 * arch.n_out]  # mean and log sigma per output
    shapes: list[tuple[int, ...]] = []
    for n_in, n_out in zip(sizes[:-1], sizes[1:]):
        shapes += [(m, n_out, n_in), (m, n_out)]
    return shapes


def from_leaves(arch: Architecture, arrays: list[np.ndarray]):
    """Rebuild an ensemble of architecture `arch` from `leaves` (shapes checked)."""
    # the structure only, traced abstractly: building it for real ran the random initialisers
    # (33 small programs compiled, 3.3 s of every `identify` on 2 cores)
    skeleton = eqx.filter_eval_shape(make_ensemble, arch, 0)
    params, static = eqx.partition(skeleton, lambda leaf: isinstance(leaf, jax.ShapeDtypeStruct))
    flat, treedef = jax.tree_util.tree_flatten(params)
    if len(flat) != len(arrays) or any(a.shape != b.shape for a, b in zip(flat, arrays)):
        raise ValueError("the stored weights do not match the stored architecture")
    params = jax.tree_util.tree_unflatten(treedef, [jnp.asarray(a) for a in arrays])
    return eqx.combine(params, static)


def gaussian_interval_scale(level: float) -> float:
    """z of a two-sided Gaussian interval at `level` (0.9 -> 1.645)."""
    from statistics import NormalDist  # not scipy.stats: its import is 0.5 s of `identify`

    return NormalDist().inv_cdf(0.5 + level / 2) if 0 < level < 1 else math.inf
