"""The axisymmetric mesh of a layered target under the ball: a flat disc (a pad, a plate) or a
spherical cap (a helmet's shell and liner), layers from the top down, quadrilaterals in (r, z).

Radially the cells start at the ball's pole element size on the axis and grow by `GROWTH` a cell
outward to the target's half-width (arc length on a cap); through each layer `cells_through`
cells of equal depth. A cap of outer radius R_c is the flat layout bent onto concentric spheres:
the node at arc length s and depth d sits at radius R_c - d and polar angle s / R_c about the
cap's centre, (0, -R_c) below the top; its layers are concentric shells.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: the radial cells grow by this a cell from the axis outward
GROWTH = 1.15
#: cells through a layer: its thickness over twice the pole element, within these bounds
MIN_CELLS_THROUGH, MAX_CELLS_THROUGH = 2, 12


@dataclass(frozen=True)
class TargetMesh:
    """Nodes (n, 2) (r, z) with the top surface's axis point at z = 0, elements (n_el, 4)
    counter-clockwise, each element's target layer, the top surface's nodes from the axis out,
    the base's nodes, and per layer the axis nodes at its top and bottom."""

    nodes_m: np.ndarray
    elements: np.ndarray
    element_layer: np.ndarray
    top_nodes: np.ndarray
    base_nodes: np.ndarray
    axis_layer_nodes: np.ndarray  # (n_layers, 2): top and bottom node on the axis
    thicknesses_m: tuple[float, ...]


def radial_lines(half_width_m: float, first_m: float, growth: float = GROWTH) -> np.ndarray:
    """Node positions from 0 to `half_width_m` (m): cells of `first_m` growing by `growth`, the
    last stretched to end at the half-width (or merged when shorter than half a cell)."""
    lines, size = [0.0], first_m
    while lines[-1] + size < half_width_m:
        lines.append(lines[-1] + size)
        size *= growth
    if half_width_m - lines[-1] < 0.5 * size / growth and len(lines) > 2:
        lines.pop()
    lines.append(half_width_m)
    return np.asarray(lines)


def cells_through(thickness_m: float, pole_m: float) -> int:
    return int(np.clip(math.ceil(thickness_m / (2.0 * pole_m)), MIN_CELLS_THROUGH,
                       MAX_CELLS_THROUGH))


def target_mesh(thicknesses_m, half_width_m: float, pole_m: float,
                sphere_radius_m: float | None = None) -> TargetMesh:
    """The mesh of layers `thicknesses_m` (top down, m), `half_width_m` wide (an arc length on a
    cap of outer radius `sphere_radius_m`, None: flat), cells from `pole_m` on the axis."""
    r = radial_lines(half_width_m, pole_m)
    depths, layer_of_cell = [0.0], []
    for i, t in enumerate(thicknesses_m):
        n = cells_through(t, pole_m)
        depths.extend(depths[-1] + t * np.arange(1, n + 1) / n)
        layer_of_cell += [i] * n
    d = np.asarray(depths)
    nr, nd = r.size, d.size
    s, depth = np.meshgrid(r, d)  # (nd, nr): row k at depth d[k]
    if sphere_radius_m is None:
        x, z = s, -depth
    else:
        rho, phi = sphere_radius_m - depth, s / sphere_radius_m
        x, z = rho * np.sin(phi), rho * np.cos(phi) - sphere_radius_m
    x[:, 0] = 0.0  # exactly on the axis
    nodes = np.stack([x.ravel(), z.ravel()], axis=1)
    ids = np.arange(nr * nd).reshape(nd, nr)
    # cell (k, i): bottom-left, bottom-right, top-right, top-left (counter-clockwise in (r, z))
    elements = np.stack([ids[1:, :-1], ids[1:, 1:], ids[:-1, 1:], ids[:-1, :-1]],
                        axis=-1).reshape(-1, 4)
    element_layer = np.repeat(np.asarray(layer_of_cell), nr - 1)
    bounds = np.concatenate([[0], np.cumsum([cells_through(t, pole_m)
                                             for t in thicknesses_m])])
    axis = np.stack([ids[bounds[:-1], 0], ids[bounds[1:], 0]], axis=1)
    return TargetMesh(nodes, elements, element_layer, ids[0].copy(), ids[-1].copy(), axis,
                      tuple(float(t) for t in thicknesses_m))
