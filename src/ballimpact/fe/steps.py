"""What the explicit kernels of both geometries share (pure JAX): chunks of steps with the
stable increment re-estimated before each (`ChunkedSteps`), the step's events
(`step_events`), the materials' stresses with Simo's Prony update (`material_stresses`), and
the cast of a kernel's parameters to its precision (`cast`).

The kernels: `fe.axi.kernel.Kernel` (axisymmetric quads) and `fe.hex.kernel.Kernel`
(hexahedra); the run loop that drives them is `fe.driver`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..constitutive import MaterialConstants, Sym, energy_and_stress, prony_update
from .stable_increment import alternating_start, lanczos_largest, shrunk_increment

#: Lanczos steps for the largest eigenvalue of the assembled system at the start (the estimate
#: agrees with ARPACK's to 1e-12 on the default meshes; tests/fe/test_fe_engine.py) and for the
#: re-estimate before each chunk, started from the previous top Ritz vector
LANCZOS_STEPS = 40
REFRESH_LANCZOS_STEPS = 8


#: the parameters every kernel has (SI), and what they hold
PARAMS = {"bv_linear_pa_s": "linear bulk-viscosity coefficient per element (Pa s)",
          "bv_quadratic_pa_s2": "quadratic bulk-viscosity coefficient per element (Pa s^2)",
          "contact_damping_n_s_m": "contact dashpots (N s/m)",
          "energy_error_limit": "energy-balance limit (fraction of the initial kinetic energy)",
          "hourglass_n_m": "hourglass stiffness per element (N/m)",
          "increment_factor": "stable increment = factor / omega_max",
          "mass_kg": "nodal masses (kg)",
          "penalty_n_m": "contact penalty springs per contact node (N/m)"}
#: the state every kernel has between steps (SI), and what it holds
STATE = {"a": "nodal accelerations (m/s^2)", "d_bv": "bulk-viscous dissipation (J)",
         "dt": "the increment (s)", "dt0": "the first increment (s)",
         "f_contact": "contact forces on the nodes (N)",
         "j0": "volume ratio J at the element centres", "ke0": "initial kinetic energy (J)",
         "mat": "material states per layer or group (the Prony branches)",
         "peak_force": "largest contact force so far (N)",
         "sigma_bv": "bulk-viscous pressure per element (Pa)",
         "stretch_max": "largest principal stretch so far",
         "stretch_min": "smallest principal stretch so far", "t": "time (s)",
         "t_bad": "first non-finite or inverted state (s; inf: none)",
         "t_energy": "first energy-balance error above the limit (s; inf: none)",
         "t_peak": "time of the peak force (s)", "t_separation": "separation (s; inf: none yet)",
         "t_start": "first contact (s; inf: none yet)", "u": "nodal displacements (m)",
         "u_peak": "displacements at the peak force (m)", "v": "nodal velocities (m/s)",
         "w_contact": "work of the contact forces (J)", "w_int": "internal work (J)",
         "x_top": "top Ritz vector of the last increment estimate"}


#: an array field of a kernel's parameters or state: NumPy (float64, built on the host) or JAX
#: (in the kernel's precision, traced)
Array = jax.Array | np.ndarray
#: the fields that are not one array, and their types
FIELD_TYPES = {"groups": list[MaterialConstants], "mat": list["PronyState"]}


class PronyState(NamedTuple):
    """The material state of one layer or group at its integration points: the instantaneous
    deviatoric and volumetric stresses of the last step (`s0_dev`, `s0_vol`, Pa; components
    first) and the Maxwell branches' overstresses (`q_dev`, `q_vol`, Pa; Prony terms first). A
    layer without bulk relaxation keeps no volumetric branches (`q_vol` and `s0_vol` of size 0
    along their first axis). Fields in alphabetical order: it flattens as the dict it replaced
    did."""

    q_dev: Array
    q_vol: Array
    s0_dev: Array
    s0_vol: Array


jax.export.register_namedtuple_serialization(PronyState, serialized_name="ballimpact.PronyState")


def named_tuple(name: str, module: str, doc: str, shared: dict, own: dict) -> type:
    """A kernel's parameters or state: a NamedTuple of the `shared` and the geometry's `own`
    fields (name -> what it holds), typed (`Array`, or `FIELD_TYPES`), in alphabetical order,
    so that it flattens as the dict it replaced did, registered with `jax.export` (the programs
    kept on disk, `fe.programs`, serialize their arguments' and results' structure)."""
    fields = {**shared, **own}
    cls = NamedTuple(name, [(field, FIELD_TYPES.get(field, Array)) for field in sorted(fields)])
    cls.__module__ = module
    cls.__doc__ = doc + "\n\n" + "\n".join(f"- `{f}`: {fields[f]}" for f in sorted(fields))
    jax.export.register_namedtuple_serialization(cls, serialized_name=f"ballimpact.{name}")
    return cls


def cast(tree, dtype):
    """Floating arrays of a pytree (NumPy) in `dtype`."""
    return jax.tree_util.tree_map(
        lambda x: np.asarray(x, dtype) if np.issubdtype(np.asarray(x).dtype, np.floating)
        else np.asarray(x), tree)


def step_events(state, t, force, velocity_z, u, kinetic, w_int, w_contact, min_j, lam2_min,
                lam2_max, energy_error_limit) -> dict:
    """What a step of either kernel flags in its state at time t (s): the contact's start and
    separation (the normal force `force` (N) gone while the centre moves away, `velocity_z`
    (m/s) > 0; a new contact cancels a separation), the peak force with its time and
    displacements `u` (None: not kept, which saves the step a write of every displacement), the
    first non-finite or inverted state (`min_j` <= 0), the first energy balance error above
    `energy_error_limit` of the initial kinetic energy, and the range of principal stretches
    (from `lam2_min`, `lam2_max`: the step's extreme eigenvalues of C)."""
    started = jnp.isfinite(state.t_start)
    separating = started & (force <= 0) & (velocity_z > 0) & jnp.isinf(state.t_separation)
    new_peak = force > state.peak_force
    bad = ~jnp.isfinite(kinetic) | (min_j <= 0.0)
    ke0 = state.ke0
    energy_bad = jnp.abs(kinetic + w_int - w_contact - ke0) > energy_error_limit * ke0
    return {"t_start": jnp.where(~started & (force > 0), t, state.t_start),
            "t_separation": jnp.where(force > 0, jnp.inf,
                                      jnp.where(separating, t, state.t_separation)),
            "peak_force": jnp.maximum(force, state.peak_force),
            "t_peak": jnp.where(new_peak, t, state.t_peak),
            "u_peak": state.u_peak if u is None else jnp.where(new_peak, u, state.u_peak),
            "t_bad": jnp.where(bad & jnp.isinf(state.t_bad), t, state.t_bad),
            "t_energy": jnp.where(energy_bad & jnp.isinf(state.t_energy), t,
                                  state.t_energy),
            "stretch_min": jnp.minimum(state.stretch_min,
                                       jnp.sqrt(jnp.maximum(lam2_min, 0.0))),
            "stretch_max": jnp.maximum(state.stretch_max, jnp.sqrt(lam2_max))}


class ChunkedSteps(ABC):
    """The abstract explicit kernel: chunks of steps, each after re-estimating the stable
    increment from the assembled system. A geometry's kernel (a frozen dataclass holding what
    its compiled programs depend on, with a `geom` and a `dtype`) provides the methods below;
    its parameters and state are NamedTuples with at least the fields these methods read
    (`mass_kg`, `increment_factor`, `bv_linear_pa_s`, `bv_quadratic_pa_s2`; `u`, `t`, `dt`,
    `dt0`, `x_top` and the events of `step_events`)."""

    #: where the start increment is estimated (`LANCZOS_STEPS`): in the first chunk (True;
    #: `initial_state` leaves dt = dt0 = 0 and x_top `alternating_start`), in the same loop as
    #: the later re-estimates, or in `initial_state` (False). The operator, a Jacobian-vector
    #: product of the internal forces, is most of a kernel's compilation: in the first chunk it
    #: is compiled into one program, not two (the 3D kernel's compilation 8.4 -> 5.8 s). The
    #: axisymmetric kernel keeps False: the first chunk's estimate differs by an ulp (u = 0 is
    #: no longer a constant XLA folds), which moves every run at round-off, and the 800-run
    #: universal study's tau1 interval coverage sits at its limit (0.8; it fell to 0.7875)
    first_estimate_in_chunk = False

    @abstractmethod
    def initial_state(self, params, *condition):
        """The state at first touch, the stable increment estimated (`LANCZOS_STEPS`), or left
        to the first chunk (`first_estimate_in_chunk`)."""

    @abstractmethod
    def step(self, params, t0, state, i):
        """(new state, history row) of step i of a chunk started at t0 (s)."""

    @abstractmethod
    def internal(self, params, u, mats, j0_prev, dt):
        """Internal nodal forces first, then what the step needs of the elements."""

    @abstractmethod
    def initial_materials(self, params) -> list:
        """The material states at rest, per layer or element group."""

    @abstractmethod
    def zeros(self, shape):
        """Zeros of the kernel's dtype."""

    @abstractmethod
    def frequency_mask(self):
        """The free degrees of freedom (components first), 1 or 0."""

    @abstractmethod
    def contact_springs(self, params, v):
        """The contact springs' K v, every spring active (components first)."""

    def chunk(self, params, state, n_steps: int):
        """`n_steps` steps, after re-estimating the stable increment at the current state (8
        Lanczos steps from the last top Ritz vector; with `first_estimate_in_chunk`, the first
        chunk, dt0 still 0, makes the start estimate of `LANCZOS_STEPS` in the same loop)."""
        if self.first_estimate_in_chunk:
            first = state.dt0 <= 0
            omega2, x_top = self.max_frequency_squared(params, state.u, state.x_top,
                                                       REFRESH_LANCZOS_STEPS, first)
            start = params.increment_factor / jnp.sqrt(omega2)
            dt0 = jnp.where(first, start, state.dt0)
            dt = jnp.where(first, start,
                           shrunk_increment(state.dt, dt0, omega2, params.increment_factor))
        else:
            omega2, x_top = self.max_frequency_squared(params, state.u, state.x_top,
                                                       REFRESH_LANCZOS_STEPS)
            dt0 = state.dt0
            dt = shrunk_increment(state.dt, dt0, omega2, params.increment_factor)
        state = state._replace(dt=dt, dt0=dt0, x_top=x_top)
        steps = jnp.arange(n_steps, dtype=self.dtype)
        return jax.lax.scan(partial(self.step, params, state.t), state, steps)

    def max_frequency_squared(self, params, u, start, steps: int, first=None):
        """Upper estimate of omega_max^2 (1/s^2) of M^-1 (K + K_contact) at displacements u
        (components first), with the instantaneous moduli and every contact spring active, by
        `steps` Lanczos steps from `start` (flat; None: a fixed vector), and the top Ritz
        vector. `first` (a traced boolean, or None): `LANCZOS_STEPS` steps where it holds."""
        elastic = params._replace(bv_linear_pa_s=jnp.zeros_like(params.bv_linear_pa_s),
                       bv_quadratic_pa_s2=jnp.zeros_like(params.bv_quadratic_pa_s2))
        mats = self.initial_materials(params)
        ones = jnp.ones(self.geom.n_elements, self.dtype)
        # an increment far below any relaxation time: the tangent at the instantaneous moduli
        tiny_dt = jnp.asarray(1e-15, self.dtype)

        def forces(u):
            return self.internal(elastic, u, mats, ones, tiny_dt)[0]

        scale = 1.0 / jnp.sqrt(params.mass_kg)
        mask = self.frequency_mask()

        def apply(x):
            v = x.reshape(u.shape) * scale * mask
            _, kv = jax.jvp(forces, (u,), (v,))
            return ((kv + self.contact_springs(params, v)) * scale * mask).reshape(-1)

        if start is None:
            start = alternating_start(mask, self.dtype)
        value, residual, vector = lanczos_largest(
            apply, start, steps, None if first is None else LANCZOS_STEPS, first)
        return value + residual, vector


def material_stresses(slices, energies, constants, C, mats, dt):
    """Second Piola-Kirchhoff stresses, new Prony states and stored energy densities of every
    point, layer by layer (`slices` of the last, element axis).

    C: components (4 for axisymmetric states, 6 in 3D), each (..., n_el). Returns the stress
    components (elements last), the new material states and the density (J/m^3, (..., n_el)):
    the long-term strain energy plus the energy held in the Maxwell branches."""
    stresses, new_mats, densities = [], [], []
    for (a, b), energy, consts, mat in zip(slices, energies, constants, mats):
        (w_dev, s_dev), (w_vol, s_vol) = energy_and_stress(
            energy, Sym(*(c[..., a:b] for c in C)), consts.hyperelastic)
        s_dev, s_vol = jnp.stack(s_dev), jnp.stack(s_vol)
        tau = consts.prony_tau_s
        q_dev = prony_update(mat.q_dev, mat.s0_dev, s_dev, consts.prony_g, tau, dt)
        if mat.q_vol.shape[0]:  # bulk relaxation (k_i > 0) in this layer
            q_vol = prony_update(mat.q_vol, mat.s0_vol, s_vol, consts.prony_k, tau, dt)
        else:
            q_vol = mat.q_vol
        # sums over the Prony terms written out (a reduction is a slow pass of its own)
        stresses.append(s_dev + s_vol - sum(q_dev) - sum(q_vol))
        new_mats.append(PronyState(q_dev=q_dev, q_vol=q_vol, s0_dev=s_dev,
                                   s0_vol=s_vol if q_vol.shape[0] else mat.s0_vol))
        density = ((1.0 - jnp.sum(consts.prony_g)) * w_dev
                   + (1.0 - jnp.sum(consts.prony_k)) * w_vol)
        density = density + _branch_energy(q_dev, s_dev, consts.prony_g,
                                           2.0 * consts.shear_modulus_pa)
        if q_vol.shape[0]:
            density = density + _branch_energy(q_vol, s_vol, consts.prony_k,
                                               3.0 * consts.bulk_modulus_pa)
        densities.append(density)
    return tuple(jnp.concatenate(stresses, axis=-1)), new_mats, jnp.concatenate(densities, axis=-1)


def _branch_energy(q, s0, g, modulus):
    """Energy density (J/m^3, per point) stored in the Maxwell branches, exact for small strains.

    Branch i carries the stress h_i = g_i S0 - Q_i (Q_i (n_terms, n_comps, ...) is the part of
    the stress already relaxed; components xx, yy, zz, then the shear ones) and stores
    h_i:h_i / (2 M_i) per unit volume, with M_i = g_i 2 mu (deviatoric; `modulus` = 2 mu) or
    k_i 3 K (bulk; `modulus` = 3 K). Relaxed branches store nothing, so at the end of an impact
    this term is small whatever its accuracy.
    """
    if q.shape[0] == 0:
        return 0.0
    h = g.reshape((-1,) + (1,) * (q.ndim - 1)) * s0 - q
    hh = h[:, 0] ** 2 + h[:, 1] ** 2 + h[:, 2] ** 2
    for k in range(3, h.shape[1]):
        hh = hh + 2.0 * h[:, k] ** 2
    stiffness = g * modulus
    scale = jnp.where(stiffness > 0, 0.5 / jnp.where(stiffness > 0, stiffness, 1.0), 0.0)
    return sum(scale[i] * hh[i] for i in range(q.shape[0]))
