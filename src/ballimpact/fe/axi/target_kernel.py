"""The explicit step of the axisymmetric ball on a layered target (pure JAX): a pad, a plate or a
helmet's shell and liner (`target_mesh`), its base fixed or carried by a backing
(`fe.backing.PlaneBacking`: a headform, a hand).

One mesh: the ball's nodes first, then the target's; the elements of the ball's layers, then
the target's (each a group with its material). The ball's surface nodes of its lower hemisphere
meet the target's top surface, interpolated linearly between its nodes at the ball node's
current radius; the contact force acts along z (the surface's slope across a contact patch is
small: on a cap of radius R_c the normal turns by a / R_c at the patch's edge, a the contact
radius), on the ball node and, split by the interpolation weights, on the two top nodes. The
base's nodes are glued: fixed, or moving along z with the backing, which they drive with the
force the target puts on them (their own mass left out of the backing: grams against kg).

Energies: the kinetic energy of every node but the base's; the internal work of every element
(the ball's and the target's, per group in `w_layers`); the "contact work" of the histories is
the work done on the ball and the target from outside the elements: by the contact forces on
both sides (its penalty springs and dashpots) and by the backing on the base.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import partial
from typing import Any

import jax.numpy as jnp
import numpy as np

from ..steps import LANCZOS_STEPS, STATE, named_tuple, step_events
from .kernel import AxiParams, BACKING_HISTORY, HISTORY, Kernel, extremes

AxiTargetState = named_tuple(
    "AxiTargetState", __name__, "The axisymmetric ball-on-target kernel's state between steps "
    "(SI; nodal arrays (2, n_nodes)).", STATE,
    {"f_e": "element corner forces (N), the last step's",
     "backing_q": "the backing's modal coordinates (sqrt(kg) m)",
     "backing_qd": "their velocities", "backing_qdd": "their accelerations",
     "w_backing": "work of the base's force on the backing (J)",
     "d_backing": "the backing's dashpot dissipation (J)",
     "f_base": "the force the target puts on its base, positive pushing it down (-z; N)",
     "w_layers": "internal work per element group (J): the ball's layers, the target's"})


@dataclass(frozen=True, eq=False)
class TargetKernel(Kernel):
    """`Kernel` on a mesh of the ball and a target (module docstring)."""

    ball_nodes: int = 0              # nodes 0 .. ball_nodes - 1 are the ball's
    ball_layers: int = 0             # element groups 0 .. ball_layers - 1 are the ball's
    contact_nodes: Any = None        # the ball's surface nodes that can meet the target
    top_nodes: Any = None            # the target's top surface, from the axis out
    base_nodes: Any = None           # the target's base
    axis_layer_nodes: Any = None     # (target layers, 2): each layer's top and bottom on the axis
    thicknesses_m: tuple = ()        # the target's layers' thicknesses (m)

    @classmethod
    def build_on(cls, kernel: Kernel, ball_nodes: int, ball_layers: int, contact_nodes,
                 top_nodes, base_nodes, axis_layer_nodes, thicknesses_m) -> TargetKernel:
        fields = {f.name: getattr(kernel, f.name) for f in dataclasses.fields(Kernel)}
        return cls(**fields, ball_nodes=ball_nodes, ball_layers=ball_layers,
                   contact_nodes=np.asarray(contact_nodes), top_nodes=np.asarray(top_nodes),
                   base_nodes=np.asarray(base_nodes),
                   axis_layer_nodes=np.asarray(axis_layer_nodes),
                   thicknesses_m=tuple(thicknesses_m))

    @property
    def target_layers(self) -> int:
        return len(self.thicknesses_m)

    @property
    def history_names(self) -> tuple[str, ...]:
        """`Kernel`'s, then the force on the base (N, positive pushing it down), the momentum
        along z of the ball, the target and a backing's first mode (N s: a free rigid
        backing's), each target layer's internal work (J) and compression on the axis (its
        thickness' loss over its thickness), and the backing's."""
        n = range(self.target_layers)
        names = (HISTORY + ("transmitted_force_n", "momentum_z_n_s")
                 + tuple(f"target_layer_{k}_work_j" for k in n)
                 + tuple(f"target_layer_{k}_compression" for k in n))
        if self.backed:
            m = range(self.backing_modes)
            names += (BACKING_HISTORY + tuple(f"backing_q_{k}" for k in m)
                      + tuple(f"backing_qd_{k}" for k in m))
        return names

    def _masks(self):
        n = len(self.geom.nodes_m)
        ball = np.zeros(n)
        ball[:self.ball_nodes] = 1.0
        moving = np.ones(n)
        moving[self.base_nodes] = 0.0
        return jnp.asarray(ball, self.dtype), jnp.asarray(moving, self.dtype)

    def initial_state(self, params, speed):
        n = len(self.geom.nodes_m)
        zeros = self.zeros((2, n))
        scalar = partial(jnp.array, dtype=self.dtype)
        ball, _ = self._masks()
        omega2, x_top = self.max_frequency_squared(params, zeros, None, LANCZOS_STEPS)
        dt = params.increment_factor / jnp.sqrt(omega2)
        backing = jnp.zeros_like(params.backing_velocity0)
        inf = jnp.array(jnp.inf, self.dtype)
        return AxiTargetState(
            backing_q=backing, backing_qd=params.backing_velocity0, backing_qdd=backing,
            w_backing=scalar(0.0), d_backing=scalar(0.0), f_base=scalar(0.0),
            w_layers=self.zeros(len(self.geom.layer_slices)),
            u=zeros, v=zeros.at[1].set(-speed * ball), a=zeros, t=scalar(0.0), dt=dt, dt0=dt,
            x_top=x_top, f_e=self.zero_corner_forces(), f_contact=self.zeros(n),
            mat=self.initial_materials(params), j0=jnp.ones(self.geom.n_elements, self.dtype),
            sigma_bv=self.zeros(self.geom.n_elements),
            ke0=0.5 * params.ball_mass_kg * speed * speed, w_int=scalar(0.0),
            w_contact=scalar(0.0), d_bv=scalar(0.0), peak_force=scalar(0.0),
            t_peak=scalar(0.0), u_peak=zeros, t_start=inf, t_separation=inf, t_bad=inf,
            t_energy=inf, stretch_min=scalar(1.0), stretch_max=scalar(1.0))

    # ---- contact -----------------------------------------------------------------------------
    def _pairs(self, u):
        """For each contact node, the top segment under it at displacements u: its nodes' ids
        (2, n_c), their weights (2, n_c) and whether the node is over the target."""
        x = self.geom.nodes_m
        top, c = self.top_nodes, self.contact_nodes
        r_top = x[top, 0] + u[0, top]
        r = x[c, 0] + u[0, c]
        k = jnp.clip(jnp.searchsorted(r_top, r) - 1, 0, top.size - 2)
        r0, r1 = r_top[k], r_top[k + 1]
        w1 = jnp.clip((r - r0) / (r1 - r0), 0.0, 1.0)
        ids = jnp.stack([jnp.asarray(top)[k], jnp.asarray(top)[k + 1]])
        return ids, jnp.stack([1.0 - w1, w1]), r <= r_top[-1]

    def target_contact(self, params, u, v_half):
        """Normal contact forces (n_c,) of the ball's contact nodes on the target's top, and the
        nodal force vector along z (n_nodes,) on both sides."""
        x, c = jnp.asarray(self.geom.nodes_m), self.contact_nodes
        ids, w, over = self._pairs(u)
        z_surface = jnp.sum(w * (x[ids, 1] + u[1, ids]), axis=0)
        v_surface = jnp.sum(w * v_half[1, ids], axis=0)
        penetration = jnp.maximum(z_surface - (x[c, 1] + u[1, c]), 0.0) * over
        k, damping = params.penalty_n_m, params.contact_damping_n_s_m
        normal = k * penetration - damping * (v_half[1, c] - v_surface) * (penetration > 0)
        normal = jnp.maximum(normal, 0.0)
        f = self.zeros(len(x)).at[c].add(normal)
        f = f.at[ids[0]].add(-w[0] * normal).at[ids[1]].add(-w[1] * normal)
        return normal, f

    # ---- the step ----------------------------------------------------------------------------
    def step(self, params, t0, state, i):
        g = self.geom
        dt = state.dt
        mass = params.mass_kg
        ball, moving = self._masks()
        base = self.base_nodes
        off_axis = g.nodes_m[:, 0] > 0.0
        v_half = state.v + 0.5 * dt * state.a
        u = state.u + dt * v_half
        if self.backed:
            phi, cmat = params.backing_shape_1_sqrt_kg, params.backing_damping_1_s
            qd_half = state.backing_qd + 0.5 * dt * state.backing_qdd
            q = state.backing_q + dt * qd_half
            plane_z, plane_v = phi @ q, phi @ qd_half
        else:
            plane_z = plane_v = jnp.asarray(0.0, self.dtype)
        # the base glued: on the ground or on the backing
        u = u.at[0, base].set(0.0).at[1, base].set(plane_z)
        v_half = v_half.at[0, base].set(0.0).at[1, base].set(plane_v)
        f_int, mats, j0, stored, e_hg, sigma_bv, J, lam2_min, lam2_max, f_e = self.internal(
            params, u, state.mat, state.j0, dt)
        normal, f_contact = self.target_contact(params, u, v_half)
        f_base = jnp.sum(f_int[1, base])  # the backing holds the base against the target
        a = (-f_int).at[1].add(f_contact) / mass
        a = (a.at[0].multiply(off_axis)) * moving
        if self.backed:
            damping = cmat @ qd_half
            qdd = -phi * f_base - damping - params.backing_omega2_1_s2 * q
            qd = qd_half + 0.5 * dt * qdd
            w_backing = state.w_backing - 0.5 * (state.f_base + f_base) * (
                plane_z - phi @ state.backing_q)
            d_backing = state.d_backing + dt * (qd_half @ damping)
            backing = {"backing_q": q, "backing_qd": qd, "backing_qdd": qdd,
                       "w_backing": w_backing, "d_backing": d_backing}
            v_base, a_base = phi @ qd, phi @ qdd
            backing_row = [plane_z, v_base, a_base,
                           0.5 * jnp.sum(qd * qd + params.backing_omega2_1_s2 * q * q),
                           w_backing, d_backing, *q, *qd]
        else:
            backing = {k: getattr(state, k) for k in ("backing_q", "backing_qd", "backing_qdd",
                                                      "w_backing", "d_backing")}
            v_base = a_base = 0.0
            backing_row = []
        v = v_half + 0.5 * dt * a
        v = v.at[1, base].set(v_base)
        a = a.at[1, base].set(a_base)
        du = u - state.u
        work_e, bv_e = self.element_work(state, u, f_e, j0, sigma_bv)
        stored, e_hg, dw_int, dd_bv = jnp.sum(jnp.stack([stored, e_hg, work_e, bv_e]), axis=1)
        w_layers = state.w_layers + jnp.stack([jnp.sum(work_e[a_:b_])
                                               for a_, b_ in g.layer_slices])
        kinetic, momentum_z, moment_z, dw_contact, momentum = jnp.sum(jnp.stack([
            0.5 * mass * moving * (v[0] * v[0] + v[1] * v[1]), ball * mass * v[1],
            ball * mass * (g.nodes_m[:, 1] + u[1]),
            0.5 * (state.f_contact + f_contact) * du[1], moving * mass * v[1]]), axis=1)
        if self.backed:
            momentum = momentum + backing["backing_qd"][0] / params.backing_shape_1_sqrt_kg[0]
        # the backing's work on the base (trapezoidal): it moves the base by plane_z's change
        dw_base = 0.5 * (state.f_base + f_base) * (plane_z - (
            params.backing_shape_1_sqrt_kg @ state.backing_q if self.backed else 0.0))
        min_j, lam2_min, lam2_max = extremes(J, lam2_min, lam2_max)
        w_int = state.w_int + dw_int
        w_contact = state.w_contact + dw_contact + dw_base
        d_bv = state.d_bv + dd_bv
        t = t0 + (i + 1) * dt
        total = jnp.sum(normal)
        v_cm = momentum_z / params.ball_mass_kg
        z_cm = moment_z / params.ball_mass_kg - g.nodes_m[self.top_nodes[0], 1]
        axis_top, axis_bottom = self.axis_layer_nodes[:, 0], self.axis_layer_nodes[:, 1]
        compression = (u[1, axis_bottom] - u[1, axis_top]) / jnp.asarray(self.thicknesses_m,
                                                                          self.dtype)
        v_top = v[1, self.top_nodes[0]]
        new = AxiTargetState(
            u=u, v=v, a=a, t=t, dt=dt, dt0=state.dt0, x_top=state.x_top, f_e=f_e,
            f_contact=f_contact, mat=mats, j0=j0, sigma_bv=sigma_bv, ke0=state.ke0,
            w_int=w_int, w_contact=w_contact, d_bv=d_bv, f_base=f_base, w_layers=w_layers,
            **backing,
            # separation: the ball's centre moving away from the target's top on the axis
            **step_events(state, t, total, v_cm - v_top, u, kinetic, w_int, w_contact, min_j,
                          lam2_min, lam2_max, params.energy_error_limit))
        row = jnp.stack([t, total, z_cm, v_cm, kinetic, w_int, w_contact, stored, d_bv, e_hg,
                         f_base, momentum, *w_layers[self.ball_layers:], *compression]
                        + backing_row)
        return new, row

    # ---- the stable increment ----------------------------------------------------------------
    def frequency_mask(self):
        """Free degrees of freedom: radial motion zero on the axis, the base glued."""
        mask = super().frequency_mask()
        return mask.at[:, self.base_nodes].set(0.0)

    def contact_springs(self, params, v):
        """K_contact v (2, n_nodes): each contact node's spring to the top surface under it at
        rest, every spring active (a two-mass spring where the target's nodes are light)."""
        ids, w, _ = self._pairs(self.zeros(v.shape))
        c = self.contact_nodes
        s = params.penalty_n_m * (v[1, c] - jnp.sum(w * v[1, ids], axis=0))
        out = self.zeros(v.shape).at[1, c].add(s)
        return out.at[1, ids[0]].add(-w[0] * s).at[1, ids[1]].add(-w[1] * s)


def target_params(params: AxiParams, ball_nodes: int) -> AxiParams:
    """The ball's mass alone (the COR and the impact energy are the ball's)."""
    return params._replace(ball_mass_kg=np.sum(params.mass_kg[:ball_nodes]))
