"""The layered-sphere O-grid mesh (`ballimpact.fe.axi.mesh`): valid counter-clockwise quads, nodes on
every layer circle, correct layers, second-order area and volume, pole refinement sizes, inputs."""

import math
from functools import cache

import numpy as np
import pytest
from scipy.spatial import cKDTree

from ballimpact.errors import InputError
from ballimpact.fe.axi.mesh import AxisymmetricMesh, layered_sphere_mesh, quad_quality

R = 0.036
SINGLE, TWO, THREE = (R,), (0.02, R), (0.02, 0.031, R)

# (radii, element size, pole element size, pole zone deg)
CONFIGS = [(radii, h, pole, 30.0) for radii in (SINGLE, TWO, THREE)
           for h in (2e-3, 1e-3, 0.5e-3) for pole in (None, h / 2)]
# strong refinement; the last one grades a thick outer layer, where neighbouring columns' radial
# spacings must blend slowly along the arc
STRONG = [(radii, 1e-3, pole, zone) for radii in (SINGLE, THREE)
          for pole, zone in ((0.25e-3, 10.0), (0.25e-3, 90.0), (0.1e-3, 30.0))]
STRONG += [(TWO, 2e-3, 0.2e-3, 10.0)]


@cache
def mesh_of(radii, h, pole=None, zone=30.0):
    return layered_sphere_mesh(radii, h, pole, zone)


def ids(config):
    radii, h, pole, zone = config
    return f"{len(radii)}layer-h{h * 1e3:g}mm-pole{'none' if pole is None else pole * 1e3}-{zone:g}deg"


def gauss_jacobians(mesh):
    """det J at the 2 x 2 Gauss points of every element, (n_elements, 4)."""
    corners = mesh.nodes_m[mesh.elements]                     # (n_el, 4, 2)
    xi_a, eta_a = np.array([-1, 1, 1, -1.0]), np.array([-1, -1, 1, 1.0])
    g = 1 / math.sqrt(3)
    dets = []
    for xi, eta in ((-g, -g), (g, -g), (g, g), (-g, g)):
        d_xi = np.einsum("a,eak->ek", xi_a * (1 + eta * eta_a) / 4, corners)
        d_eta = np.einsum("a,eak->ek", eta_a * (1 + xi * xi_a) / 4, corners)
        dets.append(d_xi[:, 0] * d_eta[:, 1] - d_xi[:, 1] * d_eta[:, 0])
    return np.stack(dets, axis=1)


def radius_of(points):
    return np.hypot(points[..., 0], points[..., 1])


@pytest.mark.parametrize("config", CONFIGS + STRONG, ids=ids)
def test_elements_counter_clockwise_valid_and_well_shaped(config):
    mesh = mesh_of(*config)
    assert mesh.element_areas_m2().min() > 0
    dets = gauss_jacobians(mesh)
    assert dets.min() > 0
    quality = quad_quality(mesh)
    # same measure, computed independently here
    assert quality["min_jacobian_ratio"] == pytest.approx(
        (4 * dets.min(axis=1) / mesh.element_areas_m2()).min(), rel=1e-9)
    assert quality["min_jacobian_ratio"] > 0.5
    assert quality["max_interior_angle_deg"] < 160
    assert quality["max_aspect_ratio"] < 20


@pytest.mark.parametrize("config", CONFIGS + STRONG, ids=ids)
def test_nodes_lie_on_every_layer_circle(config):
    mesh = mesh_of(*config)
    radius = radius_of(mesh.nodes_m)
    n_arc_nodes = len(mesh.surface_nodes)  # arc segments + 1, the same on every circle
    for r in mesh.layer_radii_m:
        assert np.count_nonzero(np.abs(radius - r) <= 1e-12 * r) == n_arc_nodes
    assert radius.max() <= R * (1 + 1e-12)


@pytest.mark.parametrize("config", CONFIGS, ids=ids)
def test_element_layers(config):
    mesh = mesh_of(*config)
    radii = (0.0,) + mesh.layer_radii_m
    corners = mesh.nodes_m[mesh.elements]
    centroid_radius = radius_of(corners.mean(axis=1))
    corner_radius = radius_of(corners)
    assert set(np.unique(mesh.element_layer)) == set(range(len(mesh.layer_radii_m)))
    for k in range(len(mesh.layer_radii_m)):
        mine = mesh.element_layer == k
        inner, outer = radii[k], radii[k + 1]
        assert np.all((centroid_radius[mine] > inner) & (centroid_radius[mine] < outer))
        assert np.all(corner_radius[mine] >= inner * (1 - 1e-12))
        assert np.all(corner_radius[mine] <= outer * (1 + 1e-12))


@pytest.mark.parametrize("radii", [SINGLE, THREE], ids=["1layer", "3layer"])
@pytest.mark.parametrize("pole", [False, True], ids=["uniform", "pole"])
def test_area_and_volume_converge_at_second_order(radii, pole):
    """The chords cut off the surface: error ~ h^2, so it falls by 4 (3.6 to 4.4, the segment
    count is rounded to a multiple of 4) each time the element size halves."""
    area_errors, volume_errors = [], []
    for h in (2e-3, 1e-3, 0.5e-3):
        mesh = mesh_of(radii, h, h / 2 if pole else None)
        area_errors.append(np.pi * R**2 / 2 - mesh.element_areas_m2().sum())
        volume_errors.append(4 / 3 * np.pi * R**3 - mesh.volume_m3())
    area_errors, volume_errors = np.array(area_errors), np.array(volume_errors)
    assert np.all(area_errors > 0) and np.all(volume_errors > 0)  # inscribed polygon
    for errors, exact in ((area_errors, np.pi * R**2 / 2), (volume_errors, 4 / 3 * np.pi * R**3)):
        ratios = errors[:-1] / errors[1:]
        assert np.all((ratios > 3.6) & (ratios < 4.4)), ratios
        assert errors[1] / exact < 2.5e-4  # at 1 mm


def test_volume_is_exact_pappus_for_a_hand_made_mesh():
    """A rectangle [r1, r2] x [z1, z2] sweeps an annular cylinder; a triangle-like quad on the axis
    sweeps a cone."""
    nodes = np.array([(0.01, 0.0), (0.03, 0.0), (0.03, 0.05), (0.01, 0.05),
                      (0.0, 0.1), (0.02, 0.1), (0.01, 0.13), (0.0, 0.16)])
    elements = np.array([[0, 1, 2, 3], [4, 5, 6, 7]])
    mesh = AxisymmetricMesh(nodes, elements, np.zeros(2, dtype=np.int64),
                            np.array([0], dtype=np.int64), (0.03,))
    cylinder = np.pi * (0.03**2 - 0.01**2) * 0.05
    cone = np.pi * 0.02**2 * 0.06 / 3  # apex (0, 0.16), base radius 0.02 at z = 0.1
    assert mesh.element_areas_m2() == pytest.approx([0.02 * 0.05, 0.02 * 0.06 / 2], rel=1e-12)
    assert mesh.volume_m3() == pytest.approx(cylinder + cone, rel=1e-12)


@pytest.mark.parametrize("config", CONFIGS + STRONG, ids=ids)
def test_no_duplicate_nodes_every_node_used_axis_exact(config):
    mesh = mesh_of(*config)
    distance, _ = cKDTree(mesh.nodes_m).query(mesh.nodes_m, k=2)
    assert distance[:, 1].min() > 1e-9
    assert np.array_equal(np.unique(mesh.elements), np.arange(mesh.n_nodes))
    r = mesh.nodes_m[:, 0]
    assert r.min() == 0.0
    assert np.all((r == 0.0) | (r > 1e-9))  # on the axis exactly, or clearly off it


@pytest.mark.parametrize("config", CONFIGS, ids=ids)
def test_surface_nodes_from_south_to_north_pole(config):
    mesh = mesh_of(*config)
    _, h, pole, _ = config
    surface = mesh.nodes_m[mesh.surface_nodes]
    assert mesh.surface_nodes.dtype == np.int64
    assert tuple(surface[0]) == (0.0, -R) and tuple(surface[-1]) == (0.0, R)
    polar = np.arctan2(surface[:, 0], -surface[:, 1])
    assert np.all(np.diff(polar) > 0)
    on_surface = np.flatnonzero(np.abs(radius_of(mesh.nodes_m) - R) <= 1e-12 * R)
    assert np.array_equal(np.sort(mesh.surface_nodes), on_surface)
    n_segments = len(mesh.surface_nodes) - 1
    assert n_segments % 4 == 0
    if pole is None:
        assert abs(n_segments - np.pi * R / h) <= 2  # rounded to a multiple of 4
    assert mesh.outer_radius_m == R


def test_uniform_mesh_is_mirror_symmetric_and_typed():
    """Without refinement the block is the half-square [0, a] x [-a, a], so the whole mesh is
    symmetric about z = 0."""
    mesh = mesh_of(THREE, 1e-3)
    mirrored = mesh.nodes_m * np.array([1.0, -1.0])
    distance, _ = cKDTree(mesh.nodes_m).query(mirrored)
    assert distance.max() < 1e-12
    assert mesh.nodes_m.dtype == np.float64 and mesh.nodes_m.shape == (mesh.n_nodes, 2)
    assert mesh.elements.dtype == np.int64 and mesh.elements.shape == (mesh.n_elements, 4)
    assert mesh.element_layer.dtype == np.int64 and mesh.element_layer.shape == (mesh.n_elements,)
    assert mesh.layer_radii_m == THREE
    with pytest.raises(ValueError):
        mesh.nodes_m[0, 0] = 1.0  # read-only


def test_pole_size_equal_to_element_size_means_no_refinement():
    plain, same = mesh_of(TWO, 1e-3), mesh_of(TWO, 1e-3, 1e-3)
    assert np.array_equal(plain.nodes_m, same.nodes_m)
    assert np.array_equal(plain.elements, same.elements)


@pytest.mark.parametrize("radii", [SINGLE, THREE], ids=["1layer", "3layer"])
@pytest.mark.parametrize("h, pole, zone", [(1e-3, 0.5e-3, 30.0), (2e-3, 0.5e-3, 30.0),
                                           (1e-3, 0.25e-3, 10.0), (0.5e-3, 0.25e-3, 45.0)])
def test_pole_refinement_sizes(radii, h, pole, zone):
    mesh = mesh_of(radii, h, pole, zone)
    surface = mesh.nodes_m[mesh.surface_nodes]
    edges = np.linalg.norm(np.diff(surface, axis=0), axis=1)
    # polar angle of each surface edge's midpoint, from the south pole
    middle = 0.5 * (surface[1:] + surface[:-1])
    polar_deg = np.degrees(np.arctan2(middle[:, 0], -middle[:, 1]))
    assert edges[0] == pytest.approx(pole, rel=0.2)
    assert np.all(np.abs(edges[polar_deg < 0.2 * zone] / pole - 1) < 0.2)
    # beyond the zone (with a margin for the growth-rate cap) the edges are back to element size
    far = polar_deg > zone + 15
    assert np.all(np.abs(edges[far] / h - 1) < 0.25)
    # neighbouring surface edges grow smoothly
    assert np.max(edges[1:] / edges[:-1]) < 1.3

    # the column under the pole: nodes on the axis, in the outermost layer, from the surface in
    axis = mesh.nodes_m[mesh.nodes_m[:, 0] == 0.0]
    inner = mesh.layer_radii_m[-2] if len(radii) > 1 else 0.0
    column = np.sort(axis[(axis[:, 1] < 0) & (-axis[:, 1] >= inner)][:, 1])
    spacing = np.diff(column)
    assert spacing[0] == pytest.approx(pole, rel=0.2)  # the element under the pole
    assert np.max(spacing[1:] / spacing[:-1]) <= 1.3   # geometric growth inward


def test_refinement_adds_elements_near_the_pole_only():
    plain, refined = mesh_of(SINGLE, 1e-3), mesh_of(SINGLE, 1e-3, 0.5e-3)
    assert refined.n_elements > plain.n_elements
    # the refined mesh's surface edges near the pole are about half as long
    near = refined.nodes_m[refined.surface_nodes[:10]]
    assert np.linalg.norm(np.diff(near, axis=0), axis=1).max() < 0.65e-3


@pytest.mark.parametrize("radii", [SINGLE, THREE], ids=["1layer", "3layer"])
@pytest.mark.parametrize("pole", [False, True], ids=["uniform", "pole"])
def test_element_count_scales_as_inverse_square_of_size(radii, pole):
    counts = np.array([mesh_of(radii, h, h / 2 if pole else None).n_elements
                       for h in (2e-3, 1e-3, 0.5e-3)])
    ratios = counts[1:] / counts[:-1]
    assert np.all((ratios > 3.3) & (ratios < 4.7)), ratios


def test_quad_quality_of_hand_made_elements():
    nodes = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0),      # unit square
                      (2.0, 0.0), (6.0, 0.0), (6.0, 1.0), (2.0, 1.0)])     # 4 x 1 rectangle
    mesh = AxisymmetricMesh(nodes, np.array([[0, 1, 2, 3]]), np.zeros(1, dtype=np.int64),
                            np.array([0], dtype=np.int64), (1.0,))
    assert quad_quality(mesh) == pytest.approx(
        {"min_jacobian_ratio": 1.0, "max_interior_angle_deg": 90.0, "max_aspect_ratio": 1.0})
    mesh = AxisymmetricMesh(nodes, np.array([[0, 1, 2, 3], [4, 5, 6, 7]]),
                            np.zeros(2, dtype=np.int64), np.array([0], dtype=np.int64), (1.0,))
    assert quad_quality(mesh)["max_aspect_ratio"] == pytest.approx(4.0)
    # a dart (one reflex corner): angle above 180 deg and a negative Jacobian at a Gauss point
    dart = np.array([(0.0, 0.0), (2.0, 0.0), (0.4, 0.4), (0.0, 2.0)])
    mesh = AxisymmetricMesh(dart, np.array([[0, 1, 2, 3]]), np.zeros(1, dtype=np.int64),
                            np.array([0], dtype=np.int64), (1.0,))
    quality = quad_quality(mesh)
    assert quality["max_interior_angle_deg"] > 180
    assert quality["min_jacobian_ratio"] < 0


@pytest.mark.parametrize("kwargs, name", [
    ({"layer_radii_m": ()}, "layer_radii_m"),
    ({"layer_radii_m": (0.02, 0.02)}, "layer_radii_m"),
    ({"layer_radii_m": (0.03, 0.02)}, "layer_radii_m"),
    ({"layer_radii_m": (-0.01, 0.02)}, "layer_radii_m"),
    ({"layer_radii_m": (0.0, 0.02)}, "layer_radii_m"),
    ({"layer_radii_m": (0.01, math.inf)}, "layer_radii_m"),
    ({"layer_radii_m": (0.01, math.nan)}, "layer_radii_m"),
    ({"layer_radii_m": "abc"}, "layer_radii_m"),
    ({"layer_radii_m": ((0.01, 0.02),)}, "layer_radii_m"),
    ({"element_size_m": 0.0}, "element_size_m"),
    ({"element_size_m": -1e-3}, "element_size_m"),
    ({"element_size_m": R / 2}, "element_size_m"),
    ({"element_size_m": math.nan}, "element_size_m"),
    ({"element_size_m": None}, "element_size_m"),
    ({"pole_element_size_m": 0.0}, "pole_element_size_m"),
    ({"pole_element_size_m": 1.5e-3}, "pole_element_size_m"),
    ({"pole_element_size_m": math.inf}, "pole_element_size_m"),
    ({"pole_element_size_m": "small"}, "pole_element_size_m"),
    ({"pole_zone_deg": 0.0}, "pole_zone_deg"),
    ({"pole_zone_deg": 90.5}, "pole_zone_deg"),
    ({"pole_zone_deg": math.nan}, "pole_zone_deg"),
])
def test_bad_inputs_raise_input_error_naming_the_argument(kwargs, name):
    arguments = {"layer_radii_m": THREE, "element_size_m": 1e-3} | kwargs
    with pytest.raises(InputError, match=name) as error:
        layered_sphere_mesh(**arguments)
    assert isinstance(error.value, ValueError)
    message = str(error.value)
    assert "must be" in message and ("(0," in message or "increasing" in message)


def test_refinement_too_strong_for_the_o_grid_is_refused():
    with pytest.raises(InputError, match="pole_element_size_m.*pole_zone_deg"):
        layered_sphere_mesh(SINGLE, 1e-3, 0.01e-3, 90.0)


@pytest.mark.parametrize("radii, size, pole", [
    ((0.036,), 1.5e-3, None),
    ((0.02, 0.031, 0.036), 1.5e-3, None),
    ((0.002, 0.036), 1.5e-3, None),          # a small core: a tiny block
    ((0.0355, 0.036), 1.5e-3, None),         # a thin cover
    ((0.11,), 1.5e-3, None),
    ((0.036,), 4e-3, None),
    ((0.036,), 1.5e-3, 5e-4),
    ((0.02, 0.031, 0.036), 1e-3, 2e-4),
    ((0.01, 0.02, 0.03, 0.036), 2e-3, 1e-3),
])
def test_estimate_mesh_counts_without_meshing(radii, size, pole):
    """The memory guard's element count (`estimate_mesh`, no node built) against the mesh:
    exact without pole refinement, within 2% with it; the smallest element's length within a
    factor 2.5 on the small side (the steps estimate stays on the high side)."""
    from ballimpact.fe.axi.element import geometry
    from ballimpact.fe.axi.mesh import estimate_mesh

    mesh = layered_sphere_mesh(radii, size, pole)
    estimate = estimate_mesh(radii, size, pole)
    if pole is None:
        assert estimate.elements == mesh.n_elements
    else:
        assert estimate.elements == pytest.approx(mesh.n_elements, rel=0.02)
    smallest = float(np.min(geometry(mesh).characteristic_length_m))
    assert 0.4 * smallest <= estimate.smallest_length_m <= 1.1 * smallest


def test_estimate_mesh_of_a_millimetre_ball_is_instant():
    """36.6 m (a radius in mm as m) at 1.5 mm: 1.5e9 elements counted, nothing built."""
    import time

    from ballimpact.fe.axi.mesh import estimate_mesh

    start = time.perf_counter()
    estimate = estimate_mesh((36.6,), 1.5e-3)
    assert time.perf_counter() - start < 1.0
    assert 1e9 < estimate.elements < 2e9
    with pytest.raises(InputError, match="element_size_m must be in"):
        estimate_mesh((0.036,), 0.1)


def test_both_poles_refined_alike():
    """`both_poles` (the two platens of `fe.compress`): the north pole refined as the south one,
    the mesh mirror-symmetric about the equator, well shaped, and counted by `estimate_mesh`."""
    from ballimpact.fe.axi.mesh import estimate_mesh

    mesh = layered_sphere_mesh(SINGLE, 1.5e-3, 4e-4, 30.0, both_poles=True)
    surface = mesh.nodes_m[mesh.surface_nodes]
    np.testing.assert_allclose(surface[::-1, 0], surface[:, 0], atol=1e-9 * SINGLE[0])
    np.testing.assert_allclose(surface[::-1, 1], -surface[:, 1], atol=1e-9 * SINGLE[0])
    segment = np.linalg.norm(np.diff(surface, axis=0), axis=1)
    assert segment[0] == pytest.approx(4e-4, rel=0.05)
    assert segment[-1] == pytest.approx(segment[0], rel=1e-6)
    assert segment.max() == pytest.approx(1.5e-3, rel=0.1)
    # every node has its mirror image: the radial grading is the same under both poles
    distance, _ = cKDTree(mesh.nodes_m).query(mesh.nodes_m * [1.0, -1.0])
    assert distance.max() < 1e-9 * SINGLE[0]
    assert quad_quality(mesh)["min_jacobian_ratio"] > 0.5
    assert estimate_mesh(SINGLE, 1.5e-3, 4e-4, 30.0, both_poles=True).elements == \
        pytest.approx(mesh.n_elements, rel=0.05)
    single = layered_sphere_mesh(SINGLE, 1.5e-3, 4e-4, 30.0)
    assert mesh.n_elements > single.n_elements
