"""The explicit step of a layered axisymmetric ball on a rigid plane (pure JAX).

The ball's south pole touches the plane z = 0 at t = 0, every node moving at -v_in along z. The
plane is fixed, or carried by a backing of oscillators (`fe.backing.PlaneBacking`: a headform, a
bat's modes at the impact point) stepped with the nodes.
Central difference (velocity form, constant increment) with lumped masses; internal forces from
`element` (reduced integration with hourglass control, or F-bar) and the materials' strain
energies with Simo's Prony update; linear and quadratic bulk viscosity; node-to-plane penalty
contact with a stiffness derived from the contacting elements.

A `Kernel` holds what a compiled program depends on (mesh, material models, integration,
precision); everything that varies between balls of that structure (constants, densities, masses,
contact and hourglass stiffnesses, the increment, the impact speed) is in `params` and the state,
so one compiled program serves every speed and parameter set, and `vmap` batches them.

Energies (J): kinetic; internal work (the work of the internal forces, hourglass included,
accumulated by the trapezoidal rule); contact work; bulk-viscous dissipation; strain energy (the
long-term strain energy plus the energy held in the Maxwell branches); hourglass energy.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import partial
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from ..backing import no_backing_arrays
from ..stable_increment import increment_factor
from ..steps import (LANCZOS_STEPS, PARAMS, STATE, ChunkedSteps, PronyState, material_stresses,
                     named_tuple, step_events)
from .element import (
    AxiGeometry,
    centre_deformation,
    centre_forces,
    deformation,
    element_corners,
    element_values,
    fbar,
    first_piola,
    gather_nodal,
    hourglass,
    right_cauchy_green,
)

HISTORY = ("time_s", "contact_force_n", "centre_z_m", "centre_velocity_z_m_s", "kinetic_energy_j",
           "internal_work_j", "contact_work_j", "strain_energy_j", "bulk_viscous_dissipation_j",
           "hourglass_energy_j")
#: the histories a backed plane adds: its position, velocity and acceleration along z, the
#: oscillators' kinetic plus spring energy, the contact force's work on the plane and the
#: backing's dashpot dissipation
BACKING_HISTORY = ("backing_z_m", "backing_velocity_z_m_s", "backing_acceleration_z_m_s2",
                   "backing_energy_j", "backing_work_j", "backing_damping_j")


def ball_arrays(ball, geom: AxiGeometry, options, backing=None, layers=None) -> AxiParams:
    """Per-ball parameters of the step (NumPy, float64): masses, contact springs, hourglass and
    bulk-viscosity factors, increment factor, material constants, and the plane's backing
    (`fe.backing.PlaneBacking`, None: a fixed plane). `layers`: every element group's (density,
    material), default the ball's layers (a target's follow them)."""
    layers = ball.layers if layers is None else layers
    rho = np.array([layer.density_kg_m3 for layer in layers])
    wave = np.array([layer.material.wave_modulus_pa() for layer in layers])
    shear = np.array([layer.material.shear_modulus_pa() for layer in layers])
    c_d = np.sqrt(wave / rho)
    element_layer = np.concatenate([np.full(b - a, i) for i, (a, b) in enumerate(geom.layer_slices)])
    length = geom.characteristic_length_m
    c_el, rho_el = c_d[element_layer], rho[element_layer]
    mass = rho @ geom.nodal_volume_m3
    m_surface = mass[geom.surface_nodes]
    penalty = (options.penalty_scale * m_surface
               * (c_d[geom.surface_layer] / geom.surface_length_m) ** 2)
    return AxiParams(
        mass_kg=mass, ball_mass_kg=np.sum(mass), penalty_n_m=penalty,
        contact_damping_n_s_m=options.contact_damping * 2.0 * np.sqrt(penalty * m_surface),
        hourglass_n_m=options.hourglass_scale * shear[element_layer] * geom.hourglass_length_m,
        bv_linear_pa_s=options.bulk_viscosity_linear * rho_el * c_el * length,
        bv_quadratic_pa_s2=rho_el * (options.bulk_viscosity_quadratic * length) ** 2,
        energy_error_limit=np.float64(options.energy_error_limit),
        increment_factor=np.float64(increment_factor(options.time_step_scale,
                                                     options.bulk_viscosity_linear)),
        groups=[layer.material.constants() for layer in layers],
        **(no_backing_arrays() if backing is None else backing.arrays()))


AxiParams = named_tuple(
    "AxiParams", __name__, "The axisymmetric kernel's per-ball parameters (SI; NumPy float64 "
    "from `ball_arrays`).", PARAMS,
    {"groups": "material constants per element group (the ball's layers)",
     "ball_mass_kg": "the ball's mass (kg)",
     "backing_shape_1_sqrt_kg": "the backing's modes' shapes at the impact point "
                                "(1/sqrt(kg); none: a fixed plane)",
     "backing_omega2_1_s2": "their squared frequencies (1/s^2)",
     "backing_damping_1_s": "their damping matrix (1/s)",
     "backing_velocity0": "their velocities at t = 0 (sqrt(kg) m/s)"})
AxiState = named_tuple(
    "AxiState", __name__, "The axisymmetric kernel's state between steps (SI; nodal arrays "
    "(2, n_nodes)).", STATE, {"f_e": "element corner forces (N), the last step's",
                              "backing_q": "the backing's modal coordinates (sqrt(kg) m)",
                              "backing_qd": "their velocities",
                              "backing_qdd": "their accelerations",
                              "w_backing": "work of the contact force on the plane (J)",
                              "d_backing": "the backing's dashpot dissipation (J)"})


def extremes(J, lam2_min, lam2_max):
    """The step's smallest volume ratio and smallest and largest eigenvalue of C over the
    elements' points (each (points, elements)), in one reduction (each is a pass of its own)."""
    min_j, low, neg_high = jnp.min(jnp.stack([
        jnp.min(J, axis=0), jnp.min(lam2_min, axis=0), -jnp.max(lam2_max, axis=0)]), axis=1)
    return min_j, low, -neg_high


@dataclass(frozen=True, eq=False)
class Kernel(ChunkedSteps):
    """Static data of one mesh, ball structure, integration and precision; traced by JAX."""

    geom: AxiGeometry      # float arrays in `dtype`
    energies: tuple        # one energy function per layer
    bulk_relaxation: tuple  # per layer: does it have k_i > 0
    reduced: bool          # one-point integration with hourglass control
    dtype: Any
    backing_modes: int = 0  # the plane's backing's modes (0: a fixed plane)

    @classmethod
    def build(cls, geom: AxiGeometry, energies, bulk_relaxation, reduced: bool, dtype,
              backing_modes: int = 0) -> Kernel:
        floats = {f.name: getattr(geom, f.name).astype(dtype) for f in dataclasses.fields(geom)
                  if isinstance(getattr(geom, f.name), np.ndarray)
                  and np.issubdtype(getattr(geom, f.name).dtype, np.floating)}
        return cls(dataclasses.replace(geom, **floats), tuple(energies), tuple(bulk_relaxation),
                   reduced, np.dtype(dtype), backing_modes)

    @property
    def backed(self) -> bool:
        return self.backing_modes > 0

    @property
    def history_names(self) -> tuple[str, ...]:
        """The columns of a history row (a backing's: `BACKING_HISTORY`, then its modal
        coordinates `backing_q_K` and velocities `backing_qd_K`, K from 0)."""
        if not self.backed:
            return HISTORY
        n = range(self.backing_modes)
        return (HISTORY + BACKING_HISTORY + tuple(f"backing_q_{k}" for k in n)
                + tuple(f"backing_qd_{k}" for k in n))

    @property
    def n_points(self) -> int:
        return 1 if self.reduced else 4

    @property
    def point_volume_m3(self) -> np.ndarray:
        """Volume weight of each integration point (n_points, n_el)."""
        g = self.geom
        return g.element_volume_m3[None] if self.reduced else g.volume_weight_m3

    @property
    def surface_height_m(self) -> np.ndarray:
        """Reference height of the surface nodes above the plane (south pole at 0)."""
        g = self.geom
        return g.nodes_m[g.surface_nodes, 1] - g.nodes_m[:, 1].min()

    def zeros(self, shape) -> jax.Array:
        return jnp.zeros(shape, self.dtype)

    def zero_corner_forces(self):
        """Corner forces f_e[c][a] of the undeformed ball (the layout `internal` returns)."""
        n_el = self.geom.n_elements
        if self.reduced:
            return tuple(tuple(self.zeros(n_el) for _ in range(4)) for _ in range(2))
        return self.zeros((2, 4, n_el))

    def initial_materials(self, params) -> list[PronyState]:
        mats = []
        for (a, b), bulk, consts in zip(self.geom.layer_slices, self.bulk_relaxation,
                                        params.groups):
            shape = (4, self.n_points, b - a)  # (S_rr, S_zz, S_hoop, S_rz) at the points
            n_terms = consts.prony_g.shape[-1]
            n_bulk = n_terms if bulk else 0  # without bulk relaxation its states are not kept
            mats.append(PronyState(q_dev=self.zeros((n_terms,) + shape),
                                   q_vol=self.zeros((n_bulk,) + shape),
                                   s0_dev=self.zeros(shape),
                                   s0_vol=self.zeros(shape if bulk else (0,) + shape[1:])))
        return mats

    def initial_state(self, params, speed):
        n = len(self.geom.nodes_m)
        zeros = self.zeros((2, n))
        inf = jnp.array(jnp.inf, self.dtype)
        scalar = partial(jnp.array, dtype=self.dtype)
        omega2, x_top = self.max_frequency_squared(params, zeros, None, LANCZOS_STEPS)
        dt = params.increment_factor / jnp.sqrt(omega2)
        backing = jnp.zeros_like(params.backing_velocity0)
        return AxiState(backing_q=backing, backing_qd=params.backing_velocity0,
                        backing_qdd=backing,
                        w_backing=scalar(0.0), d_backing=scalar(0.0),u=zeros, v=zeros.at[1].set(-speed), a=zeros, t=scalar(0.0),
                        dt=dt, dt0=dt, x_top=x_top,
                        f_e=self.zero_corner_forces(), f_contact=self.zeros(n),
                        mat=self.initial_materials(params),
                        j0=jnp.ones(self.geom.n_elements, self.dtype),
                        sigma_bv=self.zeros(self.geom.n_elements),
                        ke0=0.5 * params.ball_mass_kg * speed * speed,
                        w_int=scalar(0.0), w_contact=scalar(0.0), d_bv=scalar(0.0),
                        peak_force=scalar(0.0), t_peak=scalar(0.0), u_peak=zeros,
                        t_start=inf, t_separation=inf, t_bad=inf, t_energy=inf,
                        stretch_min=scalar(1.0), stretch_max=scalar(1.0))

    # ---- forces ------------------------------------------------------------------------------
    def internal(self, params, u, mats, j0_prev, dt):
        """Internal nodal forces (2, n_nodes) at displacements u (2, n_nodes), new material
        states, centre J, and per element: stored strain energy (J), hourglass energy (J),
        bulk-viscous Cauchy pressure (Pa); J and the eigenvalues' range of C at the points; and
        the element corner forces f_e[c][a]. Per-element values, not sums: the step sums all of
        them in one pass."""
        g = self.geom

        if self.reduced:
            u_e = element_corners(g, u)
            Fb2, Fbh = centre_deformation(g, u_e)
            J = (Fb2[0] * Fb2[3] - Fb2[1] * Fb2[2]) * Fbh
        else:
            def kinematics(u_e):
                Fb2, Fbh, J = fbar(*deformation(g, u_e))
                return (Fb2, Fbh), J

            u_e = element_values(g, u)
            (Fb2, Fbh), pull, J = jax.vjp(kinematics, u_e, has_aux=True)
        C = right_cauchy_green(Fb2, Fbh)
        weight = self.point_volume_m3
        S, new_mats, density = material_stresses(g.layer_slices, self.energies, params.groups,
                                                 C[:4], mats, dt)
        stored = jnp.sum(density * weight, axis=0)
        j0 = J[-1]  # at the centre (the last of the F-bar points; the only reduced one)
        rate = (j0 - j0_prev) / (dt * j0)  # volumetric strain rate at the centre (1/s)
        sigma_bv = rate * (params.bv_linear_pa_s
                           + params.bv_quadratic_pa_s2 * jnp.maximum(-rate, 0.0))
        P2, Ph = first_piola(Fb2, Fbh, S, sigma_bv * j0)
        if self.reduced:
            f_p = centre_forces(g, P2, Ph, g.element_volume_m3)
            f_hg, e_hg = hourglass(g, u_e, params.hourglass_n_m)  # e_hg per element
            f_e = tuple(tuple(f_p[c][a] + f_hg[c][a] for a in range(4)) for c in range(2))
        else:
            (f_e,) = pull((tuple(p * weight for p in P2), Ph * weight))
            e_hg = self.zeros(g.n_elements)
        f = gather_nodal(g, f_e)
        # the stretch range is a diagnostic: no derivative (the square root's is infinite at
        # equal stretches, which would poison reverse-mode gradients with 0 * inf)
        Cd = jax.lax.stop_gradient(C)
        m_ = 0.5 * (Cd.xx + Cd.yy)
        d_ = jnp.sqrt(0.25 * (Cd.xx - Cd.yy) ** 2 + Cd.xy ** 2)
        lam2_min = jnp.minimum(m_ - d_, Cd.zz)
        lam2_max = jnp.maximum(m_ + d_, Cd.zz)
        return f, new_mats, j0, stored, e_hg, sigma_bv, J, lam2_min, lam2_max, f_e

    def contact(self, params, u, v_half, plane_z=None, plane_v=None):
        """Normal contact forces (n_surface,) of the surface nodes on the plane z = 0, or at
        `plane_z` (m) moving at `plane_v` (m/s) when backed."""
        s = self.geom.surface_nodes
        height, velocity = self.surface_height_m + u[1, s], v_half[1, s]
        if plane_z is not None:
            height, velocity = height - plane_z, velocity - plane_v
        penetration = jnp.maximum(-height, 0.0)
        normal = params.penalty_n_m * penetration \
            - params.contact_damping_n_s_m * velocity * (penetration > 0)
        return jnp.maximum(normal, 0.0)

    def backing_step(self, params, state, dt, u, v_half):
        """The contact forces with the plane on its backing, and the backing's new state: its
        modes (`fe.backing`) stepped by the same central difference as the nodes, driven by the
        contact force (down, -z), with the work of that force on the plane (trapezoidal) and the
        modal dashpots' dissipation. Returns (forces, new state fields, history row)."""
        phi, c = params.backing_shape_1_sqrt_kg, params.backing_damping_1_s
        qd_half = state.backing_qd + 0.5 * dt * state.backing_qdd
        q = state.backing_q + dt * qd_half
        plane_z = phi @ q
        normal = self.contact(params, u, v_half, plane_z, phi @ qd_half)
        total = jnp.sum(normal)
        damping = c @ qd_half
        qdd = -phi * total - damping - params.backing_omega2_1_s2 * q
        qd = qd_half + 0.5 * dt * qdd
        dz = plane_z - phi @ state.backing_q
        w_backing = state.w_backing - 0.5 * (jnp.sum(state.f_contact) + total) * dz
        d_backing = state.d_backing + dt * (qd_half @ damping)
        energy = 0.5 * jnp.sum(qd * qd + params.backing_omega2_1_s2 * q * q)
        new = {"backing_q": q, "backing_qd": qd, "backing_qdd": qdd, "w_backing": w_backing,
               "d_backing": d_backing}
        return normal, new, [plane_z, phi @ qd, phi @ qdd, energy, w_backing, d_backing,
                             *q, *qd]

    # ---- the step ----------------------------------------------------------------------------
    def step(self, params, t0, state, i):
        g = self.geom
        dt = state.dt
        mass = params.mass_kg
        off_axis = g.nodes_m[:, 0] > 0.0  # radial motion is zero on the axis
        v_half = state.v + 0.5 * dt * state.a
        u = state.u + dt * v_half
        f_int, mats, j0, stored, e_hg, sigma_bv, J, lam2_min, lam2_max, f_e = self.internal(
            params, u, state.mat, state.j0, dt)
        if self.backed:
            normal, backing, backing_row = self.backing_step(params, state, dt, u, v_half)
            plane_v = params.backing_shape_1_sqrt_kg @ backing["backing_qd"]
        else:
            normal, plane_v, backing_row = self.contact(params, u, v_half), 0.0, []
            backing = {k: getattr(state, k) for k in ("backing_q", "backing_qd", "backing_qdd",
                                                      "w_backing", "d_backing")}
        f_contact = self.zeros(len(g.nodes_m)).at[g.surface_nodes].set(normal)
        a = (-f_int).at[1].add(f_contact) / mass
        a = a.at[0].multiply(off_axis)
        v = v_half + 0.5 * dt * a
        du = u - state.u
        work_e, bv_e = self.element_work(state, u, f_e, j0, sigma_bv)
        # every sum and extremum of the step in three reductions (each is a pass of its own)
        stored, e_hg, dw_int, dd_bv = jnp.sum(jnp.stack([stored, e_hg, work_e, bv_e]), axis=1)
        height = g.nodes_m[:, 1] - g.nodes_m[:, 1].min() + u[1]
        kinetic, momentum_z, moment_z, dw_contact = jnp.sum(jnp.stack([
            0.5 * mass * (v[0] * v[0] + v[1] * v[1]), mass * v[1], mass * height,
            0.5 * (state.f_contact + f_contact) * du[1]]), axis=1)
        min_j, lam2_min, lam2_max = extremes(J, lam2_min, lam2_max)
        w_int = state.w_int + dw_int
        w_contact = state.w_contact + dw_contact
        d_bv = state.d_bv + dd_bv
        t = t0 + (i + 1) * dt  # not a running sum over the whole run: accurate in float32 too
        total = jnp.sum(normal)
        v_cm = momentum_z / params.ball_mass_kg
        z_cm = moment_z / params.ball_mass_kg
        new = AxiState(u=u, v=v, a=a, t=t, dt=dt, dt0=state.dt0,
                       x_top=state.x_top, f_e=f_e, f_contact=f_contact, mat=mats,
                       j0=j0, sigma_bv=sigma_bv, ke0=state.ke0, w_int=w_int,
                       w_contact=w_contact, d_bv=d_bv, **backing,
                       # separation: the ball's centre moving away from the plane
                       **step_events(state, t, total, v_cm - plane_v, u, kinetic, w_int,
                                     w_contact, min_j, lam2_min, lam2_max,
                                     params.energy_error_limit))
        row = jnp.stack([t, total, z_cm, v_cm, kinetic, w_int, w_contact, stored, d_bv, e_hg]
                        + backing_row)
        return new, row

    def element_work(self, state, u, f_e, j0, sigma_bv):
        """Per element, the step's internal work (its corner forces, the last step's and this
        one's averaged, over its corners' displacement) and bulk-viscous work (the trapezoidal
        rule too: power = sigma dJ/dt V), from `state` to displacements `u` (J)."""
        g = self.geom
        # Summed over elements (the same as over nodes): the corner forces then have a second
        # reader besides the nodal gather, so XLA computes them once into memory instead of
        # fusing their whole computation into the gather (4x slower).
        corners = element_corners if self.reduced else element_values
        new_u, old_u = corners(g, u), corners(g, state.u)
        work_e = 0.5 * sum((state.f_e[c][a] + f_e[c][a]) * (new_u[c][a] - old_u[c][a])
                           for c in range(2) for a in range(4))
        bv_e = 0.5 * (state.sigma_bv + sigma_bv) * (j0 - state.j0) * g.element_volume_m3
        return work_e, bv_e

    # ---- the stable increment ----------------------------------------------------------------
    def frequency_mask(self):
        """Free degrees of freedom (2, n_nodes): radial motion is zero on the axis."""
        g = self.geom
        return jnp.stack([g.nodes_m[:, 0] > 0.0,
                          jnp.ones(len(g.nodes_m), bool)]).astype(self.dtype)

    def contact_springs(self, params, v):
        """K_contact v (2, n_nodes): every surface node's normal spring active."""
        s = self.geom.surface_nodes
        return self.zeros(v.shape).at[1, s].set(params.penalty_n_m * v[1, s])


