"""Assembly of element corner vectors into nodal vectors by gathers (no scatter), shared by the
axisymmetric and 3D elements: on a CPU, XLA's scatter-add is several times slower than gathering
each node's few contributions."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np


def corner_tables(elements: np.ndarray, n_nodes: int) -> tuple[np.ndarray, ...]:
    """Per corner a: (slots, n_nodes) the elements that have each node as corner a, padded with
    n_el (a zero appended to the values)."""
    tables = []
    for a in range(elements.shape[1]):
        counts = np.bincount(elements[:, a], minlength=n_nodes)
        table = np.full((max(counts.max(), 1), n_nodes), len(elements), dtype=np.int64)
        by_node = np.argsort(elements[:, a], kind="stable")
        slot = np.arange(len(elements)) - np.repeat(np.cumsum(counts) - counts, counts)
        table[slot, elements[by_node, a]] = by_node
        tables.append(table)
    return tuple(tables)


def gather_nodal(tables, f_e, n_components: int, dtype) -> jnp.ndarray:
    """Sum corner vectors f_e[c][a] (n_el,) to nodes: (n_components, n_nodes)."""
    zero = jnp.zeros(1, dtype)
    out = []
    for c in range(n_components):
        total = 0.0
        for a, table in enumerate(tables):
            padded = jnp.concatenate([f_e[c][a], zero])
            for slot in table:
                total = total + padded[slot]
        out.append(total)
    return jnp.stack(out)
