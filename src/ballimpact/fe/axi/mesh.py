"""Axisymmetric 4-node quadrilateral mesh of a layered solid sphere (NumPy only).

The mesh covers the meridian half-disc r >= 0, r^2 + z^2 <= R^2 of a sphere centred at the origin,
in (r, z) coordinates (m). The contact pole is the south pole (0, -R).

Layout (an O-grid):

* a central *block*, meshed as a structured n x 2n grid. Without pole refinement it is the
  half-square [0, a] x [-a, a] with a = `BLOCK_HALF_SIDE_FRACTION` x the innermost radius;
* a *transition ring* from the block boundary, walked (0, z_bottom) -> bottom-right corner ->
  top-right corner -> (0, z_top), to the innermost layer circle;
* one ring of element columns per further layer, circle to circle.

Every ring has the same 4n segments along the arc (n along the block's bottom edge, 2n along its
right edge, n along its top edge), so node p of every circle lies on one ray from the centre at
polar angle theta_p, measured from the south pole. Nodes lie exactly on each layer circle, so
layers share their interface nodes (bonded).

With pole refinement the angles theta_p crowd toward the south pole, and the corner nodes n and 3n
of each circle no longer sit at 45 and 135 degrees. The block's right corners are then moved onto
the rays theta_n and theta_3n (same distance from the centre; the bottom edge stays horizontal, the
top edge tilts up toward the axis once theta_3n < 135 deg, see `_axis_distance`). Keeping the
square there would shear the thin part of the transition ring next to a corner by the whole
angular mismatch and fold its elements.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...checks import shown

#: half-side a of the central half-square block over the innermost layer radius: the block corners
#: sit at 0.81 x that radius, well inside it, and the ring between block and circle is thick enough
#: for its elements to stay close to square
BLOCK_HALF_SIDE_FRACTION = 0.57

#: largest size ratio of neighbouring elements in the refined pole zone: along the surface, and
#: radially (geometric growth inward from the surface)
GROWTH_RATIO = 1.2

#: smallest polar angle of the arc node 3n (the block's top corner): below it the top edge of the
#: block faces more than 135 deg of arc and the transition ring's corner angles exceed ~158 deg
MIN_TOP_CORNER_RAD = math.radians(45.0)

#: largest shear (depth offset over width) between neighbouring columns of the outermost ring
#: caused by blending the pole's radial grading into the uniform spacing away from it (0.4: 22 deg)
MAX_COLUMN_SHEAR = 0.4

#: samples of the surface element-size function used to place the refined arc nodes
_ARC_SAMPLES = 16385

#: 2 x 2 Gauss points of the reference square [-1, 1]^2
_GAUSS_2X2 = np.array([(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]) / math.sqrt(3.0)


@dataclass(frozen=True)
class AxisymmetricMesh:
    """A 4-node quadrilateral mesh of a layered sphere's meridian half-disc.

    Attributes
    ----------
    nodes_m : ndarray, shape (n_nodes, 2), float64
        Reference coordinates (r, z) in m. r >= 0; nodes on the axis have r == 0.0 exactly.
    elements : ndarray, shape (n_elements, 4), int64
        Node indices of each element, counter-clockwise in the (r, z) plane (positive area).
    element_layer : ndarray, shape (n_elements,), int64
        Layer index of each element, 0 = innermost.
    surface_nodes : ndarray, int64
        Nodes on the outer sphere surface, ordered from the south pole (0, -R) to the north pole
        (0, R).
    layer_radii_m : tuple of float
        Outer radius of each layer (m), from the centre out.

    The arrays are read-only.
    """

    nodes_m: np.ndarray
    elements: np.ndarray
    element_layer: np.ndarray
    surface_nodes: np.ndarray
    layer_radii_m: tuple[float, ...]

    @property
    def n_nodes(self) -> int:
        return int(self.nodes_m.shape[0])

    @property
    def n_elements(self) -> int:
        return int(self.elements.shape[0])

    @property
    def outer_radius_m(self) -> float:
        """Radius R of the sphere (m)."""
        return float(self.layer_radii_m[-1])

    def element_areas_m2(self) -> np.ndarray:
        """Signed area of each element in the (r, z) plane (m^2), by the shoelace formula.

        Returns
        -------
        ndarray, shape (n_elements,)
            Positive for counter-clockwise elements.
        """
        r, z = _corner_coordinates(self)
        return 0.5 * np.sum(r * np.roll(z, -1, axis=1) - np.roll(r, -1, axis=1) * z, axis=1)

    def element_volumes_m3(self) -> np.ndarray:
        """Volume of the ring each element sweeps about the z axis (m^3), shape (n_elements,).

        Pappus: each element sweeps 2 pi r_c A, with r_c the r of its polygon centroid and A its
        area. This is exact for the polygons as meshed (straight edges).
        """
        r, z = _corner_coordinates(self)
        r_next, z_next = np.roll(r, -1, axis=1), np.roll(z, -1, axis=1)
        # 2 pi A r_c = pi/3 sum_i (r_i + r_i+1)(r_i z_i+1 - r_i+1 z_i)
        return np.pi / 3.0 * np.sum((r + r_next) * (r * z_next - r_next * z), axis=1)

    def volume_m3(self) -> float:
        """Volume of the solid swept by the elements about the z axis (m^3): it differs from
        4/3 pi R^3 only by the chords cut off the surface."""
        return float(np.sum(self.element_volumes_m3()))


def layered_sphere_mesh(
    layer_radii_m,
    element_size_m: float,
    pole_element_size_m: float | None = None,
    pole_zone_deg: float = 30.0,
    both_poles: bool = False,
) -> AxisymmetricMesh:
    """Mesh a layered solid sphere's meridian half-disc with 4-node quadrilaterals (an O-grid).

    Parameters
    ----------
    layer_radii_m : sequence of float
        Outer radius of each layer (m), strictly increasing from the centre out; the last one is
        the sphere radius R.
    element_size_m : float
        Target element edge length (m), in (0, R/2). The outer semicircle gets about
        pi R / element_size_m segments (a multiple of 4); each layer gets about
        thickness / element_size_m radial segments (at least 1).
    pole_element_size_m : float, optional
        Target element size at the contact (south) pole (m), in (0, element_size_m]. When smaller
        than `element_size_m` the surface element length grows smoothly from this size at the pole
        to `element_size_m` at `pole_zone_deg`, and the outermost layer's radial spacing is graded
        (ratio `GROWTH_RATIO` inward) so the element under the pole is about this thick.
        None (default): no refinement.
    pole_zone_deg : float
        Polar angle from the south pole (degrees, in (0, 90]) beyond which the surface elements
        have `element_size_m`. The zone stretches where that would need neighbouring surface
        elements to grow by more than `GROWTH_RATIO`.
    both_poles : bool
        Refine the north pole as the south one (a ball between two platens, `fe.compress`).

    Returns
    -------
    AxisymmetricMesh

    Raises
    ------
    InputError
        An argument out of its range; the message names it. Also a pole refinement so strong
        (a tiny `pole_element_size_m` over a wide `pole_zone_deg`) that three quarters of the
        surface segments would crowd within `MIN_TOP_CORNER_RAD` of the pole, where the O-grid
        cannot stay well shaped.
    """
    radii, h, h_pole, zone_deg = _validated_sizes(layer_radii_m, element_size_m,
                                                  pole_element_size_m, pole_zone_deg)
    outer = float(radii[-1])
    refine = h_pole < h
    zone_rad = math.radians(zone_deg)

    theta = _arc_angles(outer, h, h_pole, zone_rad, refine, both_poles)
    n_arc = len(theta) - 1
    n = n_arc // 4
    if theta[3 * n] < MIN_TOP_CORNER_RAD:
        # The block's top edge would face more than 135 deg of arc: its ring elements flatten.
        raise InputError(
            f"pole_element_size_m = {h_pole:g} m with pole_zone_deg = {zone_deg:g} refines too "
            f"much for this O-grid: 3/4 of the {n_arc} surface segments would lie within "
            f"{math.degrees(theta[3 * n]):.0f} deg of the contact pole (at least "
            f"{math.degrees(MIN_TOP_CORNER_RAD):.0f} deg needed); raise pole_element_size_m "
            "(or element_size_m) or narrow pole_zone_deg")
    direction = np.stack([np.sin(theta), -np.cos(theta)], axis=1)
    direction[[0, -1], 0] = 0.0  # sin(pi) is 1e-16, not 0: keep the poles exactly on the axis
    surface_size = (_surface_size_m(theta, outer, h, h_pole, zone_rad, both_poles) if refine
                    else None)

    block_xy = _block_nodes(theta, BLOCK_HALF_SIDE_FRACTION * math.sqrt(2.0) * radii[0])
    block_ids = np.arange(block_xy.shape[0] * block_xy.shape[1]).reshape(block_xy.shape[:2])
    nodes = [block_xy.reshape(-1, 2)]
    next_id = block_ids.size
    elements = [_grid_elements(block_ids)]
    layers = [np.zeros(n * 2 * n, dtype=np.int64)]

    # ids of the block boundary walked like the arc: bottom edge, right edge, top edge
    inner_ids = np.concatenate([block_ids[:, 0], block_ids[n, 1:], block_ids[n - 1::-1, 2 * n]])
    inner_xy = block_xy.reshape(-1, 2)[inner_ids]
    n_layers = len(radii)
    for k in range(n_layers):
        outer_xy = radii[k] * direction
        if k == 0:
            length = np.linalg.norm(outer_xy - inner_xy, axis=1)
            # The block's spacing along the arc is below element_size_m when the innermost layer is
            # smaller than R (every ring has the same 4n segments): size the transition ring's
            # radial segments on the mean spacing of its two curves so its elements stay square.
            arc_spacing = 0.5 * (_mean_spacing(inner_xy) + _mean_spacing(outer_xy))
            n_uniform = max(1, round(float(np.mean(length)) / min(h, arc_spacing)))
        else:
            length = np.full(n_arc + 1, radii[k] - radii[k - 1])
            n_uniform = max(1, round(float(length[0]) / h))
        if k == n_layers - 1 and refine:
            fractions = _graded_fractions(float(length[0]), n_uniform, h_pole,
                                          float(np.linalg.norm(inner_xy[0])), outer,
                                          surface_size, outer * theta, both_poles)
        else:
            fractions = np.broadcast_to(np.linspace(0.0, 1.0, n_uniform + 1), (n_arc + 1,
                                                                                n_uniform + 1))
        n_radial = fractions.shape[1] - 1
        t = fractions[:, 1:-1, None]
        if k == 0:  # straight columns from the block boundary to the circle
            ring_xy = inner_xy[:, None, :] + t * (outer_xy - inner_xy)[:, None, :]
        else:  # radial columns: intermediate nodes on intermediate circles
            ring_xy = (radii[k - 1] + t * length[:, None, None]) * direction[:, None, :]
        ring_xy = np.concatenate([ring_xy, outer_xy[:, None, :]], axis=1)  # (n_arc+1, n_radial, 2)
        new_ids = next_id + np.arange((n_arc + 1) * n_radial).reshape(n_arc + 1, n_radial)
        next_id += new_ids.size
        nodes.append(ring_xy.reshape(-1, 2))
        column_ids = np.concatenate([inner_ids[:, None], new_ids], axis=1).T  # (radial, arc)
        elements.append(_grid_elements(column_ids))
        layers.append(np.full(n_arc * n_radial, k, dtype=np.int64))
        inner_ids, inner_xy = new_ids[:, -1], outer_xy

    return AxisymmetricMesh(
        nodes_m=_read_only(np.concatenate(nodes).astype(np.float64)),
        elements=_read_only(np.concatenate(elements).astype(np.int64)),
        element_layer=_read_only(np.concatenate(layers)),
        surface_nodes=_read_only(inner_ids.astype(np.int64)),
        layer_radii_m=tuple(float(r) for r in radii),
    )


def quad_quality(mesh: AxisymmetricMesh) -> dict[str, float]:
    """Worst-element shape measures of a mesh.

    Parameters
    ----------
    mesh : AxisymmetricMesh

    Returns
    -------
    dict
        ``min_jacobian_ratio``: smallest Jacobian determinant at the 2 x 2 Gauss points times 4 over
        the element area (1 for a parallelogram, <= 0 for an invalid element);
        ``max_interior_angle_deg``: largest interior corner angle (degrees; > 180 for a
        non-convex element); ``max_aspect_ratio``: largest ratio of an element's longest edge to
        its shortest.
    """
    r, z = _corner_coordinates(mesh)
    xi, eta = _GAUSS_2X2[:, 0, None], _GAUSS_2X2[:, 1, None]  # (4 points, 1)
    # bilinear shape-function derivatives at the Gauss points, (4 points, 4 nodes)
    dn_dxi = 0.25 * np.stack([-(1 - eta), 1 - eta, 1 + eta, -(1 + eta)], axis=-1)[:, 0, :]
    dn_deta = 0.25 * np.stack([-(1 - xi), -(1 + xi), 1 + xi, 1 - xi], axis=-1)[:, 0, :]
    det = (r @ dn_dxi.T) * (z @ dn_deta.T) - (z @ dn_dxi.T) * (r @ dn_deta.T)  # (n_el, 4 points)
    jacobian_ratio = 4.0 * det.min(axis=1) / mesh.element_areas_m2()

    edge_r, edge_z = np.roll(r, -1, axis=1) - r, np.roll(z, -1, axis=1) - z  # edge i: node i -> i+1
    in_r, in_z = np.roll(edge_r, 1, axis=1), np.roll(edge_z, 1, axis=1)      # edge into node i
    # interior angle of a counter-clockwise polygon = 180 deg - turning angle at the corner
    turning = np.arctan2(in_r * edge_z - in_z * edge_r, in_r * edge_r + in_z * edge_z)
    interior_deg = np.degrees(np.pi - turning)
    edge_length = np.hypot(edge_r, edge_z)
    return {
        "min_jacobian_ratio": float(jacobian_ratio.min()),
        "max_interior_angle_deg": float(interior_deg.max()),
        "max_aspect_ratio": float((edge_length.max(axis=1) / edge_length.min(axis=1)).max()),
    }


def _surface_size_m(theta: np.ndarray, outer: float, h: float, h_pole: float,
                    zone_rad: float, both_poles: bool = False) -> np.ndarray:
    """Target surface element length (m) at polar angle `theta` (rad, from the south pole; from
    the nearer pole with `both_poles`).

    A C1 ramp of log(size) from `h_pole` at the pole to `h` at the zone's edge (for a large size
    ratio a linear ramp would keep near-`h_pole` elements over much of the zone), capped by a
    linear growth of `GROWTH_RATIO` - 1 per unit arc length: neighbouring elements then differ by
    at most about that ratio, which stretches the zone when a steep size ratio would not fit in it.
    """
    if both_poles:
        theta = np.minimum(theta, math.pi - theta)
    ramp = h_pole * (h / h_pole) ** _smoothstep(theta / zone_rad)
    return np.minimum(ramp, h_pole + (GROWTH_RATIO - 1.0) * outer * theta)


def _arc_angles(outer: float, h: float, h_pole: float, zone_rad: float, refine: bool,
                both_poles: bool = False) -> np.ndarray:
    """Polar angles theta_p (rad, from the south pole) of the 4n + 1 nodes of every circle.

    The count comes from the outer surface: the integral of arc length over the target element
    size, rounded to a multiple of 4. Nodes are placed at equal steps of that integral, so the
    surface segment at angle theta is about the target size there.
    """
    if not refine:
        return np.linspace(0.0, math.pi, 4 * _quarters(math.pi * outer / h) + 1)
    grid, count = _arc_integral(outer, h, h_pole, zone_rad, both_poles)
    theta = np.interp(np.linspace(0.0, count[-1], 4 * _quarters(count[-1]) + 1), count, grid)
    theta[0], theta[-1] = 0.0, math.pi
    return theta


def _arc_integral(outer: float, h: float, h_pole: float, zone_rad: float,
                  both_poles: bool = False):
    """(polar angles, surface segments from the pole to each) of a refined surface."""
    # samples crowd quadratically toward the refined pole(s), where segments can be very short
    u = np.linspace(0.0, 1.0, _ARC_SAMPLES)
    grid = math.pi * (0.5 - 0.5 * np.cos(math.pi * u) if both_poles else u**2)
    density = outer / _surface_size_m(grid, outer, h, h_pole, zone_rad, both_poles)
    return grid, np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1])
                                                  * np.diff(grid))])


def _quarters(segments: float) -> int:
    """n: a surface of about `segments` target-sized segments gets 4n (a multiple of 4)."""
    return max(1, math.floor(segments / 4.0 + 0.5))


def _quarter_count(outer: float, h: float, h_pole: float, zone_rad: float,
                   both_poles: bool = False) -> int:
    """n: the surface has 4n segments (without building them: a mis-scaled ball can ask for
    billions)."""
    return _quarters(math.pi * outer / h if h_pole >= h
                     else float(_arc_integral(outer, h, h_pole, zone_rad, both_poles)[1][-1]))


@dataclass(frozen=True)
class MeshEstimate:
    """The size of a mesh, estimated without building it (`estimate_mesh`)."""

    elements: int
    smallest_length_m: float   # about the smallest element's characteristic length


def estimate_mesh(layer_radii_m, element_size_m: float, pole_element_size_m: float | None = None,
                  pole_zone_deg: float = 30.0, both_poles: bool = False) -> MeshEstimate:
    """The element count and smallest element length of `layered_sphere_mesh` with these
    arguments, from its counting rules alone (no node is built, so a ball given in millimetres
    as metres costs nothing here): within 10% of the count on the presets, the refined meshes
    and thin or small cores (tests/fe/test_fe_mesh.py). Arguments are checked as there."""
    radii, h, h_pole, zone_deg = _validated_sizes(layer_radii_m, element_size_m,
                                                  pole_element_size_m, pole_zone_deg)
    outer, inner = float(radii[-1]), float(radii[0])
    n = _quarter_count(outer, h, h_pole, math.radians(zone_deg), both_poles)
    n_arc = 4 * n
    # block n x 2n; the transition ring spans ~0.35 r0 (block boundary at 1.15 half-sides on
    # average) in segments sized on its two curves' mean spacing, as `layered_sphere_mesh`
    half_side = BLOCK_HALF_SIDE_FRACTION * inner
    spacing = 0.5 * (half_side / n + math.pi * inner / n_arc)
    radial = [max(1, round((inner - 1.148 * half_side) / min(h, spacing)))]
    radial += [max(1, round((r - r0) / h)) for r0, r in zip(radii[:-1], radii[1:])]
    if h_pole < h:  # the outer ring grows geometrically from h_pole to its uniform spacing
        length = outer - (float(radii[-2]) if len(radii) > 1 else 1.148 * half_side)
        cap = length / radial[-1]
        if h_pole < cap:
            steps = math.ceil(math.log(cap / h_pole) / math.log(GROWTH_RATIO))
            graded = h_pole * (GROWTH_RATIO ** steps - 1.0) / (GROWTH_RATIO - 1.0)
            radial[-1] = steps + max(0, math.ceil((length - graded) / cap))
    elements = 2 * n * n + n_arc * sum(radial)
    # the smallest elements: the block's corners (a quarter of the arc spacing at the innermost
    # radius) or the surface element at the pole
    smallest = 0.25 * min(h_pole, math.pi * inner / n_arc)
    return MeshEstimate(elements=int(elements), smallest_length_m=smallest)


def _block_nodes(theta: np.ndarray, corner_radius: float) -> np.ndarray:
    """Nodes of the central block, shape (n + 1, 2n + 1, 2), index [i along r, j along z].

    The block is the quadrilateral (axis bottom, corner_b, corner_t, axis top) with its right
    corners on the rays theta_n and theta_3n at `corner_radius` from the centre and straight
    edges; without refinement (theta_n = 45 deg, theta_3n = 135 deg) it is the half-square (see
    `_axis_distance`). Each edge's nodes follow the arc's angle distribution (same relative
    spacing as the matching stretch of the circles). The interior is a transfinite interpolation
    of the edges: with straight edges that is the bilinear map of the corners, evaluated where the
    straight parameter lines joining opposite edge nodes cross, which cannot fold.
    """
    n = (len(theta) - 1) // 4
    bottom, top = theta[n], theta[3 * n]
    corner_b = corner_radius * np.array([math.sin(bottom), -math.cos(bottom)])
    corner_t = corner_radius * np.array([math.sin(top), -math.cos(top)])
    axis_b = np.array([0.0, -_axis_distance(bottom, corner_radius)])
    axis_t = np.array([0.0, _axis_distance(math.pi - top, corner_radius)])

    u_bottom = theta[: n + 1] / bottom  # along the bottom edge, from the axis
    u_top = (math.pi - theta[4 * n: 3 * n - 1: -1]) / (math.pi - top)  # along the top edge
    v_side = (theta[n: 3 * n + 1] - bottom) / (top - bottom)  # along the right edge and the axis
    # Parameter lines: u = u_bottom + (u_top - u_bottom) v joins opposite bottom/top nodes, and
    # v = v_side joins the axis to the right edge (same distribution on both), so they cross at
    u = u_bottom[:, None] + (u_top - u_bottom)[:, None] * v_side[None, :]
    v = np.broadcast_to(v_side[None, :], u.shape)
    uu, vv = u[..., None], v[..., None]
    xy = ((1 - uu) * (1 - vv) * axis_b + uu * (1 - vv) * corner_b + uu * vv * corner_t
          + (1 - uu) * vv * axis_t)
    xy[0, :, 0] = 0.0  # the axis edge, exactly
    return xy


def _axis_distance(corner_angle: float, corner_radius: float) -> float:
    """Distance from the centre to the block's corner on the axis (m).

    `corner_angle` (rad) is the angle between the axis and the ray of the neighbouring right-hand
    corner. In the triangle (centre, right corner, axis corner) the angle at the axis corner is
    kept at 90 deg (a horizontal edge: the half-square) while the corner's ray is at most 45 deg
    off the axis. Beyond that a horizontal edge would meet the ray at more than 135 deg and the
    transition-ring element there would flatten (the top corner when refinement crowds the arc
    nodes south), so the edge is tilted toward the axis just enough to keep that angle at 135 deg,
    and never past the isosceles triangle (axis corner as far out as the right corner).
    """
    axis_angle = min(math.pi / 2, max((math.pi - corner_angle) / 2, 0.75 * math.pi - corner_angle))
    # law of sines: the angle at the right corner is pi - corner_angle - axis_angle
    return corner_radius * math.sin(corner_angle + axis_angle) / math.sin(axis_angle)


def _graded_fractions(pole_length: float, n_uniform: int, first: float, inner_radius: float,
                      outer_radius: float, surface_size: np.ndarray,
                      arc_length: np.ndarray, both_poles: bool = False) -> np.ndarray:
    """Radial node fractions (0 inner curve, 1 surface) of each column of the outermost ring.

    At the pole the spacing grows geometrically inward from `first` (ratio at most
    `GROWTH_RATIO`) up to a uniform spacing no coarser than the ungraded one. Away from the pole
    the columns are uniform, with the same count. In between, a column blends the two with a
    weight chosen so that its surface element is about as thick as `surface_size` (the arc's
    target size at that column), except that the weight may fall only slowly along the arc
    (`arc_length`, m): node j of neighbouring columns then sits at nearly the same depth, and the
    elements between them shear by at most about `MAX_COLUMN_SHEAR`.

    Parameters
    ----------
    pole_length : float
        Length of the pole column (m), inner curve to surface.
    n_uniform : int
        Radial segments of the ring without grading.
    first : float
        Thickness of the surface element at the pole (m).
    inner_radius, outer_radius : float
        Distance of the pole column's ends from the centre (m); columns narrow toward the centre.
    surface_size, arc_length : ndarray, shape (n_columns,)
        Target surface element size (m) and surface arc length from the south pole (m) of each
        column.
    both_poles : bool
        The north pole's column is graded as the south one's.

    Returns
    -------
    ndarray, shape (n_columns, n_radial + 1)
    """
    cap = pole_length / n_uniform
    if first >= cap:  # the ungraded spacing is already fine enough
        return np.broadcast_to(np.linspace(0.0, 1.0, n_uniform + 1), (len(arc_length),
                                                                        n_uniform + 1))
    # fewest segments whose capped geometric sequence reaches the surface-to-inner length
    m = n_uniform
    while np.minimum(first * GROWTH_RATIO ** np.arange(m), cap).sum() < pole_length:
        m += 1
    growth = first * GROWTH_RATIO ** np.arange(m)
    if m * first >= pole_length:
        spacing = np.full(m, pole_length / m)
    else:  # lower the cap until the sequence fits the length exactly (sum is monotone in it)
        low, high = first, cap
        for _ in range(100):
            mid = 0.5 * (low + high)
            low, high = (mid, high) if np.minimum(growth, mid).sum() < pole_length else (low, mid)
        spacing = np.minimum(growth, 0.5 * (low + high))
    depth = np.concatenate([[0.0], np.cumsum(spacing)])  # from the surface inward
    graded = 1.0 - depth[::-1] / depth[-1]
    graded[0], graded[-1] = 0.0, 1.0
    uniform = np.linspace(0.0, 1.0, m + 1)
    offset = np.abs(graded - uniform) * pole_length
    moved = offset > 1e-9 * pole_length
    if not moved.any():  # the capped sequence came out uniform
        return np.broadcast_to(uniform, (len(arc_length), m + 1))

    # weight giving each column's surface element the target size: w first + (1 - w) L/m = size
    uniform_spacing = pole_length / m
    weight = np.clip((uniform_spacing - surface_size) / (uniform_spacing - first), 0.0, 1.0)
    # Between columns a step dw moves node j by dw |graded_j - uniform_j| L; keep that below
    # MAX_COLUMN_SHEAR x the column width there, which is the surface arc step scaled by the
    # node's distance from the centre over the outer radius.
    width_scale = (inner_radius + uniform * (outer_radius - inner_radius)) / outer_radius
    slope = MAX_COLUMN_SHEAR * float(np.min(width_scale[moved] / offset[moved]))  # per m of arc
    # the smallest slope-limited weight not below the target: a running maximum from the pole
    # (from each pole, the larger of the two, with `both_poles`)
    limited = np.maximum.accumulate(weight + slope * arc_length) - slope * arc_length
    if both_poles:
        back = arc_length[-1] - arc_length[::-1]
        limited = np.maximum(limited, (np.maximum.accumulate(weight[::-1] + slope * back)
                                       - slope * back)[::-1])
    weight = np.clip(limited, 0.0, 1.0)
    # a convex blend of two increasing sequences is increasing: every column stays valid
    return weight[:, None] * graded[None, :] + (1.0 - weight[:, None]) * uniform[None, :]


def _grid_elements(ids: np.ndarray) -> np.ndarray:
    """Counter-clockwise quads of a structured grid of node ids [i, j], i along r-ish, j along z-ish.

    For a ring the grid is [radial, arc]: moving out along a column then along the arc toward the
    north pole turns counter-clockwise, like moving along r then z in the block.
    """
    return np.stack([ids[:-1, :-1], ids[1:, :-1], ids[1:, 1:], ids[:-1, 1:]], axis=-1).reshape(-1, 4)


def _mean_spacing(xy: np.ndarray) -> float:
    return float(np.mean(np.linalg.norm(np.diff(xy, axis=0), axis=1)))


def _smoothstep(x: np.ndarray) -> np.ndarray:
    """3x^2 - 2x^3 on [0, 1], 0 below, 1 above: a C1 ramp, so element sizes change smoothly."""
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def _corner_coordinates(mesh: AxisymmetricMesh) -> tuple[np.ndarray, np.ndarray]:
    corners = mesh.nodes_m[mesh.elements]  # (n_elements, 4, 2)
    return corners[..., 0], corners[..., 1]


def _read_only(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array


def _validated_in_range(value, name: str, low: float, high: float, high_allowed: bool,
                        allowed: str) -> float:
    """`value` as a float in (low, high) or (low, high]; else InputError naming `name`, `allowed`."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (low < number and (number <= high if high_allowed else number < high)):  # NaN fails
        raise InputError(f"{name} must be in {allowed}, got {shown(value)}")
    return number


def _validated_sizes(layer_radii_m, element_size_m, pole_element_size_m, pole_zone_deg):
    """(radii, element size, pole element size, pole zone in degrees), checked; InputError
    naming the argument and its allowed range."""
    radii = _validated_radii(layer_radii_m)
    outer = float(radii[-1])
    h = _validated_in_range(element_size_m, "element_size_m", 0.0, outer / 2.0, False,
                            f"(0, outer radius/2 = {outer / 2.0:g}) m")
    h_pole = h if pole_element_size_m is None else _validated_in_range(
        pole_element_size_m, "pole_element_size_m", 0.0, h, True,
        f"(0, element_size_m = {h:g}] m")
    zone_deg = _validated_in_range(pole_zone_deg, "pole_zone_deg", 0.0, 90.0, True, "(0, 90] deg")
    return radii, h, h_pole, zone_deg


def _validated_radii(layer_radii_m) -> np.ndarray:
    message = ("layer_radii_m must be a non-empty sequence of positive, finite, strictly "
               f"increasing radii in m, got {shown(layer_radii_m)}")
    try:
        radii = np.asarray(layer_radii_m, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(message) from None
    if (radii.ndim != 1 or radii.size == 0 or not np.all(np.isfinite(radii)) or radii[0] <= 0.0
            or np.any(np.diff(radii) <= 0.0)):
        raise InputError(message)
    return radii
