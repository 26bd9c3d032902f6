"""The ball as a deck sees it: nodes, elements per layer, the outer-surface faces, the node sets
of its boundary conditions, and the mesh's own mass (NumPy only).

The meshes are the solvers' own (`fe.axi.mesh.layered_sphere_mesh` for the axisymmetric ball,
`fe.hex.mesh.ball_mesh` for the 3D one), so an exported ball is the ball that `simulate` runs.
Placement: the contact (south) pole at the origin, the ball above the plane y = 0 (axisymmetric,
(r, z) written as (x, y) with y the axis, as ABAQUS and CalculiX expect) or z = 0 (3D).
Element faces are numbered as ABAQUS numbers them (CAX4: S1 = nodes 1-2 ... S4 = 4-1; C3D8: S1
bottom 1-2-3-4, S2 top 5-8-7-6, S3 1-5-6-2, S4 2-6-7-3, S5 3-7-8-4, S6 4-8-5-1); LS-DYNA uses
the same corner order for its hexahedra.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..balls.ball import BallModel
from ..fe.axi.mesh import estimate_mesh, layered_sphere_mesh
from ..fe.hex.contact_grading import without_contact
from ..fe.hex.element import geometry
from ..fe.hex.mesh import ball_mesh, estimate_ball_mesh
from ..fe.options import Options3D, SolverOptions

SOLVERS = ("axisymmetric", "3d")

QUAD_FACES = ((0, 1), (1, 2), (2, 3), (3, 0))
HEX_FACES = ((0, 1, 2, 3), (4, 7, 6, 5), (0, 4, 5, 1), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 4, 0))


@dataclass(frozen=True)
class BallGeometry:
    """A meshed ball placed on its contact plane, in metres (0-based indices)."""

    solver: str                 # "axisymmetric" or "3d"
    nodes_m: np.ndarray         # (n, 2): (r, z) as (x, y); (n, 3): (x, y, z)
    elements: np.ndarray        # (n_el, 4) counter-clockwise quads, or (n_el, 8) hexahedra
    element_layer: np.ndarray   # (n_el,) layer index, 0 = innermost
    surface_faces: np.ndarray   # (k, 2): element index, face number (1-based) on the outer surface
    axis_nodes: np.ndarray      # axisymmetric: nodes on r = 0
    symmetry_nodes: np.ndarray  # 3D half model: nodes on y = 0
    half: bool
    element_volume_m3: np.ndarray  # as swept about the axis (axisymmetric: the whole ring)

    @property
    def dimension(self) -> int:
        return self.nodes_m.shape[1]

    def layer_volumes_m3(self, n_layers: int) -> np.ndarray:
        """Meshed volume of each layer (m^3; a half model's is half the ball's)."""
        return np.bincount(self.element_layer, self.element_volume_m3, minlength=n_layers)

    def mass_kg(self, ball: BallModel) -> float:
        """Mass of the meshed ball (whole ball; a half model's is doubled)."""
        density = np.array([layer.density_kg_m3 for layer in ball.layers])
        mass = float(density @ self.layer_volumes_m3(len(ball.layers)))
        return 2.0 * mass if self.half else mass


def _surface_faces(elements: np.ndarray, on_surface: np.ndarray, faces) -> np.ndarray:
    out = []
    for number, face in enumerate(faces, start=1):
        hit = np.flatnonzero(np.all(on_surface[elements[:, list(face)]], axis=1))
        out.extend((int(e), number) for e in hit)
    return np.array(sorted(out), dtype=np.int64).reshape(-1, 2)


def _mesh_options(solver: str, element_size_m: float | None, divisions: int | None,
                  pole_grading: float | None):
    """The checked mesh options of `solver`: the element size (axisymmetric) or
    `Options3D` (3d); the other solver's options are ignored (`export --solver` refuses them)."""
    if solver == "axisymmetric":
        size = SolverOptions().element_size_m if element_size_m is None else element_size_m
        SolverOptions(element_size_m=size)  # validates
        return size
    if solver == "3d":
        given = {} if divisions is None else {"divisions": divisions}
        return without_contact(Options3D(**given, pole_grading=pole_grading))
    raise InputError(f"solver = {solver!r}: allowed {', '.join(SOLVERS)}")


def estimate_elements(ball: BallModel, solver: str = "axisymmetric", *,
                      element_size_m: float | None = None, divisions: int | None = None,
                      pole_grading: float | None = None, half: bool = False) -> int:
    """The element count of `ball_geometry` with these arguments, without meshing (the mesh's
    counting rules: `fe.axi.mesh.estimate_mesh`, `fe.hex.mesh.estimate_ball_mesh`); arguments are
    checked as there."""
    options = _mesh_options(solver, element_size_m, divisions, pole_grading)
    if solver == "axisymmetric":
        return estimate_mesh(ball.layer_radii_m, options).elements
    return estimate_ball_mesh(ball.layer_radii_m, options.divisions, options.pole_grading,
                              half)[0]


def ball_geometry(ball: BallModel, solver: str = "axisymmetric", *,
                  element_size_m: float | None = None, divisions: int | None = None,
                  pole_grading: float | None = None, half: bool = False) -> BallGeometry:
    """Mesh `ball` for a deck: axisymmetric quadrilaterals of `element_size_m` (default the
    solver's, `fe.SolverOptions`), or 3D hexahedra with `divisions` and `pole_grading`
    (defaults `oblique.Options3D`'s divisions, grading 2: `without_contact`), the whole ball
    or, with `half`, the half y >= 0."""
    options = _mesh_options(solver, element_size_m, divisions, pole_grading)
    if solver == "axisymmetric":
        mesh = layered_sphere_mesh(ball.layer_radii_m, options)
        nodes = np.array(mesh.nodes_m, dtype=float)
        nodes[:, 1] += ball.outer_radius_m
        nodes[np.abs(nodes[:, 0]) < 1e-12 * ball.outer_radius_m, 0] = 0.0
        on_surface = np.zeros(len(nodes), bool)
        on_surface[mesh.surface_nodes] = True
        elements = np.asarray(mesh.elements)
        volume = mesh.element_volumes_m3()
        return BallGeometry(solver, nodes, elements, np.asarray(mesh.element_layer),
                            _surface_faces(elements, on_surface, QUAD_FACES),
                            np.flatnonzero(nodes[:, 0] == 0.0), np.zeros(0, np.int64), False,
                            volume)
    if solver == "3d":
        mesh = ball_mesh(ball.layer_radii_m, options.divisions, options.pole_grading, half=half)
        on_surface = np.zeros(len(mesh.nodes_m), bool)
        on_surface[mesh.contact_nodes] = True
        elements = np.asarray(mesh.elements)
        volume = np.asarray(geometry(mesh, len(ball.layers))[0].volume_m3)
        return BallGeometry(solver, np.asarray(mesh.nodes_m, float), elements,
                            np.asarray(mesh.element_group), _surface_faces(elements, on_surface,
                                                                           HEX_FACES),
                            np.zeros(0, np.int64), np.asarray(mesh.symmetry_nodes), half, volume)
    raise InputError(f"solver = {solver!r}: allowed {', '.join(SOLVERS)}")

