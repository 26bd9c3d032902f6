"""8-node hexahedron, total Lagrangian: one integration point with hourglass control (as
ABAQUS/Explicit's C3D8R and the axisymmetric engine's default "reduced" integration), or 2x2x2
points with F-bar ("full", as the axisymmetric engine's other choice: each point's F scaled to the
centre's volume change, Fbar = (J0 / J)^(1/3) F, forces the exact pull-back of P : dFbar).

F is evaluated at the element centre, F = I + sum_a u_a (x) b_a with b_a = dN_a/dX there, which
avoids volumetric locking; corner forces f_a = V P b_a are the exact gradient of V W(F), so the
energy balance closes. The four spurious modes per direction are held by the Flanagan-Belytschko
(1981) stiffness: with the base vectors h = (xi eta, eta zeta, zeta xi, xi eta zeta) at the
corners and gamma_a = h_a - (h . X_d) b_ad (orthogonal to every linear field, so rigid motions,
large rotations included, and homogeneous strains give no hourglass force), q = gamma . u and the
energy 0.5 k_e |q|^2 with k_e = scale x mu x V_e x (b : b), the same form as the axisymmetric
engine's.

Arrays are laid out components first and elements last, (..., n_el), so that each operation is
one fused loop over elements.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from ..assembly import corner_tables, gather_nodal as gather_corners
from ...constitutive.fastmath import cube_root
from .mesh import HEX_CORNERS, HexMesh

_GAUSS = HEX_CORNERS / np.sqrt(3.0)     # 2 x 2 x 2 points (weight 1), for volumes and masses
_MODES = np.stack([HEX_CORNERS[:, 0] * HEX_CORNERS[:, 1], HEX_CORNERS[:, 1] * HEX_CORNERS[:, 2],
                   HEX_CORNERS[:, 2] * HEX_CORNERS[:, 0],
                   HEX_CORNERS[:, 0] * HEX_CORNERS[:, 1] * HEX_CORNERS[:, 2]])  # (4, 8)


def _shape_gradients(point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """N_a and dN_a/dxi_k at a reference point: (8,), (8, 3)."""
    factors = 1.0 + HEX_CORNERS * point          # (8, 3)
    values = np.prod(factors, axis=1) / 8.0
    grads = np.empty((8, 3))
    for k in range(3):
        others = [j for j in range(3) if j != k]
        grads[:, k] = HEX_CORNERS[:, k] * np.prod(factors[:, others], axis=1) / 8.0
    return values, grads


@dataclass(frozen=True, eq=False)
class HexGeometry:
    """Reference data of a hexahedral mesh, elements sorted by group (NumPy, float64)."""

    nodes_m: np.ndarray           # (n_nodes, 3)
    elements: np.ndarray          # (n_el, 8)
    group_slices: tuple[tuple[int, int], ...]
    grad_n: np.ndarray            # (8, 3, n_el) dN_a/dX_d at the centre (1/m)
    point_grad_n: np.ndarray      # (8, 3, 8, n_el) dN_a/dX_d at the 2x2x2 Gauss points
    point_volume_m3: np.ndarray   # (8, n_el) det(dX/dxi) at the Gauss points (weight 1)
    volume_m3: np.ndarray         # (n_el,)
    hourglass_moment_m: np.ndarray  # (4, 3, n_el) h . X_d, so that gamma_a = h_a - (h . X_d) b_ad
    hourglass_length_m: np.ndarray  # (n_el,) V (b : b): k_e / (scale mu)
    characteristic_length_m: np.ndarray  # (n_el,) volume / largest face area
    corner_tables: tuple          # per corner: (slots, n_nodes) elements, padded with n_el
    nodal_volume_m3: np.ndarray   # (n_groups, n_nodes) row-sum lumped volume of each group
    node_length_m: np.ndarray     # (n_nodes,) smallest characteristic length around each node

    @property
    def n_elements(self) -> int:
        return len(self.elements)


FACES = ((0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))


def geometry(mesh: HexMesh, n_groups: int) -> tuple[HexGeometry, np.ndarray]:
    """The geometry of `mesh` and the permutation that sorted its elements by group."""
    order = np.argsort(mesh.element_group, kind="stable")
    elements = np.asarray(mesh.elements)[order]
    groups = np.asarray(mesh.element_group)[order]
    bounds = np.searchsorted(groups, np.arange(n_groups + 1))
    slices = tuple((int(bounds[i]), int(bounds[i + 1])) for i in range(n_groups))
    X = np.asarray(mesh.nodes_m, np.float64)
    xe = X[elements]                                      # (n_el, 8, 3)

    _, centre = _shape_gradients(np.zeros(3))
    jac = np.einsum("ak,ead->edk", centre, xe)            # dX_d/dxi_k
    b = np.einsum("ak,ekd->ead", centre, np.linalg.inv(jac))  # (n_el, 8, 3)
    volume = np.zeros(len(elements))
    contrib = np.zeros((len(elements), 8))
    point_grad, point_volume = [], []
    for point in _GAUSS:
        values, grads = _shape_gradients(point)
        jac_q = np.einsum("ak,ead->edk", grads, xe)
        det = np.linalg.det(jac_q)
        if np.any(det <= 0):
            raise ValueError("hex mesh: an element has a non-positive Jacobian")
        volume += det
        contrib += values[None] * det[:, None]
        point_grad.append(np.einsum("ak,ekd->ead", grads, np.linalg.inv(jac_q)))
        point_volume.append(det)
    moment = np.einsum("ma,ead->emd", _MODES, xe)
    face_area = np.stack([np.linalg.norm(np.cross(xe[:, f[2]] - xe[:, f[0]],
                                                  xe[:, f[3]] - xe[:, f[1]]), axis=1) / 2
                          for f in FACES])
    length = volume / face_area.max(axis=0)

    n_nodes = len(X)
    tables = corner_tables(elements, n_nodes)
    nodal_volume = np.zeros((n_groups, n_nodes))
    for i, (lo, hi) in enumerate(slices):
        np.add.at(nodal_volume[i], elements[lo:hi].reshape(-1), contrib[lo:hi].reshape(-1))
    node_length = np.full(n_nodes, np.inf)
    np.minimum.at(node_length, elements.reshape(-1), np.repeat(length, 8))
    geom = HexGeometry(
        nodes_m=X, elements=elements, group_slices=slices,
        grad_n=np.ascontiguousarray(b.transpose(1, 2, 0)),
        point_grad_n=np.ascontiguousarray(np.stack(point_grad).transpose(2, 3, 0, 1)),
        point_volume_m3=np.stack(point_volume), volume_m3=volume,
        hourglass_moment_m=np.ascontiguousarray(moment.transpose(1, 2, 0)),
        hourglass_length_m=volume * np.sum(b ** 2, axis=(1, 2)),
        characteristic_length_m=length, corner_tables=tables,
        nodal_volume_m3=nodal_volume, node_length_m=node_length)
    return geom, order


def materialized(tree, index: jnp.ndarray):
    """`tree` (arrays (..., n_el)) computed once into memory: each array gathered by `index`,
    arange(n_el) given at run time (`element_index` of the run's parameters). XLA's CPU compiler
    drops `optimization_barrier` before it fuses, and then copied the deformation gradient and
    hourglass modes into each of the 24 corner forces that read them (measured: the thesis' case
    stepped twice as slowly); a gather by an index it cannot see is a boundary it keeps. The
    gather is exact: the values are the same bits. `index` None: `tree` as it is."""
    if index is None:
        return tree
    return jax.tree_util.tree_map(lambda x: jnp.take(x, index, axis=-1, mode="clip"), tree)


def corners(geom: HexGeometry, nodal: jnp.ndarray) -> tuple:
    """Nodal vectors (3, n_nodes) at the element corners: u[c][a], each (n_el,)."""
    return tuple(tuple(nodal[c, geom.elements[:, a]] for a in range(8)) for c in range(3))


def _corner_sum(values, weights):
    total = values[0] * weights[0]
    for a in range(1, 8):
        total = total + values[a] * weights[a]
    return total


def deformation_gradient(geom: HexGeometry, u_e) -> tuple:
    """F at the centres as nine components F[i][j], each (n_el,)."""
    b = geom.grad_n
    return tuple(tuple((1.0 if i == j else 0.0) + _corner_sum(u_e[i], b[:, j])
                       for j in range(3)) for i in range(3))


def point_deformation_gradients(geom: HexGeometry, u_e) -> tuple:
    """F at the 2x2x2 Gauss points: nine components, each (8, n_el)."""
    b = geom.point_grad_n
    return tuple(tuple((1.0 if i == j else 0.0) + sum(u_e[i][a][None] * b[a, j]
                                                       for a in range(8))
                       for j in range(3)) for i in range(3))


def fbar(geom: HexGeometry, u_e) -> tuple[tuple, jnp.ndarray]:
    """F-bar at the Gauss points (nine components (8, n_el)) and J at the centre (n_el,)."""
    F = point_deformation_gradients(geom, u_e)
    F0 = deformation_gradient(geom, u_e)
    J0 = determinant(F0, cofactor(F0))
    scale = cube_root(J0[None] / determinant(F, cofactor(F)))
    return tuple(tuple(F[i][j] * scale for j in range(3)) for i in range(3)), J0


def cofactor(F) -> tuple:
    """cof(F) = J F^-T, components [i][j]."""
    return tuple(tuple(F[(i + 1) % 3][(j + 1) % 3] * F[(i + 2) % 3][(j + 2) % 3]
                       - F[(i + 1) % 3][(j + 2) % 3] * F[(i + 2) % 3][(j + 1) % 3]
                       for j in range(3)) for i in range(3))


def determinant(F, cof) -> jnp.ndarray:
    return F[0][0] * cof[0][0] + F[0][1] * cof[0][1] + F[0][2] * cof[0][2]


def right_cauchy_green(F) -> tuple:
    """C = F^T F as (xx, yy, zz, xy, yz, zx)."""
    def c(i, j):
        return F[0][i] * F[0][j] + F[1][i] * F[1][j] + F[2][i] * F[2][j]
    return c(0, 0), c(1, 1), c(2, 2), c(0, 1), c(1, 2), c(2, 0)


def first_piola(F, S, cof, pressure) -> tuple:
    """P = F S + sigma_bv cof(F), S given as (xx, yy, zz, xy, yz, zx); components [i][J]."""
    s = ((S[0], S[3], S[5]), (S[3], S[1], S[4]), (S[5], S[4], S[2]))
    return tuple(tuple(F[i][0] * s[0][j] + F[i][1] * s[1][j] + F[i][2] * s[2][j]
                       + pressure * cof[i][j] for j in range(3)) for i in range(3))


def corner_forces(geom: HexGeometry, P, F, u_e, hourglass_n_m, index=None):
    """Corner forces f[c][a] (n_el,) of the stress P and the hourglass springs, and the hourglass
    energy (J, per element).

    With gamma_a = h_a - m_d b_ad (m = h . X), the hourglass displacement is
    q = sum_a h_a u_a - m_d (F - I)_d and its force sum_m k q_m gamma_ma: the stored geometry is
    m (12 numbers an element) instead of gamma (32), and h is +-1. `index`: see `materialized`."""
    b, moment, V = geom.grad_n, geom.hourglass_moment_m, geom.volume_m3
    signs = _MODES
    q = [[sum(float(signs[m, a]) * u_e[i][a] for a in range(8))
          - sum(moment[m, d] * (F[i][d] - (1.0 if i == d else 0.0)) for d in range(3))
          for m in range(4)] for i in range(3)]
    kq = [[hourglass_n_m * q[i][m] for m in range(4)] for i in range(3)]
    energy = 0.5 * sum(kq[i][m] * q[i][m] for i in range(3) for m in range(4))
    # stress and hourglass moments combined per (i, d); computed once into memory (fused into
    # each of the 24 corner forces they would be recomputed: `materialized`)
    T = [[P[i][d] * V - sum(kq[i][m] * moment[m, d] for m in range(4)) for d in range(3)]
         for i in range(3)]
    T, kq = materialized((T, kq), index)
    forces = tuple(tuple(T[i][0] * b[a, 0] + T[i][1] * b[a, 1] + T[i][2] * b[a, 2]
                         + sum(float(signs[m, a]) * kq[i][m] for m in range(4))
                         for a in range(8)) for i in range(3))
    return forces, energy


def gather_nodal(geom: HexGeometry, f_e) -> jnp.ndarray:
    """Sum corner vectors f_e[c][a] (n_el,) to nodes (3, n_nodes): gathers, no scatter."""
    return gather_corners(geom.corner_tables, f_e, 3, geom.grad_n.dtype)
