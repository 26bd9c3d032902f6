"""The explicit step of a 3D ball (and an optional deformable target) in an oblique impact on a
flat surface (pure JAX).

The ball's south pole touches the surface z = 0 at t = 0, moving at (v sin theta, 0, -v cos theta)
and spinning at omega about the y axis. Central difference (velocity form) with lumped masses;
internal forces from `element` (one-point hexahedra with hourglass control) and the materials'
strain energies with Simo's Prony update, the same as the axisymmetric `fe.axi.kernel`; linear and
quadratic bulk viscosity; node-to-surface penalty contact with Coulomb friction.

Friction: each contacting ball node carries a tangential stick spring of stiffness k_t
(`stick_scale` x its normal penalty stiffness), stretched by the node's tangential displacement
relative to the surface since it touched; its force is capped at mu times the normal force, the
excess being slip (a return map, as a plasticity update). k_t is the regularisation of the stick:
the elastic slip before sliding is mu N / k_t. The work of the tangential forces less the energy
held in the stick springs is the frictional dissipation.

Backed target (`target.Backing`; `Kernel.backing` the slab's base node ids, None for a fixed
base, the program of a fixed base unchanged): the base nodes keep x and y fixed and move along z
together as one rigid body of mass M + m_base (the backing's M and the base nodes' own lumped
mass), (M + m_base) a = -F_t - k z - c v with F_t = sum of the base nodes' internal forces along z
(the force the slab puts on the backing, > 0 pushing it down), integrated by the same central
difference step; the damper is taken at the step's end velocity v = v_half + dt a / 2 (solved for
a: unconditionally stable in c). Energies: the step's balance (`step_events`) counts the
backing's kinetic energy M v^2 / 2 with the nodes' (the base nodes' own is theirs), its spring's
energy k z^2 / 2 and the damper's dissipation (trapezoidal, as the internal work) as kinetic, so
KE + backing energies + internal work - contact work = KE0 is the whole system's balance; the
separation's velocity is the ball centre's relative to the backing.

A slab's layers (`Kernel.centre_column` set; the same figures and history columns as the
axisymmetric `fe.axi.target_kernel`): each target layer's internal work (J), the work of the
internal forces on its elements, accumulated by the trapezoidal rule as the total internal work
is (from the slab's element corner forces, kept from the last step), and its compression
(u_z(bottom) - u_z(top)) / thickness on the slab's node column at x = y = 0 (the first touch
point; > 0 compressed). In an oblique impact the contact slides along x away from that column:
its compression is still the column's at the slab centre (where the ball first struck), not the
one under the moving contact. The ball's internal work (its nodes' share of the total) is kept
in the state (`w_ball`, a check: the ball's and the layers' works add up to the total).

A `Kernel` holds what a compiled program depends on (mesh, models, contact kind, precision);
constants, masses, stiffnesses, friction and the impact condition are in `params` and the state,
so `vmap` batches impacts of one mesh.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import partial
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from ..stable_increment import alternating_start
from ..steps import (PARAMS, STATE, ChunkedSteps, PronyState, material_stresses, named_tuple,
                     step_events)
from ...constitutive import Sym, energy_and_stress
from .element import (
    HexGeometry,
    cofactor,
    corner_forces,
    corners,
    deformation_gradient,
    determinant,
    fbar,
    first_piola,
    gather_nodal,
    materialized,
    right_cauchy_green,
)

HISTORY = ("time_s", "contact_force_n", "tangential_force_x_n", "tangential_force_y_n",
           "centre_x_m", "centre_z_m", "centre_velocity_x_m_s", "centre_velocity_y_m_s",
           "centre_velocity_z_m_s", "spin_x_rad_s", "spin_y_rad_s", "spin_z_rad_s",
           "contact_slip_velocity_m_s", "kinetic_energy_j", "internal_work_j", "contact_work_j",
           "strain_energy_j", "bulk_viscous_dissipation_j", "hourglass_energy_j",
           "tangential_work_j", "stick_energy_j", "slipping_load_fraction")


def target_layer_history(layers: int) -> tuple[str, ...]:
    """The columns of a slab's `layers` layers (the axisymmetric target kernel's names): each
    one's internal work (J), then each one's compression at the slab's centre."""
    return (tuple(f"target_layer_{k}_work_j" for k in range(layers))
            + tuple(f"target_layer_{k}_compression" for k in range(layers)))


#: the columns a backed target (`Kernel.backing`) adds: the backing's z displacement, velocity
#: and acceleration (+z up), the force the slab puts on it (N, > 0 pushing it down), its kinetic
#: energy M v^2 / 2 (the user's mass M; the base nodes' own is in the nodes' kinetic energy),
#: its spring's energy, its damper's dissipation, and the z momentum of the target (slab nodes
#: and M; the ball's is its mass times its centre's velocity)
BACKING_HISTORY = ("backing_z_m", "backing_velocity_z_m_s", "backing_acceleration_z_m_s2",
                   "transmitted_force_n", "backing_kinetic_energy_j", "backing_spring_energy_j",
                   "backing_damper_dissipation_j", "target_momentum_z_kg_m_s")


def dot3(a, b):
    """Per node, a . b of two (3, n) arrays, the components summed one by one: XLA's CPU compiler
    makes a reduction over the 3 components a pass of its own (a fifth of the step)."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


HexParams = named_tuple(
    "HexParams", __name__, "The hexahedral kernel's per-run parameters (SI; NumPy float64 from "
    "`fe.hex.geometry.model_arrays`).", PARAMS,
    {"ball_mass_kg": "the ball's mass (kg; of the model: half for a half model)",
     "contact_spring_factor": "stable-increment factor of each contact spring (a slab's node "
                              "beneath)",
     "backing": "a backed target's (M kg, k N/m, c N s/m, the base nodes' mass kg), each of "
                "the model (half for a half model); empty for a fixed base",
     "element_index": "arange of the elements (`element.materialized`'s fusion boundary)",
     "friction": "Coulomb coefficient",
     "groups": "material constants per element group (ball layers, slab layers)",
     "outer_radius_m": "the ball's outer radius (m)",
     "stick_n_m": "friction stick springs per contact node (N/m)"})
HexState = named_tuple(
    "HexState", __name__, "The hexahedral kernel's state between steps (SI; nodal arrays "
    "(3, n_nodes)).", STATE,
    {"backing": "a backed target's (damper dissipation J, damper force N of the last step); "
                "empty for a fixed base",
     "f_int": "internal nodal forces (N), the last step's",
     "f_slab": "the slab's element corner forces (N; (3, 8, slab elements)), the last step's; "
               "empty without a slab's layer figures (`Kernel.centre_column`)",
     "w_ball": "internal work of the ball's elements (J; 0 without layer figures)",
     "w_layers": "internal work of each target layer's elements (J; empty without layer "
                 "figures)",
     "f_tangential": "friction forces on the contact nodes (N)",
     "stick": "friction stick-spring extensions (m)",
     "w_tangential": "work of the friction forces (J)"})


@dataclass(frozen=True, eq=False)
class Kernel(ChunkedSteps):
    """Static data of one mesh, model structure, contact kind and precision; traced by JAX."""

    geom: HexGeometry            # float arrays in `dtype`
    energies: tuple              # one energy function per group (ball layers, target layers)
    bulk_relaxation: tuple       # per group: does it have k_i > 0
    contact_nodes: np.ndarray    # ball surface nodes
    ball_nodes: np.ndarray       # bool (n_nodes,)
    free_dof: np.ndarray         # (3, n_nodes) 1 where the motion is free, 0 where held
    half: bool                   # a half model on y >= 0 (extensive results doubled)
    reduced: bool                # one point with hourglass control, or 2x2x2 points with F-bar
    target: dict | None          # deformable slab: "top" node ids (nx+1, ny+1), "x_m", "y_m"
    dtype: Any
    backing: np.ndarray | None = None  # a backed slab's base node ids (None: a fixed base)
    # a slab's layer figures (None: none kept): its node ids at x = y = 0 (the first touch
    # point; an oblique impact's contact slides away from it along x, and the compression is
    # still this column's) at the top of each layer and at the base (target layers + 1,), with
    # the ball's element groups' count and the layers' thicknesses (m)
    centre_column: np.ndarray | None = None
    ball_groups: int = 0
    thicknesses_m: tuple = ()

    @property
    def history_names(self) -> tuple[str, ...]:
        """The columns of the step's history row: `HISTORY`, a slab's layers' columns
        (`target_layer_history`) and a backing's (`BACKING_HISTORY`)."""
        names = HISTORY
        if self.centre_column is not None:
            names = names + target_layer_history(len(self.thicknesses_m))
        return names if self.backing is None else names + BACKING_HISTORY

    @property
    def slab_start(self) -> int:
        """The slab's first element (its groups follow the ball's, elements sorted by
        group)."""
        return self.geom.group_slices[self.ball_groups][0]

    def backing_mask(self) -> np.ndarray:
        """(3, n_nodes) 1 on the z components of a backed slab's base nodes, else 0."""
        mask = np.zeros((3, self.n_nodes))
        mask[2, self.backing] = 1.0
        return mask.astype(self.dtype)

    @property
    def n_nodes(self) -> int:
        return len(self.geom.nodes_m)

    def zeros(self, shape) -> jax.Array:
        return jnp.zeros(shape, self.dtype)

    # ---- materials ---------------------------------------------------------------------------
    @property
    def point_shape(self) -> tuple[int, ...]:
        """Integration points per element as an axis: () reduced, (8,) full."""
        return () if self.reduced else (8,)

    def initial_materials(self, params) -> list[PronyState]:
        mats = []
        for (a, b), bulk, consts in zip(self.geom.group_slices, self.bulk_relaxation,
                                        params.groups):
            shape = (6,) + self.point_shape + (b - a,)
            n_terms = consts.prony_g.shape[-1]
            mats.append(PronyState(q_dev=self.zeros((n_terms,) + shape),
                                   q_vol=self.zeros(((n_terms if bulk else 0),) + shape),
                                   s0_dev=self.zeros(shape),
                                   s0_vol=self.zeros(shape if bulk else (0,) + shape[1:])))
        return mats

    def internal(self, params, u, mats, j_prev, dt):
        """Internal nodal forces (3, n_nodes), new material states, J at the centres, per-element
        stored and hourglass energies (J), the bulk-viscous stress (Pa), bounds on C's
        eigenvalues (per element) and the element corner forces f_e[c][a] (n_el,) (N) they are
        gathered from."""
        g = self.geom
        # F computed once into memory (`element.materialized`; XLA would recompute it in every
        # consumer it fuses it into). The corner values are gathers, which XLA keeps as they are.
        index = params.element_index
        u_e = corners(g, u)
        if self.reduced:
            F = materialized(deformation_gradient(g, u_e), index)
            J = determinant(F, cofactor(F))
        else:
            F, pull, J = jax.vjp(lambda ue: fbar(g, ue), u_e, has_aux=True)
        C = right_cauchy_green(F)
        S, new_mats, density = material_stresses(g.group_slices, self.energies,
                                                 params.groups, C, mats, dt)
        rate = (J - j_prev) / (dt * J)
        sigma_bv = rate * (params.bv_linear_pa_s
                           + params.bv_quadratic_pa_s2 * jnp.maximum(-rate, 0.0))
        if self.reduced:
            stored = density * g.volume_m3
            P = first_piola(F, S, cofactor(F), sigma_bv)
            f_e, e_hg = corner_forces(g, P, F, u_e, params.hourglass_n_m, index)
        else:
            weight = g.point_volume_m3
            stored = jnp.sum(density * weight, axis=0)
            P = first_piola(F, S, cofactor(F), sigma_bv[None])
            (f_e,) = pull(tuple(tuple(p * weight for p in row) for row in P))
            e_hg = self.zeros(g.n_elements)
        f = gather_nodal(g, f_e)
        Cd = jax.lax.stop_gradient(C)
        # Gershgorin bounds on C's eigenvalues: the stretch range, a diagnostic
        n_el = g.n_elements
        lam_lo = jnp.min(jnp.stack([Cd[0] - jnp.abs(Cd[3]) - jnp.abs(Cd[5]),
                                    Cd[1] - jnp.abs(Cd[3]) - jnp.abs(Cd[4]),
                                    Cd[2] - jnp.abs(Cd[4]) - jnp.abs(Cd[5])]).reshape(-1, n_el),
                         axis=0)
        lam_hi = jnp.max(jnp.stack([Cd[0] + jnp.abs(Cd[3]) + jnp.abs(Cd[5]),
                                    Cd[1] + jnp.abs(Cd[3]) + jnp.abs(Cd[4]),
                                    Cd[2] + jnp.abs(Cd[4]) + jnp.abs(Cd[5])]).reshape(-1, n_el),
                         axis=0)
        return f, new_mats, J, stored, e_hg, sigma_bv, lam_lo, lam_hi, f_e

    def cauchy_stress(self, params, u, mats):
        """Cauchy stress (6, n_el) (Pa; xx, yy, zz, xy, yz, zx; the mean over the points of an
        element) at displacements u with the Maxwell branches' overstresses of `mats` (for
        output)."""
        g = self.geom
        u_e = corners(g, u)
        F = deformation_gradient(g, u_e) if self.reduced else fbar(g, u_e)[0]
        J = determinant(F, cofactor(F))
        parts = []
        for (a, b), energy, consts, mat in zip(g.group_slices, self.energies, params.groups,
                                               mats):
            (_, s_dev), (_, s_vol) = energy_and_stress(
                energy, Sym(*(c[..., a:b] for c in right_cauchy_green(F))),
                consts.hyperelastic)
            parts.append(jnp.stack(s_dev) + jnp.stack(s_vol) - jnp.sum(mat.q_dev, axis=0)
                         - jnp.sum(mat.q_vol, axis=0))
        S = jnp.concatenate(parts, axis=-1)
        s = ((S[0], S[3], S[5]), (S[3], S[1], S[4]), (S[5], S[4], S[2]))
        FS = [[sum(F[i][k] * s[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
        sigma = jnp.stack([sum(FS[i][k] * F[j][k] for k in range(3)) / J
                           for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0))])
        return sigma if self.reduced else jnp.mean(sigma, axis=1)

    # ---- contact -----------------------------------------------------------------------------
    def surface(self, u, v_half):
        """Height above the target surface (m) of each contact node, its velocity relative to
        the surface (3, n_contact), and the surface interpolation (slab node ids (4, n_c) and
        weights (4, n_c)), or None for the rigid plane."""
        s = self.contact_nodes
        x = self.geom.nodes_m[s].T + u[:, s]
        vel = v_half[:, s]
        if self.target is None:
            return x[2], vel, None
        t = self.target
        xs, ys = jnp.asarray(t["x_m"]), jnp.asarray(t["y_m"])
        i = jnp.clip(jnp.searchsorted(xs, x[0]) - 1, 0, len(xs) - 2)
        j = jnp.clip(jnp.searchsorted(ys, x[1]) - 1, 0, len(ys) - 2)
        xi = jnp.clip((x[0] - xs[i]) / (xs[i + 1] - xs[i]), 0.0, 1.0)
        eta = jnp.clip((x[1] - ys[j]) / (ys[j + 1] - ys[j]), 0.0, 1.0)
        top = jnp.asarray(t["top"])
        ids = jnp.stack([top[i, j], top[i + 1, j], top[i + 1, j + 1], top[i, j + 1]])
        w = jnp.stack([(1 - xi) * (1 - eta), xi * (1 - eta), xi * eta, (1 - xi) * eta])
        z_surface = jnp.sum(w * (jnp.asarray(self.geom.nodes_m[:, 2])[ids] + u[2][ids]), axis=0)
        v_surface = jnp.sum(w[None] * v_half[:, ids], axis=1)
        return x[2] - z_surface, vel - v_surface, (ids, w)

    def contact(self, params, u, v_half, stick, dt):
        """Contact forces (3, n_contact) on the contact nodes, the new stick extensions
        (2, n_contact), the interpolation onto the target, the relative velocity and which nodes
        slip (at the Coulomb limit)."""
        height, rel, where = self.surface(u, v_half)
        penetration = jnp.maximum(-height, 0.0)
        touching = penetration > 0
        normal = jnp.maximum(params.penalty_n_m * penetration
                             - params.contact_damping_n_s_m * rel[2] * touching, 0.0)
        trial = jnp.where(touching, stick + dt * rel[:2], 0.0)
        k_t = params.stick_n_m
        f_trial = -k_t * trial
        size = jnp.sqrt(f_trial[0] ** 2 + f_trial[1] ** 2)
        limit = params.friction * normal
        scale = jnp.where(size > limit, limit / jnp.where(size > 0, size, 1.0), 1.0)
        f_t = f_trial * scale
        new_stick = -f_t / k_t
        slipping = touching & (size > limit)
        return jnp.concatenate([f_t, normal[None]]), new_stick, where, rel, slipping

    def nodal_contact(self, forces, where):
        """Contact forces (3, n_contact) on ball nodes (and their reactions on the target) as
        nodal forces (3, n_nodes)."""
        # a gather (each node's slot in the contact list, or a zero), not a scatter
        n_c = len(self.contact_nodes)
        slot = np.full(self.n_nodes, n_c)
        slot[self.contact_nodes] = np.arange(n_c)
        out = jnp.concatenate([forces, self.zeros((3, 1))], axis=1)[:, slot]
        if where is not None:
            ids, w = where
            reaction = -(w[None] * forces[:, None])            # (3, 4, n_contact)
            out = out.at[:, ids.reshape(-1)].add(reaction.reshape(3, -1))
        return out

    # ---- the state ---------------------------------------------------------------------------
    first_estimate_in_chunk = True

    def initial_state(self, params, speed, angle_rad, spin_rad_s):
        """The state at first touch: every ball node moving at v + omega x r, with the spin
        vector `spin_rad_s` (3,) (rad/s) about the centre; the increment is estimated in the
        first chunk."""
        n = self.n_nodes
        X = self.geom.nodes_m.T
        ball = self.ball_nodes.astype(self.dtype)
        centre = jnp.array([0.0, 0.0, 1.0], self.dtype) * params.outer_radius_m
        r = X - centre[:, None]
        wx, wy, wz = spin_rad_s[0], spin_rad_s[1], spin_rad_s[2]
        v = jnp.stack([speed * jnp.sin(angle_rad) + wy * r[2] - wz * r[1],
                       wz * r[0] - wx * r[2],
                       -speed * jnp.cos(angle_rad) + wx * r[1] - wy * r[0]]) \
            * ball * self.free_dof
        zeros = self.zeros((3, n))
        scalar = partial(jnp.array, dtype=self.dtype)
        inf = scalar(jnp.inf)
        n_el, n_c = self.geom.n_elements, len(self.contact_nodes)
        backing = self.zeros((0,) if self.backing is None else (2,))
        layered = self.centre_column is not None
        slab_elements = n_el - self.slab_start if layered else 0
        return HexState(u=zeros, v=v, a=zeros, t=scalar(0.0), dt=scalar(0.0), dt0=scalar(0.0),
                        x_top=alternating_start(self.frequency_mask(), self.dtype),
                        f_int=zeros, f_contact=zeros, backing=backing,
                        f_slab=self.zeros((3, 8, slab_elements)), w_ball=scalar(0.0),
                        w_layers=self.zeros(len(self.thicknesses_m) if layered else 0),
                        f_tangential=self.zeros((2, n_c)), stick=self.zeros((2, n_c)),
                        mat=self.initial_materials(params), j0=jnp.ones(n_el, self.dtype),
                        sigma_bv=self.zeros(n_el),
                        ke0=0.5 * jnp.sum(params.mass_kg * jnp.sum(v * v, axis=0)),
                        w_int=scalar(0.0), w_contact=scalar(0.0), w_tangential=scalar(0.0),
                        d_bv=scalar(0.0), peak_force=scalar(0.0), t_peak=scalar(0.0),
                        u_peak=self.zeros((3, 0)),  # not kept in 3D (`step`)
                        t_start=inf, t_separation=inf, t_bad=inf,
                        t_energy=inf, stretch_min=scalar(1.0), stretch_max=scalar(1.0))

    # ---- the step ----------------------------------------------------------------------------
    def rigid_body(self, params, u, v):
        """Ball centre-of-mass position and velocity (3,) and angular velocity (3,) (rad/s),
        from the nodes' momenta about the centre of mass and the current inertia tensor."""
        mass = params.mass_kg * self.ball_nodes
        x = self.geom.nodes_m.T + u
        # every sum over the nodes in one product (6, n) x (n, 4): m x x^T, m v x^T, m x, m v
        # (HIGHEST: no reduced-precision products on accelerators)
        ones = jnp.ones((1, x.shape[1]), self.dtype)
        sums = jnp.dot(jnp.concatenate([x, v]) * mass, jnp.concatenate([x, ones]).T,
                       precision=jax.lax.Precision.HIGHEST)
        m_total = params.ball_mass_kg
        cm, vcm = sums[0:3, 3] / m_total, sums[3:6, 3] / m_total
        vx = sums[3:6, 0:3]  # vx[j, i] = sum m v_j x_i
        L = (jnp.stack([vx[2, 1] - vx[1, 2], vx[0, 2] - vx[2, 0], vx[1, 0] - vx[0, 1]])
             - m_total * jnp.cross(cm, vcm))
        second = sums[0:3, 0:3] - m_total * jnp.outer(cm, cm)
        inertia = jnp.trace(second) * jnp.eye(3, dtype=self.dtype) - second
        if self.half:  # the mirror image cancels these components
            cm, vcm = cm.at[1].set(0.0), vcm.at[1].set(0.0)
            L = L * jnp.array([0.0, 1.0, 0.0], self.dtype)
            keep = jnp.array([[1, 0, 1], [0, 1, 0], [1, 0, 1]], self.dtype)
            inertia = inertia * keep
        return cm, vcm, jnp.linalg.solve(inertia, L)

    def step(self, params, t0, state, i):
        g = self.geom
        dt = state.dt
        mass = params.mass_kg
        v_half = state.v + 0.5 * dt * state.a
        u = state.u + dt * v_half
        f_int, mats, J, stored, e_hg, sigma_bv, lam_lo, lam_hi, f_e = self.internal(
            params, u, state.mat, state.j0, dt)
        forces, stick, where, rel, slipping = self.contact(params, u, v_half, state.stick, dt)
        f_contact = self.nodal_contact(forces, where)
        a = (f_contact - f_int) / mass * self.free_dof
        if self.backing is not None:
            a, backing, row_backing, kinetic_backing, energy_backing, v_backing = \
                self.backed_step(params, state, u, v_half, f_int, a, dt)
        v = v_half + 0.5 * dt * a
        du = u - state.u
        bv_e = 0.5 * (state.sigma_bv + sigma_bv) * (J - state.j0) * g.volume_m3
        # separate reductions: each fuses with what it sums (a stack is written out first)
        stored, e_hg, dd_bv = jnp.sum(stored), jnp.sum(e_hg), jnp.sum(bv_e)
        k_t = params.stick_n_m
        du_t = dt * rel[:2]  # tangential displacement relative to the surface over the step
        normal = forces[2]
        kinetic, dw_int, dw_contact = jnp.sum(jnp.stack([
            0.5 * mass * dot3(v, v), 0.5 * dot3(state.f_int + f_int, du),
            0.5 * dot3(state.f_contact + f_contact, du)]), axis=1)
        dw_tangential, e_stick, f_n, f_x, f_y, slip_weighted, f_slipping = jnp.sum(jnp.stack([
            0.5 * jnp.sum((state.f_tangential + forces[:2]) * du_t, axis=0),
            0.5 * k_t * jnp.sum(stick * stick, axis=0), normal, forces[0], forces[1],
            normal * rel[0], normal * slipping]), axis=1)
        min_j, lam_lo, lam_hi = jnp.min(J), jnp.min(lam_lo), jnp.max(lam_hi)
        cm, vcm, omega = self.rigid_body(params, u, v)
        velocity_z = vcm[2]
        if self.backing is not None:
            # the backing's M v^2 / 2 is kinetic energy; its spring's energy and damper's
            # dissipation count with it in the balance, and separation is relative to it
            kinetic = kinetic + kinetic_backing
            balance_kinetic = kinetic + energy_backing
            velocity_z = vcm[2] - v_backing
        else:
            balance_kinetic, backing = kinetic, state.backing
        w_int = state.w_int + dw_int
        if self.centre_column is not None:
            layers = self.layer_step(state, du, f_int, f_e)
        else:
            layers = {k: getattr(state, k) for k in ("f_slab", "w_ball", "w_layers")}
        w_contact = state.w_contact + dw_contact
        w_tangential = state.w_tangential + dw_tangential
        d_bv = state.d_bv + dd_bv
        t = t0 + (i + 1) * dt
        slip = slip_weighted / jnp.where(f_n > 0, f_n, 1.0)
        slipping_share = f_slipping / jnp.where(f_n > 0, f_n, 1.0)
        new = HexState(u=u, v=v, a=a, t=t, dt=dt, dt0=state.dt0,
                       x_top=state.x_top, f_int=f_int, f_contact=f_contact,
                       f_tangential=forces[:2], stick=stick, mat=mats, j0=J, backing=backing,
                       sigma_bv=sigma_bv, ke0=state.ke0, w_int=w_int, **layers,
                       w_contact=w_contact, w_tangential=w_tangential, d_bv=d_bv,
                       # no shape at the peak: the 3D results keep frames instead
                       **step_events(state, t, f_n, velocity_z, None, balance_kinetic, w_int,
                                     w_contact, min_j, lam_lo, lam_hi,
                                     params.energy_error_limit))
        columns = [t, f_n, f_x, f_y, cm[0], cm[2], vcm[0], vcm[1], vcm[2], omega[0], omega[1],
                   omega[2], slip, kinetic, w_int, w_contact, stored, d_bv, e_hg, w_tangential,
                   e_stick, slipping_share]
        if self.centre_column is not None:
            # on the slab's centre column (x = y = 0), also in an oblique impact, whose contact
            # moves along x away from it (`centre_column`)
            column = u[2, self.centre_column]
            compression = (column[1:] - column[:-1]) / jnp.asarray(self.thicknesses_m,
                                                                    self.dtype)
            columns += [*layers["w_layers"], *compression]
        if self.backing is not None:
            columns += row_backing(v)
        row = jnp.stack(columns)
        return new, row

    def layer_step(self, state, du, f_int, f_e) -> dict:
        """A slab's layer figures over a step (`Kernel.centre_column`): the slab's corner forces
        f_e[c][a] (the slab's part kept, (3, 8, slab elements)), the internal work of the
        ball's elements (its nodes' share of the total, trapezoidal) and of each target layer's
        (each element's corner forces, the last step's and this one's, on its corners'
        displacement increments du: the total internal work per element, summed per layer)."""
        g, start = self.geom, self.slab_start
        slab = g.elements[start:]
        f_slab = jnp.stack([jnp.stack([f_e[c][k][start:] for k in range(8)]) for c in range(3)])
        work_e = 0.5 * sum((state.f_slab[c, k] + f_slab[c, k]) * du[c, slab[:, k]]
                           for c in range(3) for k in range(8))
        ball = jnp.asarray(self.ball_nodes, self.dtype)
        dw_ball = jnp.sum(0.5 * dot3(state.f_int + f_int, du) * ball)
        dw_layers = jnp.stack([jnp.sum(work_e[a - start:b - start])
                               for a, b in g.group_slices[self.ball_groups:]])
        return {"f_slab": f_slab, "w_ball": state.w_ball + dw_ball,
                "w_layers": state.w_layers + dw_layers}

    def backed_step(self, params, state, u, v_half, f_int, a, dt):
        """The backing's rigid-body z motion in a step (`Kernel.backing`): the accelerations `a`
        with the base nodes' z set to the backing's, its new state (damper dissipation J, damper
        force N), a function of the end velocities v giving its history columns
        (`BACKING_HISTORY`), its kinetic energy M v^2 / 2 (J), its spring's energy plus its
        damper's dissipation (J), and its velocity (m/s)."""
        base = self.backing
        mass_m, spring, damper, mass_base = (params.backing[i] for i in range(4))
        z = u[2, base[0]]                         # every base node moves alike
        transmitted = jnp.sum(f_int[2, base])     # the slab's push on the base, > 0 downward
        # (M + m_base) a = -F_t - k z - c (v_half + dt a / 2), solved for a
        a_backing = ((-transmitted - spring * z - damper * v_half[2, base[0]])
                     / (mass_m + mass_base + 0.5 * dt * damper))
        a = a + jnp.asarray(self.backing_mask()) * a_backing
        v_backing = v_half[2, base[0]] + 0.5 * dt * a_backing
        f_damper = damper * v_backing
        dissipation = state.backing[0] + 0.5 * (state.backing[1] + f_damper) * (
            z - state.u[2, base[0]])
        kinetic = 0.5 * mass_m * v_backing * v_backing
        e_spring = 0.5 * spring * z * z
        slab = jnp.asarray(~self.ball_nodes, self.dtype) * params.mass_kg

        def columns(v):
            momentum = jnp.sum(slab * v[2]) + mass_m * v_backing
            return [z, v_backing, a_backing, transmitted, kinetic, e_spring, dissipation,
                    momentum]

        return (a, jnp.stack([dissipation, f_damper]), columns, kinetic, e_spring + dissipation,
                v_backing)

    # ---- the stable increment ----------------------------------------------------------------
    def frequency_mask(self):
        """The free degrees of freedom; a backed slab's base nodes free along z each on its own
        (`contact_springs` ties each to the ground by its share of the backing spring): the
        backed system is this one with the base nodes' z tied together and the backing's mass
        added, which lowers every frequency, so the estimate stays an upper bound."""
        if self.backing is None:
            return jnp.asarray(self.free_dof, self.dtype)
        return jnp.asarray(self.free_dof + self.backing_mask(), self.dtype)

    def contact_springs(self, params, v):
        """K_contact v (3, n_nodes): every contact node's stick (x, y) and normal (z) springs
        active, tied to the ground; `contact_spring_factor` allows for lighter target nodes at
        their other end."""
        s = self.contact_nodes
        springs = params.contact_spring_factor * jnp.stack(
            [params.stick_n_m, params.stick_n_m, params.penalty_n_m])
        kv = self.zeros(v.shape).at[:, s].set(springs * v[:, s])
        if self.backing is not None:
            # the backing spring shared by the base nodes in proportion to their masses (each
            # then at k / m_base, above the backing's k / (M + m_base))
            spring, mass_base = params.backing[1], params.backing[3]
            kv = kv + jnp.asarray(self.backing_mask()) * (spring / mass_base) * params.mass_kg * v
        return kv


def build(geom: HexGeometry, energies, bulk_relaxation, contact_nodes, ball_nodes, free_dof,
          half: bool, reduced: bool, target, dtype, backing=None, centre_column=None,
          ball_groups: int = 0, thicknesses_m=()) -> Kernel:
    """The kernel; `backing`: a backed slab's base node ids (None: a fixed base);
    `centre_column`, `ball_groups`, `thicknesses_m`: a slab's layer figures (`Kernel`; None:
    none kept)."""
    floats = {f.name: getattr(geom, f.name).astype(dtype) for f in dataclasses.fields(geom)
              if isinstance(getattr(geom, f.name), np.ndarray)
              and np.issubdtype(getattr(geom, f.name).dtype, np.floating)}
    if target is not None:
        target = {"top": np.asarray(target["top"]), "x_m": np.asarray(target["x_m"], dtype),
                  "y_m": np.asarray(target["y_m"], dtype)}
    return Kernel(dataclasses.replace(geom, **floats), tuple(energies), tuple(bulk_relaxation),
                  np.asarray(contact_nodes), np.asarray(ball_nodes), np.asarray(free_dof, dtype),
                  half, reduced, target, np.dtype(dtype),
                  None if backing is None else np.asarray(backing),
                  None if centre_column is None else np.asarray(centre_column),
                  int(ball_groups), tuple(float(t) for t in thicknesses_m))
