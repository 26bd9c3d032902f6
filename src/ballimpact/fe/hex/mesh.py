"""Hexahedral meshes for the 3D solver (NumPy only): a layered ball (an O-grid: a cube inside six
cubed-sphere blocks) and a flat target slab.

Ball layout. Directions come from the equiangular cubed sphere: on the face of axis k and sign s,
the ray through the angles (g_i, g_j) points along c = (tan g_i, tan g_j, s) (components in the
order k+1, k+2, k). The central cube of half side a is a uniform grid (its cells would otherwise be
the smallest of the mesh and set the stable increment). Each block holds levels of nodes: level 0
on the cube face, a (2i/n - 1, 2j/n - 1, s), then levels interpolated in space between that point
and the point r_b c/|c| on the sphere of radius r_b, then spheres at radii that include every
layer radius, so layers share their interface nodes.
The angles g crowd toward 0 (a geometric grading, `pole_grading` = largest over smallest spacing)
so the contact region around the south pole (0, 0, -R) is finer; radial spacing shrinks toward the
surface. The ball is placed with its south pole on z = 0.

The half model keeps the elements with y > 0 (the plane of incidence is x-z); its nodes on y = 0
carry the symmetry condition v_y = 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...errors import InputError
from ...checks import check_integer, check_range

#: corner signs of the reference hexahedron, VTK order (bottom face, then top face)
HEX_CORNERS = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)

#: the cube's half side over the blend radius r_b: its corners sit at 0.78 r_b
CUBE_FRACTION = 0.45
#: the blend radius r_b over the innermost layer radius and over the outer radius (the smaller)
BLEND_OF_INNERMOST, BLEND_OF_OUTER = 0.9, 0.7
BLEND_LEVELS = 3
#: radial growth of the shell thickness inward from the surface
RADIAL_GROWTH = 1.15
#: the pole grading's range (largest over smallest arc spacing)
GRADING_RANGE = (1.0, 40.0)


@dataclass(frozen=True)
class HexMesh:
    """8-node hexahedra (VTK corner order) with a group per element (ball layers, then target
    layers), in metres."""

    nodes_m: np.ndarray            # (n_nodes, 3)
    elements: np.ndarray           # (n_el, 8)
    element_group: np.ndarray      # (n_el,) index into the groups (ball layers first)
    ball_nodes: np.ndarray         # bool (n_nodes,): the node belongs to the ball
    contact_nodes: np.ndarray      # ball surface nodes (indices)
    symmetry_nodes: np.ndarray     # nodes on y = 0 of a half model (indices; empty if full)
    fixed_nodes: np.ndarray = field(default_factory=lambda: np.zeros(0, int))  # target base
    half: bool = False
    outer_radius_m: float = 0.0
    target: dict | None = None     # structured slab data for contact (see `slab_mesh`)

    @property
    def n_elements(self) -> int:
        return len(self.elements)


def estimate_ball_mesh(layer_radii_m, divisions: int = 16, pole_grading: float = 2.0,
                       half: bool = True) -> tuple[int, float]:
    """(elements, about the smallest element's length in m) of `ball_mesh` with these arguments,
    from its counting rules alone (no node is built): the count is exact (the cube's d^3 and six
    blocks of d^2 per level, halved for a half model); the length is on the small side (0.55 of
    the smaller of the surface shell and the cube's cell: 0.6-1.0 of the real one)."""
    radii = np.asarray(layer_radii_m, dtype=float)
    g = _graded_angles(divisions, pole_grading)
    surface = pole_spacing_m(radii[-1], divisions, pole_grading)
    r_blend = min(BLEND_OF_INNERMOST * radii[0], BLEND_OF_OUTER * radii[-1])
    levels = BLEND_LEVELS + len(_radial_levels(radii, r_blend, surface, np.max(np.diff(g))))
    elements = divisions ** 3 + 6 * divisions ** 2 * (levels - 1)
    cube_cell = 2.0 * CUBE_FRACTION * r_blend / divisions
    return (elements // 2 if half else elements), 0.55 * min(surface, cube_cell)


def pole_spacing_m(outer_radius_m: float, divisions: int, pole_grading: float) -> float:
    """Arc spacing (m) of `ball_mesh`'s elements at the contact pole (also its surface shells'
    default thickness)."""
    g = _graded_angles(divisions, pole_grading)
    return outer_radius_m * float(g[divisions // 2 + 1] - g[divisions // 2])


def pole_cell_growth(divisions: int, pole_grading: float) -> float:
    """How much each of `ball_mesh`'s cells is longer than the next toward the pole."""
    return pole_grading ** (1.0 / max(divisions // 2 - 1, 1))


def _graded_angles(n: int, grading: float) -> np.ndarray:
    """n + 1 angles over [-pi/4, pi/4], symmetric, spacing growing geometrically from 0 outward
    with largest / smallest = `grading` (n even)."""
    half = n // 2
    steps = pole_cell_growth(n, grading) ** np.arange(half)
    edges = np.concatenate([[0.0], np.cumsum(steps)]) / steps.sum() * (math.pi / 4)
    return np.concatenate([-edges[:0:-1], edges])


def _growing_cells(span: float, cell: float, growth: float, cap, min_cells: int = 1):
    """Cells filling `span` (m): the first `cell` thick, each next `growth` times the one before
    and at most `cap(covered)` (covered: the span filled so far), at least `min_cells`, all
    scaled to fill it exactly (a last cell under half the one before is dropped and its share
    spread over the others). Returns the cells (m) and the size the next cell would have."""
    steps = []
    while sum(steps) < span - 1e-9 or len(steps) < min_cells:
        steps.append(min(cell, cap(sum(steps))))
        cell *= growth
    if len(steps) > min_cells and steps[-1] < 0.5 * steps[-2]:
        steps = steps[:-1]
    return np.array(steps) * span / sum(steps), cell


def _radial_levels(radii: np.ndarray, r_blend: float, surface_thickness: float,
                   max_angle: float) -> np.ndarray:
    """Sphere radii from r_blend to the outer radius, including every layer radius: thickness
    `surface_thickness` at the outer surface growing by RADIAL_GROWTH inward, at most the
    largest arc spacing (r x max_angle)."""
    levels = [radii[-1]]
    thickness = surface_thickness
    r = radii[-1]
    for bound in [*radii[::-1][1:], r_blend]:
        cells, thickness = _growing_cells(r - bound, thickness, RADIAL_GROWTH,
                                          lambda covered, r=r: (r - covered) * max_angle)
        levels.extend(r - np.cumsum(cells))
        r = bound
    return np.array(levels[::-1])


def _hexes(ids: np.ndarray) -> np.ndarray:
    """Hexahedra of a structured block of node ids (ni, nj, nk)."""
    a = ids[:-1, :-1, :-1]
    b = ids[1:, :-1, :-1]
    c = ids[1:, 1:, :-1]
    d = ids[:-1, 1:, :-1]
    return np.stack([a, b, c, d, ids[:-1, :-1, 1:], ids[1:, :-1, 1:], ids[1:, 1:, 1:],
                     ids[:-1, 1:, 1:]], axis=-1).reshape(-1, 8)


def centre_jacobian_det(nodes: np.ndarray, elements: np.ndarray) -> np.ndarray:
    """det(dX/dxi) at the element centres."""
    xe = nodes[elements]                                  # (n_el, 8, 3)
    jac = np.einsum("ak,ead->edk", HEX_CORNERS / 8.0, xe)
    return np.linalg.det(jac)


def _oriented(nodes: np.ndarray, elements: np.ndarray) -> np.ndarray:
    flip = centre_jacobian_det(nodes, elements) < 0
    elements = elements.copy()
    elements[flip] = elements[flip][:, [4, 5, 6, 7, 0, 1, 2, 3]]
    return elements


def _morton_order(points: np.ndarray) -> np.ndarray:
    """Indices that sort points along a Z-order curve (10 bits an axis): neighbours in space end
    up close in memory, which keeps the step's gathers in cache."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    cells = np.clip(((points - lo) / np.maximum(hi - lo, 1e-300) * 1023).astype(np.int64), 0, 1023)
    code = np.zeros(len(points), np.int64)
    for bit in range(10):
        for axis in range(3):
            code |= ((cells[:, axis] >> bit) & 1) << (3 * bit + axis)
    return np.argsort(code, kind="stable")


def _spatially_ordered(nodes: np.ndarray, elements: np.ndarray):
    """Nodes and elements renumbered along a Z-order curve."""
    order = _morton_order(nodes)
    renumber = np.empty(len(nodes), np.int64)
    renumber[order] = np.arange(len(nodes))
    elements = renumber[elements]
    return nodes[order], elements[_morton_order(nodes[order][elements].mean(axis=1))]


def _merge(nodes: np.ndarray, elements: np.ndarray, scale: float):
    key = np.round(nodes / (scale * 1e-9)).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    return nodes[first], inverse.reshape(-1)[elements]


def ball_mesh(layer_radii_m, divisions: int = 16, pole_grading: float = 2.0,
              surface_thickness_m: float | None = None, half: bool = True) -> HexMesh:
    """A layered ball of hexahedra: `divisions` elements along each cube edge (90 degrees of
    arc; even), angular spacing graded toward the poles by `pole_grading` (>= 1), shells of
    `surface_thickness_m` at the surface (default: the smallest arc spacing there)."""
    radii = np.asarray(layer_radii_m, dtype=float)
    divisions = check_integer("divisions", divisions, 4, even=True)
    check_range("pole_grading", pole_grading, *GRADING_RANGE)
    outer = radii[-1]
    g = _graded_angles(divisions, pole_grading)
    t = np.tan(g)
    if surface_thickness_m is None:
        surface_thickness_m = pole_spacing_m(outer, divisions, pole_grading)
    check_range("surface_thickness_m", surface_thickness_m, 0.0, 0.5 * outer, low_open=True,
                high_open=True)
    r_blend = min(BLEND_OF_INNERMOST * radii[0], BLEND_OF_OUTER * outer)
    a = CUBE_FRACTION * r_blend
    spheres = _radial_levels(radii, r_blend, surface_thickness_m, np.max(np.diff(g)))
    # per level: point = cube_part x (its cube-face point) + radius x c / |c|
    s = np.arange(BLEND_LEVELS) / BLEND_LEVELS
    cube_part = np.concatenate([1.0 - s, np.zeros(len(spheres))])
    level_radius = np.concatenate([s * r_blend, spheres])
    uniform = np.linspace(-1.0, 1.0, divisions + 1)

    node_blocks, element_blocks, offset = [], [], 0
    ti, tj, tk = np.meshgrid(uniform, uniform, uniform, indexing="ij")
    node_blocks.append(a * np.stack([ti, tj, tk], axis=-1).reshape(-1, 3))
    n1 = divisions + 1
    element_blocks.append(_hexes(np.arange(n1 ** 3).reshape(n1, n1, n1)))
    offset = n1 ** 3
    ci, cj = np.meshgrid(t, t, indexing="ij")
    ui, uj = np.meshgrid(uniform, uniform, indexing="ij")
    for axis in range(3):
        for sign in (-1.0, 1.0):
            c, face = np.zeros((n1, n1, 3)), np.zeros((n1, n1, 3))
            c[..., (axis + 1) % 3], c[..., (axis + 2) % 3], c[..., axis] = ci, cj, sign
            face[..., (axis + 1) % 3], face[..., (axis + 2) % 3], face[..., axis] = ui, uj, sign
            unit = c / np.linalg.norm(c, axis=-1, keepdims=True)
            pts = (cube_part[None, None, :, None] * a * face[:, :, None]
                   + level_radius[None, None, :, None] * unit[:, :, None])
            node_blocks.append(pts.reshape(-1, 3))
            ids = offset + np.arange(pts.shape[0] * pts.shape[1] * pts.shape[2]).reshape(
                pts.shape[:3])
            element_blocks.append(_hexes(ids))
            offset += ids.size
    nodes, elements = _merge(np.concatenate(node_blocks), np.concatenate(element_blocks), outer)
    centroid = nodes[elements].mean(axis=1)
    if half:
        keep = centroid[:, 1] > 0
        elements, centroid = elements[keep], centroid[keep]
        used = np.unique(elements)
        renumber = np.full(len(nodes), -1)
        renumber[used] = np.arange(len(used))
        nodes, elements = nodes[used], renumber[elements]
    nodes, elements = _spatially_ordered(nodes, elements)
    centroid = nodes[elements].mean(axis=1)
    group = np.searchsorted(radii, np.linalg.norm(centroid, axis=1))
    nodes = nodes + np.array([0.0, 0.0, outer])          # south pole on z = 0
    elements = _oriented(nodes, elements)
    radius = np.linalg.norm(nodes - np.array([0.0, 0.0, outer]), axis=1)
    surface = np.flatnonzero(np.abs(radius - outer) < 1e-9 * outer)
    symmetry = np.flatnonzero(np.abs(nodes[:, 1]) < 1e-9 * outer) if half else np.zeros(0, int)
    if np.any(centre_jacobian_det(nodes, elements) <= 0):
        raise InputError("ball mesh: an element has a non-positive Jacobian")
    return HexMesh(nodes_m=nodes, elements=elements, element_group=group,
                   ball_nodes=np.ones(len(nodes), bool), contact_nodes=surface,
                   symmetry_nodes=symmetry, half=half, outer_radius_m=float(outer))


def graded_line(half_width: float, cells_half: int, grading: float) -> np.ndarray:
    """Coordinates over [0, half_width], spacing growing geometrically by `grading` overall."""
    ratio = grading ** (1.0 / max(cells_half - 1, 1))
    steps = ratio ** np.arange(cells_half)
    return np.concatenate([[0.0], np.cumsum(steps)]) / steps.sum() * half_width


def graded_depths_m(layer_thicknesses_m, top_cell_m: float, largest_cell_m: float,
                    growth: float = RADIAL_GROWTH, min_cells: int = 2) -> np.ndarray:
    """Depths (m, down from the surface, 0 to the total thickness) of a slab's cell boundaries:
    `top_cell_m` thick at the surface, growing by `growth` a cell down to at most
    `largest_cell_m`, at least `min_cells` in a layer, each layer's cells scaled to fill it (its
    bottom is a boundary)."""
    depths, cell = [0.0], top_cell_m
    for thickness in layer_thicknesses_m:
        cells, cell = _growing_cells(thickness, cell, growth, lambda covered: largest_cell_m,
                                     min_cells)
        depths.extend(depths[-1] + np.cumsum(cells))
    return np.array(depths)


def uniform_depths_m(layer_thicknesses_m, cells_per_layer) -> np.ndarray:
    """Depths (m, down from the surface) of a slab's cell boundaries: equal cells in each
    layer."""
    depths = [0.0]
    for thickness, cells in zip(layer_thicknesses_m, cells_per_layer):
        depths.extend(depths[-1] + thickness * np.arange(1, cells + 1) / cells)
    return np.array(depths)


def slab_mesh(layer_thicknesses_m, half_width_m: float, cells_half: int, cells_per_layer=None,
              grading: float = 4.0, half: bool = True, depths_m=None) -> HexMesh:
    """A flat target: layers (top down) of the given thicknesses under z = 0, over
    [-w, w] x [-w, w] (y >= 0 for a half model), spacing graded toward the centre by `grading`;
    its base is fixed. Through the depth: `cells_per_layer` equal cells in each layer, or the
    cell boundaries `depths_m` (`graded_depths_m`). `target` holds the top surface's node grid
    for contact."""
    line = graded_line(half_width_m, cells_half, grading)
    xs = np.concatenate([-line[:0:-1], line])
    ys = line if half else xs
    if depths_m is None:
        depths_m = uniform_depths_m(layer_thicknesses_m, cells_per_layer)
    zs = -np.asarray(depths_m)[::-1]                    # from the base up to 0
    X, Y, Z = np.meshgrid(xs, ys, zs, indexing="ij")
    nodes = np.stack([X, Y, Z], axis=-1).reshape(-1, 3)
    ids = np.arange(len(nodes)).reshape(X.shape)
    elements = _hexes(ids)
    elements = _oriented(nodes, elements)
    centroid_z = nodes[elements][:, :, 2].mean(axis=1)
    bounds = -np.cumsum(layer_thicknesses_m)            # layer bottoms
    group = np.sum(centroid_z[:, None] < bounds[None, :-1], axis=1) if len(bounds) > 1 \
        else np.zeros(len(elements), int)
    symmetry = ids[:, 0, :].reshape(-1) if half else np.zeros(0, int)
    return HexMesh(nodes_m=nodes, elements=elements, element_group=group,
                   ball_nodes=np.zeros(len(nodes), bool), contact_nodes=np.zeros(0, int),
                   symmetry_nodes=symmetry, fixed_nodes=ids[:, :, 0].reshape(-1), half=half,
                   target={"top": ids[:, :, -1], "x_m": xs, "y_m": ys})


def combine(ball: HexMesh, slab: HexMesh, n_ball_groups: int) -> HexMesh:
    """The ball and a target slab in one mesh (slab nodes and groups after the ball's)."""
    offset = len(ball.nodes_m)
    target = dict(slab.target, top=slab.target["top"] + offset)
    return HexMesh(
        nodes_m=np.concatenate([ball.nodes_m, slab.nodes_m]),
        elements=np.concatenate([ball.elements, slab.elements + offset]),
        element_group=np.concatenate([ball.element_group, slab.element_group + n_ball_groups]),
        ball_nodes=np.concatenate([ball.ball_nodes, slab.ball_nodes]),
        contact_nodes=ball.contact_nodes,
        symmetry_nodes=np.concatenate([ball.symmetry_nodes, slab.symmetry_nodes + offset]),
        fixed_nodes=slab.fixed_nodes + offset, half=ball.half,
        outer_radius_m=ball.outer_radius_m, target=target)
