"""Oblique impact of an elastic sphere on a rigid plane with tangential compliance: the reference
for the gripping regime (Maw, Barber & Fawcett 1976, 1981).

The sphere moves as a rigid body outside a small contact. Normally the contact is Hertz's;
tangentially it is Mindlin and Deresiewicz's, with Coulomb friction acting locally: the rim of
the contact slips while its centre sticks, and the traction follows the whole loading history
(loading, unloading, reversal) as in Maw et al.'s solution. That history is computed exactly by
the method of dimensionality reduction (Popov & Hess, *Method of Dimensionality Reduction in
Contact Mechanics and Friction*, Springer 2015, chapters 3 and 5; Hess' proof covers any
history of normal and tangential loading under Mindlin's uncoupling assumption, the one Maw et
al. make): the contact equals a bed of independent springs along a line, at x with normal
stiffness E* dx and tangential stiffness G* dx, pressed by the profile x^2 / R, each spring
sticking until its tangential force reaches mu times its normal force. Springs that enter the
contact start unstrained; springs that leave it lose their strain.

Moduli for an elastic sphere (E, nu) on a rigid plane: E* = E / (1 - nu^2) and
G* = 4 G / (2 - nu) (G = E / (2 (1 + nu))), so the bed's stuck tangential stiffness 2 a G* is
Mindlin's 8 G a / (2 - nu), and G* / E* = 2 (1 - nu) / (2 - nu); on an elastic plane the
compliances of the two bodies add. Like Maw et al.'s, the theory leaves out the coupling of
normal pressure and tangential displacement (Dundurs' beta = 0: identical materials, or
nu = 0.5 on a rigid plane); a sphere of nu < 0.5 on a rigid plane has beta = (1 - 2 nu) /
(2 (1 - nu)) and its contact slips radially under the normal load alone (docs/oblique.md).

The equations of motion are integrated with velocity Verlet; the springs are advanced by the
contact point's displacement over each step (its velocity v_x - w R at the half step), then
returned to the Coulomb limit. Resolution (`springs`, `steps`) sets the error: halving both
changes the normalised results by less than 1e-3 at the defaults
(`tests/oblique/test_elastic_reference.py`).

Results are normalised as in `rigid_body`: incidence Psi = 2 (v_x - w R) / (mu (1 + e_n) v_n),
rebound spin Omega = w' R / (mu (1 + e_n) v_n). For Psi above the gross-sliding limit the
tangential impulse is mu times the normal one and the results are the rigid-body lines.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..checks import check_range
from ..errors import InputError
from ..closedform import hertz_impact
from .rigid_body import HOMOGENEOUS_K2

@dataclass(frozen=True)
class ElasticSphere:
    """A homogeneous elastic sphere: radius (m), mass (kg), Young's modulus (Pa), Poisson's
    ratio, and k^2 = I / (m R^2) (0.4 for uniform density), hitting a plane that is rigid or,
    with `plane_youngs_modulus_pa`, an elastic half-space of that modulus and
    `plane_poissons_ratio`."""

    radius_m: float
    mass_kg: float
    youngs_modulus_pa: float
    poissons_ratio: float
    k2: float = HOMOGENEOUS_K2
    plane_youngs_modulus_pa: float | None = None
    plane_poissons_ratio: float = 0.3

    def __post_init__(self) -> None:
        for name, low, high in (("radius_m", 0.0, 10.0), ("mass_kg", 0.0, 1e4),
                                ("youngs_modulus_pa", 0.0, 1e13), ("poissons_ratio", -1.0, 0.5),
                                ("k2", 0.0, 1.0), ("plane_youngs_modulus_pa", 0.0, 1e13),
                                ("plane_poissons_ratio", -1.0, 0.5)):
            value = getattr(self, name)
            if value is None:
                continue
            if not (np.isfinite(value) and low < value <= high):
                raise InputError(f"{name} = {value!r}: allowed range ({low:g}, {high:g}]")
        # unit slips a range cannot catch: MPa given as Pa, grams as kg, millimetres as metres
        for name in ("youngs_modulus_pa", "plane_youngs_modulus_pa"):
            value = getattr(self, name)
            if value is not None and value < 1e4:
                raise InputError(f"{name} = {value!r}: below 10 kPa, softer than any ball or "
                                 f"surface; looks like MPa given as Pa (use {value * 1e6:g})")
        density = self.mass_kg / (4.0 / 3.0 * np.pi * self.radius_m ** 3)
        if not 10.0 <= density <= 3e4:
            raise InputError(f"mass_kg = {self.mass_kg!r}, radius_m = {self.radius_m!r}: density "
                             f"{density:.4g} kg/m^3, outside [10, 30000]; grams given as kg or "
                             "millimetres as metres?")

    def _bodies(self):
        yield self.youngs_modulus_pa, self.poissons_ratio
        if self.plane_youngs_modulus_pa is not None:
            yield self.plane_youngs_modulus_pa, self.plane_poissons_ratio

    @property
    def contact_modulus_pa(self) -> float:
        """E* (Pa): 1 / E* = sum over the bodies of (1 - nu^2) / E."""
        return 1.0 / sum((1.0 - nu ** 2) / e for e, nu in self._bodies())

    @property
    def tangential_modulus_pa(self) -> float:
        """The bed's tangential modulus G* (Pa): 1 / G* = sum over the bodies of
        (2 - nu) / (4 G), G = E / (2 (1 + nu))."""
        return 1.0 / sum((2.0 - nu) * 2.0 * (1.0 + nu) / (4.0 * e) for e, nu in self._bodies())


def hertz_normal_impact(sphere: ElasticSphere, normal_speed_m_s: float) -> tuple[float, float]:
    """Hertz's (largest deflection m, contact time s) of the normal motion."""
    deflection, _, contact_time = hertz_impact(sphere.contact_modulus_pa, 0.0, sphere.radius_m,
                                               sphere.mass_kg, normal_speed_m_s)
    return deflection, contact_time


def tangential_force_n(sphere: ElasticSphere, deflection_m, tangential_displacement_m,
                       friction: float, springs: int = 2000) -> np.ndarray:
    """Tangential force (N) along a path of normal deflections (m) and tangential displacements
    of the sphere (m) from the first touch (arrays of one length, or a deflection held
    constant): Mindlin and Deresiewicz's history rules computed on the spring bed (for tests
    against their closed forms, e.g. Cattaneo's loading and Masing's unloading curves)."""
    d_t = np.atleast_1d(np.asarray(tangential_displacement_m, float))
    delta = np.broadcast_to(np.asarray(deflection_m, float), d_t.shape)
    x, dx = _bed(np.sqrt(sphere.radius_m * np.max(delta)), springs)
    ratio = friction * sphere.contact_modulus_pa / sphere.tangential_modulus_pa
    u, previous, forces = np.zeros(springs), 0.0, []
    for depth, displacement in zip(delta, d_t):
        u, _ = _bed_step(u, depth - x * x / sphere.radius_m, displacement - previous, ratio)
        previous = displacement
        forces.append(2.0 * sphere.tangential_modulus_pa * dx * np.sum(u))
    return np.array(forces)


def _bed_step(u, gap, increment, ratio):
    """Advance the springs' tangential displacements u (..., springs) by the contact point's
    displacement `increment` (m; (...,) or scalar) at the gaps `gap` (m, > 0 in contact):
    springs out of contact are unstrained, the others stick up to the Coulomb limit
    ratio x gap (ratio = mu E* / G*). Returns the new u and each spring's slip (m)."""
    touching = gap > 0.0
    trial = np.where(touching, u + np.asarray(increment)[..., None], 0.0)
    limit = ratio * np.maximum(gap, 0.0)
    new = np.clip(trial, -limit, limit)
    return new, trial - new


def _bed(half_width_m: float, springs: int) -> tuple[np.ndarray, float]:
    dx = half_width_m / springs
    return (np.arange(springs) + 0.5) * dx, dx


def oblique_impact(sphere: ElasticSphere, normal_speed_m_s: float, tangential_speed_m_s,
                   spin_rad_s, friction: float, springs: int = 1000, steps: int = 4000,
                   history: bool = False) -> dict:
    """Rebound of the elastic sphere hitting its plane (`ElasticSphere`: rigid or elastic) at
    normal speed `normal_speed_m_s`
    (m/s, > 0 toward the plane) with tangential speeds `tangential_speed_m_s` (m/s, array) and
    spins `spin_rad_s` (rad/s, topspin positive: the contact point moves at v_x - w R), under
    Coulomb friction `friction`. The normal motion is Hertz's for every condition; one spring bed
    per condition.

    Returns arrays (one value per condition): `v_x_m_s`, `spin_rad_s`, `v_n_m_s` (the rebound
    normal speed), `normal_cor`, `tangential_cor` (v_x' / v_x), `contact_point_cor`
    (-(v_x' - w' R) / (v_x - w R): positive when the contact point's velocity reversed), `psi`,
    `normalised_spin`, `frictional_dissipation_j`, `energy_error` (of the tangential motion,
    relative to its initial kinetic energy) and, with `history`, `time_s` (steps,),
    `normal_force_n` (steps,), `tangential_force_n` (steps, conditions), `slip_velocity_m_s`
    (contact-point velocity, (steps, conditions)) and `stick_fraction` (the stuck share of the
    contact radius, (steps, conditions)).
    """
    check_range("normal_speed_m_s", normal_speed_m_s, 0.0, low_open=True, unit="m/s")
    check_range("friction", friction, 0.0, low_open=True)
    v_x0 = np.atleast_1d(np.asarray(tangential_speed_m_s, float))
    w0 = np.broadcast_to(np.asarray(spin_rad_s, float), v_x0.shape).copy()
    R, m, k2 = sphere.radius_m, sphere.mass_kg, sphere.k2
    e_star, g_star = sphere.contact_modulus_pa, sphere.tangential_modulus_pa
    hertz = 4.0 / 3.0 * e_star * np.sqrt(R)
    delta_max, contact_time = hertz_normal_impact(sphere, normal_speed_m_s)
    x, dx = _bed(1.02 * np.sqrt(R * delta_max), springs)
    profile = x * x / R
    dt = contact_time / steps
    mobility = (1.0 + 1.0 / k2) / m           # d(slip velocity)/dt per unit tangential force
    ratio = friction * e_star / g_star

    delta, v_n = 0.0, float(normal_speed_m_s)  # v_n: approach velocity
    f_n = 0.0
    u = np.zeros((v_x0.size, springs))
    f_t = np.zeros(v_x0.size)
    impulse = np.zeros(v_x0.size)
    dissipated = np.zeros(v_x0.size)
    slip = v_x0 - w0 * R
    rows = []
    for _ in range(4 * steps):
        v_n_half = v_n - 0.5 * dt * f_n / m
        slip_half = slip - 0.5 * dt * mobility * f_t
        delta += dt * v_n_half
        if delta <= 0.0:
            break
        f_n_new = hertz * delta ** 1.5
        v_n = v_n_half - 0.5 * dt * f_n_new / m
        gap = delta - profile
        u, slipped = _bed_step(u, gap, dt * slip_half, ratio)
        # work of the Coulomb forces (at the limit) on the slip
        dissipated += 2.0 * g_star * dx * np.sum(np.abs(u * slipped), axis=1)
        f_t_new = 2.0 * g_star * dx * np.sum(u, axis=1)
        impulse += 0.5 * dt * (f_t + f_t_new)
        slip = slip_half - 0.5 * dt * mobility * f_t_new
        f_n, f_t = f_n_new, f_t_new
        if history:
            touching = gap > 0.0
            contact = max(np.count_nonzero(touching), 1)
            stuck = np.count_nonzero(touching & (slipped == 0.0), axis=1)
            rows.append((f_n, f_t.copy(), slip.copy(), stuck / contact))
    else:
        raise RuntimeError("the sphere did not leave the plane within 4 contact times")
    v_x = v_x0 - impulse / m
    w = w0 + impulse * R / (k2 * m * R * R)
    e_n = -v_n / normal_speed_m_s
    ke0 = 0.5 * m * (v_x0 ** 2 + k2 * R * R * w0 ** 2)
    ke = 0.5 * m * (v_x ** 2 + k2 * R * R * w ** 2)
    stored = 0.5 * 2.0 * g_star * dx * np.sum(u * u, axis=1)
    scale = friction * (1.0 + e_n) * normal_speed_m_s
    with np.errstate(divide="ignore", invalid="ignore"):
        out = {"v_x_m_s": v_x, "spin_rad_s": w, "v_n_m_s": np.full(v_x.shape, -v_n),
               "normal_cor": np.full(v_x.shape, e_n),
               "tangential_cor": v_x / v_x0,
               "contact_point_cor": -(v_x - w * R) / (v_x0 - w0 * R),
               "psi": 2.0 * (v_x0 - w0 * R) / scale,
               "normalised_spin": w * R / scale,
               "frictional_dissipation_j": dissipated,
               "energy_error": np.abs(ke + stored + dissipated - ke0) / np.where(ke0 > 0, ke0, 1)}
    if history:
        out["time_s"] = dt * (1 + np.arange(len(rows)))
        out["normal_force_n"] = np.array([r[0] for r in rows])
        out["tangential_force_n"] = np.array([r[1] for r in rows])
        out["slip_velocity_m_s"] = np.array([r[2] for r in rows])
        out["stick_fraction"] = np.array([r[3] for r in rows])
    return out


def normalised_curves(psi, poissons_ratio: float, k2: float = HOMOGENEOUS_K2,
                      springs: int = 1000, steps: int = 4000) -> dict:
    """The reference in Maw et al.'s normalised form for a sphere on a rigid plane, without
    initial spin: against Psi (array), the normalised rebound spin Omega, the normalised
    tangential velocity change (v_x - v_x') / (mu (1 + e_n) v_n), the tangential COR of the
    centre of mass and that of the contact point. They depend on Psi, nu and k^2 only (scaled
    impacts give the same curves; `tests/oblique/test_elastic_reference.py`)."""
    psi = np.atleast_1d(np.asarray(psi, float))
    bad = np.flatnonzero(~(np.isfinite(psi) & (psi > 0)))
    if bad.size:
        check_range(f"psi[{bad[0]}]", psi[bad[0]], 0.0, low_open=True)
    # any sphere serves (the results are scale-free): a cricket-ball-sized elastic one
    sphere = ElasticSphere(0.036, 0.156, 1e8, poissons_ratio, k2)
    friction = 0.1
    run = oblique_impact(sphere, 1.0, 0.5 * psi * friction * 2.0, 0.0, friction, springs, steps)
    # the normal COR of the integration is 1 to round-off; Psi is recomputed with it
    scale = friction * (1.0 + run["normal_cor"])
    return {"psi": run["psi"], "normalised_spin": run["normalised_spin"],
            "tangential_change": (0.5 * psi * friction * 2.0 - run["v_x_m_s"]) / scale,
            "tangential_cor": run["tangential_cor"], "contact_point_cor": run["contact_point_cor"]}
