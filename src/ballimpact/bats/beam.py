"""The bat as a Timoshenko beam: the finite-element mesh along the axis, the element matrices,
their assembly, and the interpolation of a nodal vector at any x.

Each node carries the transverse deflection w (m) and the section's rotation theta (rad),
ordered [w0, theta0, w1, theta1, ...]; shear strain gamma = dw/dx - theta.

Elements: 2 nodes, the interdependent interpolation of Friedman & Kosmatka (1993, "An improved
two-node Timoshenko beam finite element", Computers & Structures 47:473-481): cubic w, quadratic
theta, tied by phi = 12 EI / (k G A h^2) so that they solve the static Timoshenko equations;
the stiffness is the exact one of a uniform element (no shear locking, Euler-Bernoulli's
Hermite element as phi -> 0). The mass is consistent with the same functions: translational
rho A and rotary rho I. Both are integrated by 4-point Gauss-Legendre (exact: the integrands are
of degree 6 at most). Section properties of an element are those at its mid-point
(`section.sections`).

The mesh puts a node at every breakpoint of the profile (and the blade's start), at any
`extra_nodes_m` (a pivot, the hands), and splits each interval between them into equal
elements no longer than length / `elements`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .section import sections
from .spec import BatSpec

#: elements along the bat by default (element length about L / 200: 4.3 mm on a 34-in bat)
DEFAULT_ELEMENTS = 200

_GAUSS_POINTS, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(4)


def mesh_nodes(bat: BatSpec, elements: int = DEFAULT_ELEMENTS, extra_nodes_m=()) -> np.ndarray:
    """Node positions from the knob end (m): breakpoints and `extra_nodes_m` kept, intervals
    split into equal elements of at most length / `elements`."""
    fixed = np.unique(np.concatenate([bat.breakpoints_m(), np.asarray(extra_nodes_m, float)]))
    fixed = fixed[np.concatenate([[True], np.diff(fixed) > 1e-9 * bat.length_m])]
    h = bat.length_m / elements
    parts = [np.linspace(a, b, max(1, int(np.ceil((b - a) / h - 1e-9))) + 1)[:-1]
             for a, b in zip(fixed[:-1], fixed[1:])]
    return np.concatenate([*parts, fixed[-1:]])


def shape_functions(xi, h, phi):
    """Interdependent interpolation on an element of length h with parameter phi, at local
    coordinates xi in [0, 1] (arrays broadcast together). Returns (N, dN/dx, T, dT/dx), each of
    shape (..., 4): w = N . u and theta = T . u for the element's u = [w1, th1, w2, th2]."""
    xi, h, phi = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (xi, h, phi)))
    c = 1.0 / (1.0 + phi)
    x2, x3 = xi ** 2, xi ** 3
    n = c[..., None] * np.stack([
        2 * x3 - 3 * x2 - phi * xi + 1 + phi,
        h * (x3 - (2 + phi / 2) * x2 + (1 + phi / 2) * xi),
        -(2 * x3 - 3 * x2 - phi * xi),
        h * (x3 - (1 - phi / 2) * x2 - phi / 2 * xi)], axis=-1)
    dn = c[..., None] * np.stack([
        (6 * x2 - 6 * xi - phi) / h,
        3 * x2 - (4 + phi) * xi + 1 + phi / 2,
        -(6 * x2 - 6 * xi - phi) / h,
        3 * x2 - (2 - phi) * xi - phi / 2], axis=-1)
    t = c[..., None] * np.stack([
        6 * (x2 - xi) / h,
        3 * x2 - (4 + phi) * xi + 1 + phi,
        -6 * (x2 - xi) / h,
        3 * x2 - (2 - phi) * xi], axis=-1)
    dt = c[..., None] * np.stack([
        6 * (2 * xi - 1) / h ** 2,
        (6 * xi - 4 - phi) / h,
        -6 * (2 * xi - 1) / h ** 2,
        (6 * xi - 2 + phi) / h], axis=-1)
    return n, dn, t, dt


def element_matrices(h, ei, kga, rho_a, rho_i):
    """Stiffness and mass of elements (arrays of length e) -> two arrays (e, 4, 4)."""
    h, ei, kga, rho_a, rho_i = (np.atleast_1d(np.asarray(a, dtype=float))
                                for a in (h, ei, kga, rho_a, rho_i))
    phi = 12.0 * ei / (kga * h ** 2)
    xi = (_GAUSS_POINTS + 1.0) / 2.0
    w = _GAUSS_WEIGHTS / 2.0
    n, dn, t, dt = shape_functions(xi[None, :], h[:, None], phi[:, None])  # (e, q, 4)
    gamma = dn - t
    jac = (h[:, None] * w[None, :])  # dx = h dxi
    k = (np.einsum("eq,eqi,eqj->eij", jac * ei[:, None], dt, dt)
         + np.einsum("eq,eqi,eqj->eij", jac * kga[:, None], gamma, gamma))
    m = (np.einsum("eq,eqi,eqj->eij", jac * rho_a[:, None], n, n)
         + np.einsum("eq,eqi,eqj->eij", jac * rho_i[:, None], t, t))
    return k, m


@dataclass(frozen=True)
class BeamModel:
    """The assembled beam: nodes (m), stiffness K and mass M (dense, 2 dofs a node), and per
    element its length and phi (for interpolation)."""

    bat: BatSpec
    nodes_m: np.ndarray
    stiffness: np.ndarray
    mass: np.ndarray
    element_phi: np.ndarray

    @property
    def dofs(self) -> int:
        return 2 * self.nodes_m.size

    def node_index(self, x_m: float) -> int:
        """The node at x (which must be one: a pivot, a hand, a breakpoint)."""
        i = int(np.argmin(np.abs(self.nodes_m - x_m)))
        if abs(self.nodes_m[i] - x_m) > 1e-9 * self.bat.length_m:
            raise ValueError(f"no node at x = {x_m:g} m")
        return i

    def interpolate(self, vectors: np.ndarray, x_m) -> tuple[np.ndarray, np.ndarray,
                                                               np.ndarray]:
        """Deflection w, slope dw/dx and section rotation theta of nodal vectors (dofs, ...)
        at points x (clipped to the bat) with the element's own shape functions: each of
        shape (..., len(x)), the vectors' trailing axes first."""
        vectors = np.asarray(vectors, dtype=float)
        x = np.clip(np.atleast_1d(np.asarray(x_m, dtype=float)), 0.0, self.bat.length_m)
        nodes = self.nodes_m
        e = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, nodes.size - 2)
        h = nodes[e + 1] - nodes[e]
        n, dn, t, _ = shape_functions((x - nodes[e]) / h, h, self.element_phi[e])  # (p, 4)
        idx = 2 * e[:, None] + np.arange(4)[None, :]  # (p, 4)
        u = np.moveaxis(vectors[idx], (0, 1), (-2, -1))  # (..., p, 4)
        return ((u * n).sum(-1), (u * dn).sum(-1), (u * t).sum(-1))


def beam_model(bat: BatSpec, elements: int = DEFAULT_ELEMENTS, extra_nodes_m=()) -> BeamModel:
    """Mesh the bat and assemble K and M (no supports: a free beam)."""
    nodes = mesh_nodes(bat, elements, extra_nodes_m)
    h = np.diff(nodes)
    s = sections(bat, (nodes[:-1] + nodes[1:]) / 2.0)
    ei, kga = s.bending_stiffness_n_m2, s.shear_stiffness_n
    ke, me = element_matrices(h, ei, kga, s.mass_per_length_kg_m, s.rotary_inertia_kg_m)
    dofs = 2 * nodes.size
    idx = 2 * np.arange(h.size)[:, None] + np.arange(4)[None, :]
    rows = np.broadcast_to(idx[:, :, None], ke.shape)
    cols = np.broadcast_to(idx[:, None, :], ke.shape)
    k = np.zeros((dofs, dofs))
    m = np.zeros((dofs, dofs))
    np.add.at(k, (rows, cols), ke)
    np.add.at(m, (rows, cols), me)
    return BeamModel(bat, nodes, k, m, 12.0 * ei / (kga * h ** 2))
