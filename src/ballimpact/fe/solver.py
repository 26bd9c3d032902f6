"""Explicit central-difference solver: a layered axisymmetric ball hits a rigid plane.

The ball's south pole touches the plane z = 0 at t = 0, every node moving at -v_in along z.
Central difference (velocity form, constant increment) with lumped masses; internal forces from
`axisymmetric` (F-bar) and the materials' strain energies with Simo's Prony update; linear and
quadratic bulk viscosity; node-to-plane penalty contact with a stiffness derived from the contacting
elements. Every step is a pure JAX function; `lax.scan` advances a chunk of steps, `vmap` runs many
parameter sets at once, and a Python loop checks between chunks whether the ball has separated.

Energies (J): kinetic; internal work (the work of the internal forces, accumulated by the
trapezoidal rule); contact work; bulk-viscous dissipation; strain energy (the long-term strain
energy plus the energy held in the Maxwell branches); viscous dissipation = internal work - strain
energy - bulk-viscous dissipation. Energy balance error: max |KE + internal work - contact work -
KE0| / KE0 over the run.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from dataclasses import dataclass, field
from functools import partial
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from ..errors import InputError, InputWarning, SimulationError
from ..lumped.hertz import hertz_impact
from ..records import ImpactRecord
from .axisymmetric import (
    AxiGeometry,
    deformation,
    element_values,
    fbar,
    first_piola,
    gather_nodal,
    geometry,
    right_cauchy_green,
)
from .materials import Sym, energy_and_stress, prony_update
from .materials.stability import drucker_warnings
from .mesh import layered_sphere_mesh

HISTORY = ("time_s", "contact_force_n", "centre_z_m", "centre_velocity_z_m_s", "kinetic_energy_j",
           "internal_work_j", "contact_work_j", "strain_energy_j", "bulk_viscous_dissipation_j")


@dataclass(frozen=True)
class SolverOptions:
    """Numerical settings (SI). Defaults follow ABAQUS/Explicit where it has one."""

    element_size_m: float = 1.5e-3   # outer-surface element length; mean element side ~1.2 mm
    pole_element_size_m: float | None = None   # refinement toward the contact pole
    pole_zone_deg: float = 30.0
    bulk_viscosity_linear: float = 0.06
    bulk_viscosity_quadratic: float = 1.2
    penalty_scale: float = 1.0        # contact frequency sqrt(k/m) = sqrt(scale) c_d / L
    contact_damping: float = 0.0      # fraction of critical damping of each contact spring
    time_step_scale: float = 0.9      # safety factor on the element-by-element stable increment
    end_margin: float = 0.25          # simulated after separation, as a fraction of contact time
    time_limit_s: float | None = None  # default: 6 times a Hertz estimate of the contact time
    chunk_steps: int = 200
    mesh_radii_m: tuple[float, ...] = ()  # extra node circles (e.g. to mesh like another ball)

    def __post_init__(self) -> None:
        # (value, upper bound, zero allowed)
        checks = {"element_size_m": (self.element_size_m, math.inf, False),
                  "bulk_viscosity_linear": (self.bulk_viscosity_linear, 10.0, True),
                  "bulk_viscosity_quadratic": (self.bulk_viscosity_quadratic, 10.0, True),
                  "penalty_scale": (self.penalty_scale, 100.0, False),
                  "contact_damping": (self.contact_damping, 1.0, True),
                  "time_step_scale": (self.time_step_scale, 1.0, False),
                  "end_margin": (self.end_margin, 10.0, True)}
        for name, (value, high, zero_ok) in checks.items():
            low_ok = isinstance(value, (int, float)) and (value >= 0 if zero_ok else value > 0)
            if not (low_ok and value <= high):
                raise InputError(f"{name} = {value!r}: allowed range "
                                 f"{'[' if zero_ok else '('}0, {high:g}]")
        if self.time_limit_s is not None and not self.time_limit_s > 0:
            raise InputError(f"time_limit_s = {self.time_limit_s!r}: must be > 0")
        if not (isinstance(self.chunk_steps, int) and self.chunk_steps >= 1):
            raise InputError(f"chunk_steps = {self.chunk_steps!r}: must be an integer >= 1")


# --------------------------------------------------------------------------------------------
# Set-up on the host (NumPy): masses, stable increment, penalty stiffness, bulk viscosity factors.

def _layer_arrays(ball, geom: AxiGeometry, options: SolverOptions) -> dict[str, Any]:
    layers = ball.layers
    rho = np.array([layer.density_kg_m3 for layer in layers])
    wave = np.array([layer.material.wave_modulus_pa() for layer in layers])
    c_d = np.sqrt(wave / rho)
    element_layer = np.concatenate([np.full(b - a, i) for i, (a, b) in enumerate(geom.layer_slices)])
    length = geom.characteristic_length_m
    c_el, rho_el = c_d[element_layer], rho[element_layer]
    mass = rho @ geom.nodal_volume_m3
    m_surface = mass[geom.surface_nodes]
    c_surface = c_d[geom.surface_layer]
    l_surface = geom.surface_length_m
    penalty = options.penalty_scale * m_surface * (c_surface / l_surface) ** 2
    damping = options.contact_damping * 2.0 * np.sqrt(penalty * m_surface)
    xi = options.bulk_viscosity_linear
    dt_elements = np.min(length / c_el) * (math.sqrt(1.0 + xi * xi) - xi)
    dt_contact = np.min(l_surface / c_surface) * 2.0 / math.sqrt(4.0 + options.penalty_scale)
    dt = options.time_step_scale * min(dt_elements, dt_contact)
    return {"mass_kg": mass, "penalty_n_m": penalty, "contact_damping_n_s_m": damping,
            "dt_s": np.float64(dt),
            "bv_linear_pa_s": options.bulk_viscosity_linear * rho_el * c_el * length,
            "bv_quadratic_pa_s2": rho_el * (options.bulk_viscosity_quadratic * length) ** 2,
            "layers": [layer.material.constants() for layer in layers]}


def _hertz_contact_time_s(ball, speed: float) -> float:
    """Contact time of a Hertz sphere with the ball's softest long-term Young's modulus and
    nu = 0.5 (the longest plausible contact; for the default time limit)."""
    e_min = min(9 * m.bulk_modulus_pa(False) * m.shear_modulus_pa(False)
                / (3 * m.bulk_modulus_pa(False) + m.shear_modulus_pa(False))
                for m in (layer.material for layer in ball.layers))
    return hertz_impact(e_min, 0.5, ball.outer_radius_m, ball.mass_kg, speed)[2]


# --------------------------------------------------------------------------------------------
# The step (pure JAX).

@dataclass(frozen=True, eq=False)
class _Kernel:
    """Static data of one mesh and one ball structure; its methods are traced by JAX."""

    geom: AxiGeometry
    energies: tuple  # one energy function per layer
    bulk_relaxation: tuple  # per layer: does it have k_i > 0
    z_shift_m: float  # reference z of the south pole is -z_shift_m

    def initial_state(self, params, speed):
        g = self.geom
        n = len(g.nodes_m)
        zeros = jnp.zeros((2, n))
        v0 = zeros.at[1].set(-speed)
        mats = []
        for (a, b), consts, bulk in zip(g.layer_slices, params["layers"], self.bulk_relaxation):
            shape = (4, 4, b - a)  # (S_rr, S_zz, S_hoop, S_rz) at 4 Gauss points
            n_terms = consts["prony_g"].shape[-1]
            n_bulk = n_terms if bulk else 0  # without bulk relaxation its states are not kept
            mats.append({"s0_dev": jnp.zeros(shape),
                         "s0_vol": jnp.zeros(shape if bulk else (0, 4, b - a)),
                         "q_dev": jnp.zeros((n_terms,) + shape),
                         "q_vol": jnp.zeros((n_bulk,) + shape)})
        inf = jnp.array(jnp.inf)
        return {"u": zeros, "v": v0, "a": zeros, "t": jnp.array(0.0), "f_int": zeros,
                "f_contact": jnp.zeros(n), "mat": mats, "j0": jnp.ones(g.n_elements),
                "w_int": jnp.array(0.0), "w_contact": jnp.array(0.0),
                "d_bv": jnp.array(0.0),
                "peak_force": jnp.array(0.0), "t_peak": jnp.array(0.0), "u_peak": zeros,
                "t_start": inf, "t_separation": inf, "t_bad": inf,
                "stretch_min": jnp.array(1.0),
                "stretch_max": jnp.array(1.0)}

    def internal(self, params, u, mats, j0_prev, dt):
        """Internal nodal forces (2, n_nodes) at displacements u (2, n_nodes), new material
        states, centre J, stored strain energy (J), bulk-viscous power (W), min J and the range of
        the eigenvalues of C."""
        g = self.geom

        def kinematics(u_e):
            F2, Fh = deformation(g, u_e)
            Fb2, Fbh, J = fbar(F2, Fh)
            return (Fb2, Fbh), J

        (Fb2, Fbh), pull, J = jax.vjp(kinematics, element_values(g, u), has_aux=True)
        C = right_cauchy_green(Fb2, Fbh)
        stresses, new_mats, stored = [], [], 0.0
        for (a, b), energy, consts, mat in zip(g.layer_slices, self.energies, params["layers"],
                                               mats):
            (w_dev, s_dev), (w_vol, s_vol) = energy_and_stress(
                energy, Sym(*(c[:, a:b] for c in C[:4])), consts)
            s_dev, s_vol = jnp.stack(s_dev), jnp.stack(s_vol)
            tau = consts["prony_tau_s"]
            q_dev = prony_update(mat["q_dev"], mat["s0_dev"], s_dev, consts["prony_g"], tau, dt)
            if mat["q_vol"].shape[0]:  # bulk relaxation (k_i > 0) in this layer
                q_vol = prony_update(mat["q_vol"], mat["s0_vol"], s_vol, consts["prony_k"], tau, dt)
            else:
                q_vol = mat["q_vol"]
            stresses.append(s_dev + s_vol - q_dev.sum(axis=0) - q_vol.sum(axis=0))
            new_mats.append({"s0_dev": s_dev, "s0_vol": s_vol if q_vol.shape[0] else mat["s0_vol"],
                             "q_dev": q_dev, "q_vol": q_vol})
            w = g.volume_weight_m3[:, a:b]
            relaxed_dev = 1.0 - jnp.sum(consts["prony_g"])
            relaxed_vol = 1.0 - jnp.sum(consts["prony_k"])
            stored = stored + jnp.sum((relaxed_dev * w_dev + relaxed_vol * w_vol) * w)
            stored = stored + _branch_energy(q_dev, s_dev, consts["prony_g"],
                                             2.0 * consts["shear_modulus_pa"], w)
            if q_vol.shape[0]:
                stored = stored + _branch_energy(q_vol, s_vol, consts["prony_k"],
                                                 3.0 * consts["bulk_modulus_pa"], w)
        S = tuple(jnp.concatenate(stresses, axis=-1))
        j0 = J[4]
        rate = (j0 - j0_prev) / (dt * j0)  # volumetric strain rate at the centre (1/s)
        sigma_bv = rate * (params["bv_linear_pa_s"]
                           + params["bv_quadratic_pa_s2"] * jnp.maximum(-rate, 0.0))
        P2, Ph = first_piola(Fb2, Fbh, S, sigma_bv * j0)
        w = g.volume_weight_m3
        (f_e,) = pull((tuple(p * w for p in P2), Ph * w))
        f = gather_nodal(g, f_e)
        bv_power = jnp.sum(sigma_bv * rate * j0 * g.element_volume_m3)
        m_ = 0.5 * (C.xx + C.yy)
        d_ = jnp.sqrt(0.25 * (C.xx - C.yy) ** 2 + C.xy ** 2)
        lam2_min = jnp.minimum(jnp.min(m_ - d_), jnp.min(C.zz))
        lam2_max = jnp.maximum(jnp.max(m_ + d_), jnp.max(C.zz))
        return f, new_mats, j0, stored, bv_power, jnp.min(J), lam2_min, lam2_max

    def step(self, params, state, _):
        g = self.geom
        dt = params["dt_s"]
        mass = params["mass_kg"]
        off_axis = jnp.asarray(g.nodes_m[:, 0] > 0.0)  # radial motion is zero on the axis
        v_half = state["v"] + 0.5 * dt * state["a"]
        u = state["u"] + dt * v_half
        f_int, mats, j0, stored, bv_power, min_j, lam2_min, lam2_max = self.internal(
            params, u, state["mat"], state["j0"], dt)
        s = g.surface_nodes
        z = g.nodes_m[s, 1] + self.z_shift_m + u[1, s]
        penetration = jnp.maximum(-z, 0.0)
        normal = params["penalty_n_m"] * penetration \
            - params["contact_damping_n_s_m"] * v_half[1, s] * (penetration > 0)
        normal = jnp.maximum(normal, 0.0)
        f_contact = jnp.zeros(len(g.nodes_m)).at[s].set(normal)
        force = (-f_int).at[1].add(f_contact)
        a = force / mass
        a = a.at[0].multiply(off_axis)
        v = v_half + 0.5 * dt * a
        du = u - state["u"]
        w_int = state["w_int"] + 0.5 * jnp.sum((state["f_int"] + f_int) * du)
        w_contact = state["w_contact"] + 0.5 * jnp.sum((state["f_contact"] + f_contact) * du[1])
        t = state["t"] + dt
        total = jnp.sum(normal)
        m_total = jnp.sum(mass)
        v_cm = jnp.sum(mass * v[1]) / m_total
        z_cm = jnp.sum(mass * (g.nodes_m[:, 1] + self.z_shift_m + u[1])) / m_total
        kinetic = 0.5 * jnp.sum(mass * v * v)
        started = jnp.isfinite(state["t_start"])
        t_start = jnp.where(~started & (total > 0), t, state["t_start"])
        separating = started & (total <= 0) & (v_cm > 0) & jnp.isinf(state["t_separation"])
        # a new contact (the ball touching again) cancels a separation
        t_separation = jnp.where(total > 0, jnp.inf, jnp.where(separating, t, state["t_separation"]))
        new_peak = total > state["peak_force"]
        bad = ~jnp.isfinite(kinetic) | (min_j <= 0.0)
        new = {"u": u, "v": v, "a": a, "t": t, "f_int": f_int, "f_contact": f_contact, "mat": mats,
               "j0": j0, "w_int": w_int, "w_contact": w_contact,
               "d_bv": state["d_bv"] + dt * bv_power,
               "peak_force": jnp.maximum(total, state["peak_force"]),
               "t_peak": jnp.where(new_peak, t, state["t_peak"]),
               "u_peak": jnp.where(new_peak, u, state["u_peak"]),
               "t_start": t_start, "t_separation": t_separation,
               "t_bad": jnp.where(bad & jnp.isinf(state["t_bad"]), t, state["t_bad"]),
               "stretch_min": jnp.minimum(state["stretch_min"], jnp.sqrt(jnp.maximum(lam2_min, 0.0))),
               "stretch_max": jnp.maximum(state["stretch_max"], jnp.sqrt(lam2_max))}
        row = jnp.stack([t, total, z_cm, v_cm, kinetic, w_int, w_contact, stored, new["d_bv"]])
        return new, row

    def chunk(self, params, state, n_steps: int):
        return jax.lax.scan(partial(self.step, params), state, None, length=n_steps)


def _branch_energy(q, s0, g, modulus, weight):
    """Energy (J) stored in the Maxwell branches, exact for small strains.

    Branch i carries the stress h_i = g_i S0 - Q_i (Q_i (n_terms, 4, 4, n) is the part of the
    stress already relaxed) and stores h_i:h_i / (2 M_i) per unit volume, with M_i = g_i 2 mu
    (deviatoric; `modulus` = 2 mu) or k_i 3 K (bulk; `modulus` = 3 K). Relaxed branches store
    nothing, so at the end of an impact this term is small whatever its accuracy.
    """
    if q.shape[0] == 0:
        return 0.0
    h = g.reshape(-1, 1, 1, 1) * s0 - q
    hh = h[:, 0] ** 2 + h[:, 1] ** 2 + h[:, 2] ** 2 + 2.0 * h[:, 3] ** 2
    stiffness = g * modulus
    scale = jnp.where(stiffness > 0, 0.5 / jnp.where(stiffness > 0, stiffness, 1.0), 0.0)
    return jnp.sum(scale[:, None, None] * hh * weight)


_COMPILED: dict[Any, Any] = {}


def _compiled_chunk(kernel: _Kernel, n_steps: int, batched: bool):
    key = (id(kernel), n_steps, batched)
    if key not in _COMPILED:
        fn = partial(kernel.chunk, n_steps=n_steps)
        init = kernel.initial_state
        if batched:
            fn, init = jax.vmap(fn), jax.vmap(init)
        _COMPILED[key] = (jax.jit(fn), jax.jit(init))
    return _COMPILED[key]


# --------------------------------------------------------------------------------------------
# The driver (host).

@dataclass(frozen=True, eq=False)
class FEResult:
    """One simulated impact (SI). Histories are per step; `record` is an `ImpactRecord`."""

    ball_name: str
    impact_speed_m_s: float
    history: dict[str, np.ndarray]
    cor: float
    peak_force_n: float
    time_of_peak_s: float
    contact_time_s: float
    energy_balance_error: float
    stable_time_increment_s: float
    steps: int
    elements: int
    nodes: int
    mass_kg: float
    stretch_range: tuple[float, float]
    outer_radius_m: float
    moduli: tuple[str, ...]
    nodes_m: np.ndarray = field(repr=False)
    elements_connectivity: np.ndarray = field(repr=False)
    displacement_at_peak_m: np.ndarray = field(repr=False)
    layer_slices: tuple = ()
    wall_time_s: float = 0.0
    energies_j: dict[str, float] = field(default_factory=dict)

    @property
    def rebound_speed_m_s(self) -> float:
        return self.cor * self.impact_speed_m_s

    def summary(self) -> dict[str, Any]:
        """The scalar results, JSON-able, with SI unit suffixes."""
        return {"ball": self.ball_name, "impact_speed_m_s": self.impact_speed_m_s,
                "peak_force_n": self.peak_force_n, "time_of_peak_s": self.time_of_peak_s,
                "contact_time_s": self.contact_time_s, "cor": self.cor,
                "rebound_speed_m_s": self.rebound_speed_m_s,
                "energy_balance_error": self.energy_balance_error,
                "energies_j": dict(self.energies_j), "mass_kg": self.mass_kg,
                "elements": self.elements, "nodes": self.nodes, "steps": self.steps,
                "stable_time_increment_s": self.stable_time_increment_s,
                "principal_stretch_range": list(self.stretch_range),
                "moduli": self.moduli[0] if len(set(self.moduli)) == 1 else list(self.moduli),
                "wall_time_s": self.wall_time_s}

    def record(self):
        """The contact-force pulse as an `ImpactRecord` (with zero force before contact)."""
        t = self.history["time_s"]
        f = self.history["contact_force_n"]
        dt = t[1] - t[0]
        lead = np.arange(-max(3, int(0.05 * len(t))), 0) * dt
        time = np.concatenate([lead, [0.0], t])
        force = np.concatenate([np.zeros(len(lead) + 1), f])
        velocity = np.concatenate([np.full(len(lead) + 1, self.impact_speed_m_s),
                                   -self.history["centre_velocity_z_m_s"]])
        return ImpactRecord(time, force, velocity_m_s=velocity, mass_kg=self.mass_kg,
                            impact_speed_m_s=self.impact_speed_m_s,
                            rebound_speed_m_s=max(self.rebound_speed_m_s, 0.0),
                            metadata={"source": "fe", "ball": self.ball_name,
                                      "contact_time_s": self.contact_time_s})


def _structure(ball) -> tuple:
    """What a compiled run depends on: radii, material models, Prony terms, bulk relaxation."""
    return tuple((layer.outer_radius_m, type(layer.material), layer.material.sum_k > 0,
                   tuple((k, np.shape(v)) for k, v in sorted(layer.material.constants().items())))
                  for layer in ball.layers)


_KERNELS: dict[Any, _Kernel] = {}


def _kernel(ball, options: SolverOptions) -> _Kernel:
    key = (_structure(ball), options.element_size_m, options.pole_element_size_m,
           options.pole_zone_deg, tuple(options.mesh_radii_m))
    if key not in _KERNELS:
        radii = np.asarray(ball.layer_radii_m)
        extra = [r for r in options.mesh_radii_m if 0 < r < radii[-1]]
        mesh_radii = np.unique(np.concatenate([radii, extra]))
        mesh = layered_sphere_mesh(tuple(mesh_radii), options.element_size_m,
                                   options.pole_element_size_m, options.pole_zone_deg)
        # mesh rings -> ball layers: a ring belongs to the first layer that reaches its radius
        ring_layer = np.searchsorted(radii, mesh_radii - 1e-12 * radii[-1])
        mesh = dataclasses.replace(mesh, element_layer=ring_layer[mesh.element_layer],
                                   layer_radii_m=tuple(radii))
        geom = geometry(mesh)
        energies = tuple(type(layer.material).energy for layer in ball.layers)
        bulk = tuple(layer.material.sum_k > 0 for layer in ball.layers)
        _KERNELS[key] = _Kernel(geom, energies, bulk, ball.outer_radius_m)
    return _KERNELS[key]


def _stack(trees: list) -> Any:
    return jax.tree_util.tree_map(lambda *xs: np.stack(xs), *trees)


def _contact_end(time: np.ndarray, force: np.ndarray) -> float:
    """Time at which the force returns to zero, extrapolated from the last two positive samples."""
    positive = np.flatnonzero(force > 0)
    k = positive[-1]
    if k == 0 or k + 1 >= len(time) or force[k - 1] <= force[k]:
        return float(time[min(k + 1, len(time) - 1)])
    slope = (force[k - 1] - force[k]) / (time[k] - time[k - 1])
    return float(min(time[k] + force[k] / slope, time[k + 1]))


#: balls per vmapped group on a CPU, where larger groups run out of cache (universal ball on 2
#: cores, against single runs: groups of 4 ran 1.3x faster, of 8 0.93x, all 64 at once 0.66x)
CPU_GROUP_SIZE = 4


def default_group_size(n_balls: int) -> int:
    """Balls per vmapped group: `CPU_GROUP_SIZE` on a CPU, all of them on an accelerator."""
    return CPU_GROUP_SIZE if jax.default_backend() == "cpu" else max(n_balls, 1)


def simulate_batch(balls: list, impact_speed_m_s: float, options: SolverOptions = SolverOptions(),
                   progress=None, group_size: int | None = None) -> list[FEResult]:
    """Normal impacts of several balls with the same layer structure, vmapped in groups.

    The balls may differ in every material constant and density, not in the layer radii, material
    models or number of Prony terms. Each group of `group_size` balls is one vmapped run (default:
    all at once on an accelerator, `CPU_GROUP_SIZE` on a CPU); the last group is padded so that
    every group uses the same compiled program. `progress(t_s)` is called between chunks.
    """
    balls = list(balls)
    if group_size is None:
        group_size = default_group_size(len(balls))
    if not (isinstance(group_size, int) and group_size >= 1):
        raise InputError(f"group_size = {group_size!r}: must be an integer >= 1")
    if len(balls) <= group_size:
        return _simulate_group(balls, impact_speed_m_s, options, progress)
    results = []
    for start in range(0, len(balls), group_size):
        group = balls[start:start + group_size]
        padded = group + [group[-1]] * (group_size - len(group))
        results += _simulate_group(padded, impact_speed_m_s, options, progress)[:len(group)]
    return results


def _simulate_group(balls: list, impact_speed_m_s: float, options: SolverOptions,
                    progress) -> list[FEResult]:
    speed = float(impact_speed_m_s)
    if not (math.isfinite(speed) and speed > 0):
        raise InputError(f"impact_speed_m_s = {impact_speed_m_s!r}: must be > 0")
    if not balls:
        raise InputError("balls: need at least one ball")
    if any(_structure(b) != _structure(balls[0]) for b in balls):
        raise InputError("balls: a batch must share layer radii, material models and Prony terms")
    start = time.perf_counter()
    kernel = _kernel(balls[0], options)
    geom = kernel.geom
    per_ball = [_layer_arrays(b, geom, options) for b in balls]
    batched = len(balls) > 1
    params = _stack(per_ball) if batched else per_ball[0]
    chunk_fn, init_fn = _compiled_chunk(kernel, options.chunk_steps, batched)
    with jax.enable_x64(True):
        params = jax.tree_util.tree_map(jnp.asarray, params)
        state = init_fn(params, jnp.full((len(balls),), speed) if batched else jnp.asarray(speed))
        limits = np.array([options.time_limit_s or 6.0 * _hertz_contact_time_s(b, speed)
                           for b in balls])
        rows = []
        while True:
            state, chunk_rows = chunk_fn(params, state)
            rows.append(np.asarray(chunk_rows))
            t = np.atleast_1d(np.asarray(state["t"]))
            t_bad = np.atleast_1d(np.asarray(state["t_bad"]))
            t_start = np.atleast_1d(np.asarray(state["t_start"]))
            t_sep = np.atleast_1d(np.asarray(state["t_separation"]))
            if np.any(np.isfinite(t_bad)):
                i = int(np.argmax(np.isfinite(t_bad)))
                raise SimulationError(
                    f"ball {balls[i].name}: inverted element or non-finite state at "
                    f"t = {t_bad[i]:.4g} s (try a smaller time_step_scale or element size)")
            done = np.isfinite(t_sep) & (t >= t_sep + options.end_margin * (t_sep - t_start))
            if progress is not None:
                progress(float(t.min()))
            if np.all(done | (t >= limits)):
                break
        if not np.all(done):
            i = int(np.argmin(done))
            raise SimulationError(f"ball {balls[i].name}: no separation within the time limit "
                                  f"{limits[i]:.4g} s")
        state = jax.tree_util.tree_map(np.asarray, state)
    wall = time.perf_counter() - start
    history_all = np.concatenate(rows, axis=1 if batched else 0)
    if not batched:
        history_all = history_all[None]
        state = jax.tree_util.tree_map(lambda x: np.asarray(x)[None], state)
    results = []
    for i, ball in enumerate(balls):
        t_end = t_sep[i] + options.end_margin * (t_sep[i] - t_start[i])
        n = int(np.searchsorted(history_all[i, :, 0], t_end * (1 + 1e-12))) + 1
        h = {name: history_all[i, :n, j] for j, name in enumerate(HISTORY)}
        mass = float(np.sum(per_ball[i]["mass_kg"]))
        ke0 = 0.5 * mass * speed ** 2
        balance = h["kinetic_energy_j"] + h["internal_work_j"] - h["contact_work_j"] - ke0
        h["viscous_dissipation_j"] = (h["internal_work_j"] - h["strain_energy_j"]
                                      - h["bulk_viscous_dissipation_j"])
        h["energy_balance_error"] = balance / ke0
        final = {name: float(values[-1]) for name, values in h.items() if name.endswith("_j")}
        if min(final["viscous_dissipation_j"], final["bulk_viscous_dissipation_j"]) < -1e-3 * ke0:
            warnings.warn(f"ball {ball.name}: a negative dissipation at the end of the run "
                          f"({final['viscous_dissipation_j']:.3g} J viscous): the strain-energy "
                          "split is approximate at large strains", InputWarning, stacklevel=2)
        final["initial_kinetic_energy_j"] = ke0
        results.append(FEResult(
            ball_name=ball.name, impact_speed_m_s=speed, history=h,
            cor=float(h["centre_velocity_z_m_s"][-1] / speed),
            peak_force_n=float(state["peak_force"][i]), time_of_peak_s=float(state["t_peak"][i]),
            contact_time_s=_contact_end(h["time_s"], h["contact_force_n"]),
            energy_balance_error=float(np.max(np.abs(balance)) / ke0),
            stable_time_increment_s=float(per_ball[i]["dt_s"]), steps=n,
            elements=geom.n_elements, nodes=len(geom.nodes_m), mass_kg=mass,
            stretch_range=(float(state["stretch_min"][i]), float(state["stretch_max"][i])),
            outer_radius_m=ball.outer_radius_m,
            moduli=tuple(layer.material.moduli for layer in ball.layers),
            nodes_m=geom.nodes_m, elements_connectivity=geom.elements,
            layer_slices=geom.layer_slices,
            displacement_at_peak_m=state["u_peak"][i].T, wall_time_s=wall / len(balls),
            energies_j=final))
    for result, ball in zip(results, balls):
        for message in drucker_warnings(ball, *result.stretch_range):
            warnings.warn(f"{message}: principal stretches in this range occurred in the ball "
                          "(in some layer)", InputWarning, stacklevel=2)
    return results


def simulate(ball, impact_speed_m_s: float, options: SolverOptions = SolverOptions(),
             progress=None) -> FEResult:
    """Normal impact of one ball on a rigid plane at `impact_speed_m_s` (m/s)."""
    return _simulate_group([ball], impact_speed_m_s, options, progress)[0]
