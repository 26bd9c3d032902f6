"""A bat's normal modes (`modes`) and the modal model they give at any point (`BatModes`).

Supports: "free" (free-free, as a bat is tested and, to a good approximation, as it behaves in
the ~1 ms of a collision: Russell, "Vibrational modes of a baseball bat", and Nathan 2000), with
its two rigid-body modes (translation and rotation about the centre of mass) at zero frequency;
"pivot": w = 0 at `pivot_m` (a node is put there; the section turns freely), with one rigid
mode, the rotation about the pivot. `grip`: the hands as translational springs and dampers at
points of the handle; with a stiffness the rigid modes become low-frequency modes on the hands.

Without a grip stiffness the rigid-body vectors are built exactly and the flexural modes solved
in their mass-orthogonal complement (scipy.linalg.eigh): the rigid frequencies are then the
Rayleigh quotients of the exact rigid motions (~0), and the flexural modes exactly orthogonal to
them. All vectors are mass-normalised (Phi^T M Phi = I), so a mode's modal mass is 1 and its
effective mass at x is 1 / w_n(x)^2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
from threadpoolctl import threadpool_limits

from ..checks import check_integer, check_range, shown
from ..errors import InputError
from .beam import DEFAULT_ELEMENTS, BeamModel, beam_model
from .spec import BatSpec, load_bat

SUPPORTS = ("free", "pivot")


@dataclass(frozen=True)
class Grip:
    """The hands: a translational spring (N/m) and dashpot (N s/m) at each of `positions_m`
    (from the knob end). The default positions (0.05 and 0.15 m) are typical, not measured."""

    positions_m: tuple[float, ...] = (0.05, 0.15)
    stiffness_n_m: float = 0.0
    damping_n_s_m: float = 0.0

    def checked(self, bat: BatSpec) -> Grip:
        positions = tuple(check_range(f"grip.positions_m[{i}]", x, 0.0, bat.length_m, unit="m")
                          for i, x in enumerate(self.positions_m))
        return Grip(positions, check_range("grip.stiffness_n_m", self.stiffness_n_m, 0.0),
                    check_range("grip.damping_n_s_m", self.damping_n_s_m, 0.0))


@dataclass(frozen=True)
class BatModes:
    """Frequencies and mass-normalised mode shapes of a bat, lowest first (rigid modes first).

    `vectors` (dofs, count): [w0, theta0, w1, theta1, ...] per mode; `beam` holds the nodes,
    K and M; `damping` the grip's dashpots (dofs, dofs). Evaluate the shapes anywhere with
    `deflection`, `slope` (dw/dx), `rotation` (the section's theta), `effective_mass_kg`."""

    bat: BatSpec
    support: str
    pivot_m: float | None
    grip: Grip | None
    beam: BeamModel
    frequencies_hz: np.ndarray
    vectors: np.ndarray
    rigid_count: int
    damping: np.ndarray

    @property
    def count(self) -> int:
        return self.frequencies_hz.size

    @property
    def nodes_m(self) -> np.ndarray:
        return self.beam.nodes_m

    @property
    def omega_rad_s(self) -> np.ndarray:
        return 2.0 * np.pi * self.frequencies_hz

    @property
    def deflections(self) -> np.ndarray:
        """w of each mode at the nodes, (count, nodes)."""
        return self.vectors[0::2].T

    @property
    def rotations(self) -> np.ndarray:
        """theta of each mode at the nodes, (count, nodes)."""
        return self.vectors[1::2].T

    @property
    def modal_masses_kg(self) -> np.ndarray:
        """diag(Phi^T M Phi): 1 for mass-normalised vectors (kg for w in m)."""
        return np.einsum("im,ij,jm->m", self.vectors, self.beam.mass, self.vectors)

    @property
    def flexural_frequencies_hz(self) -> np.ndarray:
        return self.frequencies_hz[self.rigid_count:]

    @property
    def damping_ratios(self) -> np.ndarray:
        """Each mode's ratio from the material's loss factor (eta / 2; 0 for rigid modes)."""
        out = np.full(self.count, self.bat.loss_factor / 2.0)
        out[:self.rigid_count] = 0.0
        return out

    def modal_damping(self) -> np.ndarray:
        """The modal damping matrix (count, count): diag(2 zeta omega) + Phi^T C Phi (the
        grip's dashpots, which couple the modes)."""
        return (np.diag(2.0 * self.damping_ratios * self.omega_rad_s)
                + self.vectors.T @ self.damping @ self.vectors)

    def deflection(self, x_m) -> np.ndarray:
        """Each mode's deflection at x: (count, len(x)), per kg^(1/2)."""
        return self.beam.interpolate(self.vectors, x_m)[0]

    def slope(self, x_m) -> np.ndarray:
        """Each mode's slope dw/dx at x: (count, len(x))."""
        return self.beam.interpolate(self.vectors, x_m)[1]

    def rotation(self, x_m) -> np.ndarray:
        """Each mode's section rotation theta at x (slope minus shear strain)."""
        return self.beam.interpolate(self.vectors, x_m)[2]

    def impact_point(self, x_m: float) -> dict[str, np.ndarray | float]:
        """The modal model at one point x (from the knob end), each entry (count,): natural
        frequencies (Hz), damping ratios, and each mode's deflection, slope dw/dx, section
        rotation and effective mass there. With mass-normalised modes the bat's response to a
        force F(t) at x is w(x, t) = sum_n w_n(x) q_n(t), q_n'' + 2 zeta_n omega_n q_n' +
        omega_n^2 q_n = w_n(x) F(t) (no grip dashpots; with them use `modal_damping`)."""
        w, dw, theta = (a[:, 0] for a in self.beam.interpolate(self.vectors, [x_m]))
        with np.errstate(divide="ignore"):
            m_eff = 1.0 / w ** 2
        return {"x_m": float(x_m), "frequencies_hz": self.frequencies_hz,
                "damping_ratios": self.damping_ratios, "deflection": w, "slope": dw,
                "rotation": theta, "effective_mass_kg": m_eff}

    def effective_mass_kg(self, x_m) -> np.ndarray:
        """Each mode's effective mass at x, 1 / w(x)^2 (inf at a node of the mode)."""
        w = self.deflection(x_m)
        with np.errstate(divide="ignore"):
            return 1.0 / w ** 2


def _rigid_vectors(nodes: np.ndarray, about_m: float, translation: bool) -> np.ndarray:
    rotation = np.zeros(2 * nodes.size)
    rotation[0::2], rotation[1::2] = nodes - about_m, 1.0
    if not translation:
        return rotation[:, None]
    shift = np.zeros_like(rotation)
    shift[0::2] = 1.0
    return np.stack([shift, rotation], axis=1)


def _m_orthonormal(r: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Columns of r made orthonormal under m (Gram-Schmidt, in order)."""
    out = []
    for v in r.T:
        for u in out:
            v = v - (u @ m @ v) * u
        out.append(v / np.sqrt(v @ m @ v))
    return np.stack(out, axis=1)


def _solve(k, m, rigid: np.ndarray | None, count: int):
    """Eigenpairs (lowest `count`) of K v = w^2 M v; `rigid` (M-orthonormal) first."""
    if rigid is None or rigid.shape[1] == 0:
        lam, vec = scipy.linalg.eigh(k, m, subset_by_index=[0, count - 1])
        return lam, vec
    r = rigid.shape[1]
    lam_r = np.einsum("ir,ij,jr->r", rigid, k, rigid)
    if count == r:
        return lam_r, rigid
    q, _ = np.linalg.qr(m @ rigid, mode="complete")
    t = q[:, r:]  # R^T M T = 0
    kt, mt = t.T @ k @ t, t.T @ m @ t
    lam, y = scipy.linalg.eigh((kt + kt.T) / 2, (mt + mt.T) / 2,
                               subset_by_index=[0, count - r - 1])
    return np.concatenate([lam_r, lam]), np.concatenate([rigid, t @ y], axis=1)


def modes(bat, support: str = "free", pivot_m: float | None = None, grip: Grip | None = None,
          count: int = 8, elements: int = DEFAULT_ELEMENTS) -> BatModes:
    """The lowest `count` modes of a bat (anything `load_bat` takes), rigid modes included.

    support "free" or "pivot" (w = 0 at `pivot_m`, from the knob end); `grip` adds the hands'
    springs and dashpots. `elements`: the mesh's element count (`beam.DEFAULT_ELEMENTS`)."""
    bat = load_bat(bat)
    if support not in SUPPORTS:
        raise InputError(f"support = {shown(support)}: allowed {', '.join(SUPPORTS)}")
    if support == "pivot":
        if pivot_m is None:
            raise InputError("pivot_m: needed for support = 'pivot' (the pivot's distance "
                             "from the knob end, m)")
        pivot_m = check_range("pivot_m", pivot_m, 0.0, bat.length_m, unit="m")
    elif pivot_m is not None:
        raise InputError(f"pivot_m = {shown(pivot_m)}: only for support = 'pivot'")
    elements = check_integer("elements", elements, 4)
    grip = grip.checked(bat) if grip is not None else None
    extra = ([pivot_m] if pivot_m is not None else []) + list(grip.positions_m if grip else [])
    beam = beam_model(bat, elements, extra)
    k, m = beam.stiffness.copy(), beam.mass
    c = np.zeros_like(k)
    if grip is not None:
        for x in grip.positions_m:
            i = 2 * beam.node_index(x)
            k[i, i] += grip.stiffness_n_m
            c[i, i] += grip.damping_n_s_m
    keep = np.ones(beam.dofs, dtype=bool)
    if pivot_m is not None:
        keep[2 * beam.node_index(pivot_m)] = False
    count = check_integer("count", count, 1, int(keep.sum()), note="modes")
    rigid = None
    if grip is None or grip.stiffness_n_m == 0.0:
        # free: translation, then rotation (made about the centre of mass by Gram-Schmidt)
        rigid = _rigid_vectors(beam.nodes_m, 0.0 if pivot_m is None else pivot_m,
                               translation=pivot_m is None)
        rigid = _m_orthonormal(rigid[keep], m[np.ix_(keep, keep)])
        rigid = rigid[:, :count]
    with threadpool_limits(limits=1, user_api="blas"):  # small dense matrices: threads cost
        lam, vec = _solve(k[np.ix_(keep, keep)], m[np.ix_(keep, keep)], rigid, count)
    vectors = np.zeros((beam.dofs, count))
    vectors[keep] = vec
    for j in range(count):  # sign: the barrel end (or the largest deflection) moves positive
        w = vectors[0::2, j]
        ref = w[-1] if abs(w[-1]) > 1e-6 * np.abs(w).max() else w[np.argmax(np.abs(w))]
        vectors[:, j] *= np.sign(ref) or 1.0
    frequencies = np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * np.pi)
    return BatModes(bat, support, pivot_m, grip, beam, frequencies, vectors,
                    0 if rigid is None else rigid.shape[1], c)
