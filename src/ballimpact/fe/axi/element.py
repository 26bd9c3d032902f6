"""Axisymmetric 4-node quadrilateral, total Lagrangian: 2x2 Gauss points with F-bar ("full"), or
one point at the centre with hourglass control ("reduced", as ABAQUS/Explicit's CAX4R).

Coordinates are (r, z). At a Gauss point the deformation gradient is block diagonal: the in-plane
2x2 part and the hoop stretch r / R. Volumetric locking at Poisson ratios near 0.5 is avoided by
F-bar (de Souza Neto et al. 1996): each Gauss point's F is scaled so its determinant equals the
one at the element centre, Fbar = (J0 / J)^(1/3) F. Internal forces are the exact pull-back of
P : dFbar through the F-bar map (a JAX vector-Jacobian product), so they are consistent with the
stored energy and the energy balance closes.

Reduced integration evaluates F (and the hoop stretch) at the element centre only, which also
avoids volumetric locking. Its two spurious modes per direction (the hourglass modes) are held by
the Flanagan-Belytschko (1981) stiffness: with the hourglass vector gamma_a = h_a - (h . X_d)
dN_a/dX_d (h = (1, -1, 1, -1), orthogonal to every linear field, so rigid motions and homogeneous
strains give no hourglass force, also at large rotations in the total Lagrangian frame), the
generalised hourglass displacement q_i = gamma_a u_ia and the energy 0.5 k_e (q_r^2 + q_z^2),
k_e = scale x mu x V_e x (dN/dX : dN/dX) with the element's instantaneous shear modulus mu.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax
import numpy as np

from ..assembly import corner_tables, gather_nodal as gather_corners
from ...constitutive.fastmath import cube_root
from ...constitutive import Sym
from .mesh import AxisymmetricMesh

_G = 1.0 / np.sqrt(3.0)
# Four Gauss points (weight 1 each) and the centre (index 4, for F-bar and bulk viscosity).
POINTS = np.array([[-_G, -_G], [_G, -_G], [_G, _G], [-_G, _G], [0.0, 0.0]])
_CORNERS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])


def _shape(xi: float, eta: float) -> tuple[np.ndarray, np.ndarray]:
    n = 0.25 * (1 + _CORNERS[:, 0] * xi) * (1 + _CORNERS[:, 1] * eta)
    dn = 0.25 * np.stack([_CORNERS[:, 0] * (1 + _CORNERS[:, 1] * eta),
                          _CORNERS[:, 1] * (1 + _CORNERS[:, 0] * xi)], axis=1)
    return n, dn


@dataclass(frozen=True, eq=False)
class AxiGeometry:
    """Reference-configuration data of a mesh, elements sorted by layer (NumPy, float64).

    Arrays that the step uses are laid out components first and elements last, (..., n_el), so
    that every operation runs as a fused loop over elements (much faster on a CPU than small
    batched matrix products).
    """

    nodes_m: np.ndarray          # (n_nodes, 2) reference (r, z)
    elements: np.ndarray         # (n_el, 4), sorted by layer
    layer_slices: tuple[tuple[int, int], ...]
    shape_values: np.ndarray     # (5, 4) N_a at the points
    grad_n: np.ndarray           # (4, 2, 5, n_el) dN_a/dX_d at the points q (1/m)
    radius_m: np.ndarray         # (5, n_el) reference radius R at the points
    volume_weight_m3: np.ndarray  # (4, n_el) 2 pi R det(J) w at the Gauss points
    corner_tables: tuple         # per corner a: (slots, n_nodes) elements with the node as
                                 # corner a, padded with n_el
    nodal_volume_m3: np.ndarray  # (n_layers, n_nodes) row-sum lumped volume from each layer
    characteristic_length_m: np.ndarray  # (n_el,) area / longest diagonal
    surface_nodes: np.ndarray
    surface_length_m: np.ndarray  # (n_surface,) length of the element under each surface node
    surface_layer: int
    hourglass_vector: np.ndarray  # (4, n_el) Flanagan-Belytschko gamma_a (dimensionless)
    hourglass_length_m: np.ndarray  # (n_el,) V_e (dN/dX : dN/dX) at the centre: k_e / (scale mu)

    @property
    def n_elements(self) -> int:
        return len(self.elements)

    @property
    def element_volume_m3(self) -> np.ndarray:
        return self.volume_weight_m3.sum(axis=0)


def geometry(mesh: AxisymmetricMesh) -> AxiGeometry:
    order = np.argsort(mesh.element_layer, kind="stable")
    elements = np.asarray(mesh.elements)[order]
    layers = np.asarray(mesh.element_layer)[order]
    n_layers = len(mesh.layer_radii_m)
    bounds = np.searchsorted(layers, np.arange(n_layers + 1))
    slices = tuple((int(bounds[i]), int(bounds[i + 1])) for i in range(n_layers))

    X = np.asarray(mesh.nodes_m, dtype=np.float64)
    xe = X[elements]                                    # (n_el, 4, 2)
    values, grads = zip(*(_shape(*p) for p in POINTS))
    shape_values = np.stack(values)                     # (5, 4)
    dn_dxi = np.stack(grads)                            # (5, 4, 2)
    jac = np.einsum("qak,ead->eqdk", dn_dxi, xe)         # dX_d/dxi_k, (n_el, 5, 2, 2)
    det = np.linalg.det(jac)
    if np.any(det <= 0):
        raise ValueError("mesh has an element with a non-positive Jacobian")
    grad_n = np.einsum("qak,eqkd->eqad", dn_dxi, np.linalg.inv(jac))  # (n_el, 5, 4, 2)
    radius = np.einsum("qa,ea->eq", shape_values, xe[:, :, 0])
    weight = 2.0 * np.pi * radius[:, :4] * det[:, :4]

    n_nodes = len(X)
    tables = corner_tables(elements, n_nodes)

    nodal_volume = np.zeros((n_layers, n_nodes))
    contrib = np.einsum("qa,eq->ea", shape_values[:4], weight)  # row-sum lumping
    for i, (a, b) in enumerate(slices):
        np.add.at(nodal_volume[i], elements[a:b].reshape(-1), contrib[a:b].reshape(-1))

    area = 0.5 * np.abs(np.sum(xe[:, :, 0] * np.roll(xe[:, :, 1], -1, axis=1)
                               - np.roll(xe[:, :, 0], -1, axis=1) * xe[:, :, 1], axis=1))
    diagonal = np.maximum(np.linalg.norm(xe[:, 2] - xe[:, 0], axis=1),
                          np.linalg.norm(xe[:, 3] - xe[:, 1], axis=1))
    char_length = area / diagonal

    centre_grad = grad_n[:, 4]                          # (n_el, 4, 2) dN_a/dX_d at the centre
    h = np.array([1.0, -1.0, 1.0, -1.0])
    gamma = h[None] - np.einsum("ed,ead->ea", np.einsum("a,ead->ed", h, xe), centre_grad)
    volume = weight.sum(axis=1)
    hourglass_length = volume * np.sum(centre_grad ** 2, axis=(1, 2))

    surface = np.asarray(mesh.surface_nodes)
    # The element under each surface node: the smallest characteristic length among its elements.
    per_node = np.full(n_nodes, np.inf)
    np.minimum.at(per_node, elements.reshape(-1), np.repeat(char_length, 4))
    return AxiGeometry(nodes_m=X, elements=elements, layer_slices=slices,
                       shape_values=shape_values, grad_n=np.ascontiguousarray(
                           grad_n.transpose(2, 3, 1, 0)),
                       radius_m=np.ascontiguousarray(radius.T),
                       volume_weight_m3=np.ascontiguousarray(weight.T),
                       corner_tables=tables,
                       nodal_volume_m3=nodal_volume, characteristic_length_m=char_length,
                       surface_nodes=surface,
                       surface_length_m=per_node[surface], surface_layer=n_layers - 1,
                       hourglass_vector=np.ascontiguousarray(gamma.T),
                       hourglass_length_m=hourglass_length)


def element_values(geom: AxiGeometry, nodal: jax.Array) -> jax.Array:
    """Nodal vectors (2, n_nodes) at the element corners: (2, 4, n_el)."""
    return nodal[:, geom.elements.T]


def element_corners(geom: AxiGeometry, nodal: jax.Array) -> tuple:
    """Nodal vectors (2, n_nodes) at the element corners as ((r at corners 0..3), (z at corners
    0..3)), each (n_el,): separate arrays keep XLA's loops simple (no stacking)."""
    return tuple(tuple(nodal[c, geom.elements[:, a]] for a in range(4)) for c in range(2))


def corner_sum(values, weights):
    """sum_a values[a] weights[a] over the 4 corners (leading axis), written out: XLA fuses it
    into one elementwise loop, where a reduction over an axis of 4 runs as a slow reduce."""
    return values[0] * weights[0] + values[1] * weights[1] + values[2] * weights[2] \
        + values[3] * weights[3]


def deformation(geom: AxiGeometry, u_e: jax.Array) -> tuple[tuple, jax.Array]:
    """In-plane F as components (F_rr, F_rz, F_zr, F_zz), each (5, n_el), and the hoop stretch
    (5, n_el), from corner displacements (2, 4, n_el)."""
    ur, uz = u_e[0][:, None, :], u_e[1][:, None, :]       # (4, 1, n_el)
    gr, gz = geom.grad_n[:, 0], geom.grad_n[:, 1]          # (4, 5, n_el)
    F2 = (1.0 + corner_sum(ur, gr), corner_sum(ur, gz), corner_sum(uz, gr),
          1.0 + corner_sum(uz, gz))
    hoop = 1.0 + corner_sum(u_e[0][:, None, :], geom.shape_values.T[:, :, None]) / geom.radius_m
    return F2, hoop


def centre_deformation(geom: AxiGeometry, u_e) -> tuple[tuple, jax.Array]:
    """F at the element centre only (one-point integration): in-plane components and the hoop
    stretch, each (1, n_el), from corner displacements u_e[c][a] (`element_corners`)."""
    ur, uz = u_e[0], u_e[1]                                # (4, n_el)
    gr, gz = geom.grad_n[:, 0, 4], geom.grad_n[:, 1, 4]    # (4, n_el)
    F2 = (1.0 + corner_sum(ur, gr), corner_sum(ur, gz), corner_sum(uz, gr),
          1.0 + corner_sum(uz, gz))
    hoop = 1.0 + 0.25 * (ur[0] + ur[1] + ur[2] + ur[3]) / geom.radius_m[4]
    return tuple(f[None] for f in F2), hoop[None]


def hourglass(geom: AxiGeometry, u_e, stiffness_n_m: jax.Array):
    """Hourglass corner forces ((f_r at corners 0..3), (f_z at corners 0..3)) and energy (J, per
    element) of
    corner displacements u_e[c][a] with the per-element stiffness k_e (n_el,) (N/m, the 2 pi of
    the ring included)."""
    gamma = geom.hourglass_vector
    q = [corner_sum(u_e[c], gamma) for c in range(2)]
    kq = [stiffness_n_m * q[c] for c in range(2)]
    energy = 0.5 * (kq[0] * q[0] + kq[1] * q[1])
    return tuple(tuple(kq[c] * gamma[a] for a in range(4)) for c in range(2)), energy


def fbar(F2: tuple, Fh: jax.Array) -> tuple[tuple, jax.Array, jax.Array]:
    """F-bar at the Gauss points: components (4, n_el) each, hoop (4, n_el), J (5, n_el)."""
    J = (F2[0] * F2[3] - F2[1] * F2[2]) * Fh
    scale = cube_root(J[4] / J[:4])
    return tuple(f[:4] * scale for f in F2), Fh[:4] * scale, J


def right_cauchy_green(Fb2: tuple, Fbh: jax.Array) -> Sym:
    """C of a block-diagonal F, as `Sym` components (r, z, hoop)."""
    frr, frz, fzr, fzz = Fb2
    return Sym(frr * frr + fzr * fzr, frz * frz + fzz * fzz, Fbh * Fbh, frr * frz + fzr * fzz)


def first_piola(Fb2: tuple, Fbh, S: tuple, pressure_j) -> tuple[tuple, jax.Array]:
    """P = Fbar S + p J Fbar^-T: in-plane components and hoop. S = (S_rr, S_zz, S_hoop, S_rz);
    `pressure_j` = sigma_bv J (bulk viscosity as a Cauchy pressure)."""
    frr, frz, fzr, fzz = Fb2
    s_rr, s_zz, s_hh, s_rz = S
    p = pressure_j / (frr * fzz - frz * fzr)
    return ((frr * s_rr + frz * s_rz + p * fzz, frr * s_rz + frz * s_zz - p * fzr,
             fzr * s_rr + fzz * s_rz - p * frz, fzr * s_rz + fzz * s_zz + p * frr),
            Fbh * s_hh + pressure_j / Fbh)


def gather_nodal(geom: AxiGeometry, f_e) -> jax.Array:
    """Sum corner vectors to nodes (2, n_nodes): gathers, no scatter. `f_e[c][a]` is component c
    at corner a of every element (n_el,): an array (2, 4, n_el) or nested sequences of arrays."""
    return gather_corners(geom.corner_tables, f_e, 2, geom.grad_n.dtype)


def centre_forces(geom: AxiGeometry, P2: tuple, Ph, volume_m3) -> tuple:
    """Corner forces of one-point elements, ((f_r at corners 0..3), (f_z at corners 0..3)), each
    (n_el,): f_ia = V (P_iJ dN_a/dX_J + delta_ir P_hoop N_a / R) at the centre, written out (the
    same as the vector-Jacobian product of `centre_deformation`, without its stacking)."""
    prr, prz, pzr, pzz = (p[0] * volume_m3 for p in P2)
    hoop = Ph[0] * volume_m3 * 0.25 / geom.radius_m[4]
    br, bz = geom.grad_n[:, 0, 4], geom.grad_n[:, 1, 4]
    return (tuple(prr * br[a] + prz * bz[a] + hoop for a in range(4)),
            tuple(pzr * br[a] + pzz * bz[a] for a in range(4)))
