"""Oblique impacts of layered balls in 3D: the driver (host side).

Builds the hexahedral mesh (a half model on the plane of incidence unless told otherwise), the
per-run parameters, and runs `kernel.Kernel` in chunks until the ball has left the surface (plus
a margin), as `fe.solver` does for the axisymmetric engine; several impact conditions of one ball
run as one vmapped batch. Extensive results (forces, energies, mass) are for the whole ball: a
half model's are doubled.

Results: normal COR e_n = v_z' / (-v_z), tangential COR e_t = v_x' / v_x (the centre of mass, as
ball-sports studies quote it), the contact point's tangential COR -(v_x' - w' R) / (v_x - w R),
rebound angle from the normal atan(v_x' / v_z') and rebound spin (`ImpactCondition` sign).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field, replace
from typing import Any

import jax
import numpy as np

from ..errors import InputError, InputWarning
from ..fe.estimates import hertz_contact_time_s, hertz_series_impact, time_limit_default
from ..fe.progress import RunEstimate
from ..fe.driver import RunFigures, run_chunks
from ..fe.solver import contact_end_time, impact_speeds, warn_unresolved_contact
from ..plausibility import check_allow
from ..fe.stable_increment import increment_factor
from ..records import ImpactRecord
from ..fe.hex import kernel as kernel_module
from ..fe.hex.element import geometry
from ..fe.hex.kernel import HISTORY, HexParams, Kernel
from ..fe.hex.mesh import (
    HexMesh,
    graded_line,
    ball_mesh,
    combine,
    estimate_ball_mesh,
    graded_depths_m,
    pole_cell_growth,
    pole_spacing_m,
    slab_mesh,
    uniform_depths_m,
)
from .contact_grading import grading_for_contact
from .options import ImpactCondition, Options3D
from .target import check_target_width

__all__ = ["ObliqueResult", "estimate_oblique", "simulate_oblique", "simulate_oblique_batch"]


@dataclass(frozen=True, eq=False)
class ObliqueResult(RunFigures):
    """One simulated oblique impact (SI; `fe.driver.RunFigures` and the below; forces and
    energies of the whole ball)."""

    condition: ImpactCondition
    normal_cor: float
    tangential_cor: float
    contact_point_tangential_cor: float
    rebound_angle_deg: float
    rebound_spin_rad_s: float
    rebound_speed_m_s: float
    energies_j: dict[str, float]
    half_model: bool
    target: str
    wall_time_s: float
    pole_grading: float = float("nan")       # the mesh's (set by `contact_elements` if given)
    pole_spacing_m: float = float("nan")     # arc spacing of the elements at the contact pole
    frames: list = field(default_factory=list, repr=False)   # `_frame` dicts (single runs)
    geometry: Any = field(default=None, repr=False)           # the kernel's `HexGeometry`
    mesh: HexMesh | None = field(default=None, repr=False)

    @property
    def cor(self) -> float:
        return self.normal_cor

    def summary(self) -> dict[str, Any]:
        c = self.condition
        return {"ball": self.ball_name, "solver": "3d", "impact_speed_m_s": c.speed_m_s,
                "angle_deg": c.angle_deg, "spin_rad_s": c.spin_rad_s, "friction": c.friction,
                "target": self.target, "peak_force_n": self.peak_force_n,
                "peak_tangential_force_n": float(np.max(np.abs(
                    self.history["tangential_force_x_n"]))),
                "time_of_peak_s": self.time_of_peak_s, "contact_time_s": self.contact_time_s,
                "cor": self.normal_cor, "normal_cor": self.normal_cor,
                "tangential_cor": self.tangential_cor,
                "contact_point_tangential_cor": self.contact_point_tangential_cor,
                "rebound_angle_deg": self.rebound_angle_deg,
                "rebound_spin_rad_s": self.rebound_spin_rad_s,
                "rebound_speed_m_s": self.rebound_speed_m_s,
                "rebound_velocity_m_s": [float(self.history[f"centre_velocity_{a}_m_s"][-1])
                                         for a in "xyz"],
                "rebound_spin_vector_rad_s": [float(self.history[f"spin_{a}_rad_s"][-1])
                                              for a in "xyz"],
                "spin_x_rad_s": c.spin_x_rad_s, "spin_z_rad_s": c.spin_z_rad_s,
                "energy_balance_error": self.energy_balance_error,
                "energies_j": dict(self.energies_j), "mass_kg": self.mass_kg,
                "elements": self.elements, "nodes": self.nodes, "steps": self.steps,
                "half_model": self.half_model, "pole_grading": self.pole_grading,
                "pole_spacing_m": self.pole_spacing_m,
                "stable_time_increment_s": self.stable_time_increment_s,
                "final_time_increment_s": self.final_time_increment_s,
                "principal_stretch_bounds": list(self.stretch_range),  # Gershgorin bounds
                "wall_time_s": self.wall_time_s}

    def record(self) -> ImpactRecord:
        """The normal contact-force pulse as an `ImpactRecord` (for the 19 features)."""
        h = self.history
        dt = self.final_time_increment_s
        t = np.arange(1, int(np.floor(h["time_s"][-1] / dt * (1 + 1e-9))) + 1) * dt
        force = np.interp(t, h["time_s"], h["normal_force_n"])
        lead = np.arange(-max(3, int(0.05 * len(t))), 0) * dt
        normal_speed = self.condition.speed_m_s * math.cos(math.radians(self.condition.angle_deg))
        return ImpactRecord(np.concatenate([lead, [0.0], t]),
                            np.concatenate([np.zeros(len(lead) + 1), force]),
                            mass_kg=self.mass_kg, impact_speed_m_s=normal_speed,
                            rebound_speed_m_s=max(self.normal_cor * normal_speed, 0.0),
                            metadata={"source": "fe-3d", "ball": self.ball_name})


def _structure(ball, target) -> tuple:
    layers = tuple((layer.outer_radius_m, type(layer.material), layer.material.sum_k > 0,
                    len(layer.material.prony)) for layer in ball.layers)
    slab = None if target is None else (
        target.half_width_m, tuple((layer.thickness_m, type(layer.material),
                                    layer.material.sum_k > 0, len(layer.material.prony))
                                   for layer in target.layers))
    return layers, slab


_KERNELS: dict[Any, tuple[Kernel, HexMesh]] = {}


#: a target slab's in-plane cells grow by this a cell outward from the centre
SLAB_GROWTH = 1.15


def _slab_cell_m(ball, options: Options3D) -> float:
    """The target slab's cell size near the contact (m): about the ball mesh's arc spacing at
    the pole (the exact spacing is `mesh.pole_spacing_m`; this estimate is kept because the
    slab's documented figures rest on it)."""
    return (ball.outer_radius_m * math.radians(90.0 / options.divisions)
            / options.pole_grading ** 0.5)


def _slab_layout(ball, target, options: Options3D) -> tuple[int, float, np.ndarray]:
    """(cells across half the slab, their grading, depths of the cell boundaries m).

    Default: in plane about `_slab_cell_m` near the centre (the count is the one the slab's
    documented figures rest on; with its grading capped at 20 the centre cells come out finer
    than the ball's pole spacing), through the depth uniform cells of about 4 pole spacings (at
    least 2 a layer). With `slab_depth_growth` the slab is matched to the ball's contact: in
    plane cells of the pole spacing (`mesh.pole_spacing_m`) at the centre growing outward as
    the ball's cells do from its pole (at least by 1.15 a cell: the ball's nodes then press on
    target nodes of about their own mass, see `_contact_spring_factors`), through the depth
    the pole spacing at the surface growing by that factor to 4 pole spacings."""
    thicknesses = [layer.thickness_m for layer in target.layers]
    if options.slab_depth_growth is None:
        pole = _slab_cell_m(ball, options)
        cells = max(4, int(math.ceil(math.log(1 + target.half_width_m / pole)
                                     / math.log(SLAB_GROWTH))))
        return cells, min(20.0, SLAB_GROWTH ** (cells - 1)), uniform_depths_m(
            thicknesses, [max(2, int(math.ceil(t / (4 * pole)))) for t in thicknesses])
    pole = pole_spacing_m(ball.outer_radius_m, options.divisions, options.pole_grading)
    growth = max(SLAB_GROWTH, pole_cell_growth(options.divisions, options.pole_grading))
    # rounded down: the centre cells at least the pole spacing, so never lighter than the ball's
    cells = max(4, int(math.log(1 + (growth - 1) * target.half_width_m / pole)
                       / math.log(growth)))
    return cells, growth ** (cells - 1), graded_depths_m(thicknesses, pole, 4 * pole,
                                                          options.slab_depth_growth)


def mesh_for(ball, target, options: Options3D, half: bool) -> HexMesh:
    """The mesh of a ball (and target), ball layers then target layers as groups."""
    mesh = ball_mesh(ball.layer_radii_m, options.divisions, options.pole_grading, half=half)
    if target is None:
        return mesh
    cells, grading, depths = _slab_layout(ball, target, options)
    slab = slab_mesh([layer.thickness_m for layer in target.layers], target.half_width_m,
                     cells, grading=grading, half=half, depths_m=depths)
    return combine(mesh, slab, len(ball.layers))


def _mesh_size(ball, target, options: Options3D, half: bool) -> tuple[int, float]:
    """(elements, about the smallest element's length m) of `mesh_for`, without building it."""
    elements, smallest = estimate_ball_mesh(ball.layer_radii_m, options.divisions,
                                            options.pole_grading, half)
    if target is not None:
        cells, grading, depths = _slab_layout(ball, target, options)
        centre = float(graded_line(target.half_width_m, cells, grading)[1])
        elements += (2 * cells) * (cells if half else 2 * cells) * (len(depths) - 1)
        smallest = min(smallest, centre, float(np.min(np.diff(depths))))
    return elements, smallest


def kernel_for(ball, target, options: Options3D, half: bool) -> tuple[Kernel, HexMesh]:
    key = (_structure(ball, target), options.divisions, options.pole_grading, half,
           options.integration, options.precision,
           None if target is None else options.slab_depth_growth)
    if key not in _KERNELS:
        mesh = mesh_for(ball, target, options, half)
        materials = [layer.material for layer in ball.layers]
        if target is not None:
            materials += [layer.material for layer in target.layers]
        geom, _ = geometry(mesh, len(materials))
        free = np.ones((3, len(mesh.nodes_m)))
        free[1, mesh.symmetry_nodes] = 0.0
        free[:, mesh.fixed_nodes] = 0.0
        kernel = kernel_module.build(
            geom, [type(m).energy for m in materials], [m.sum_k > 0 for m in materials],
            mesh.contact_nodes, mesh.ball_nodes, free, half, options.integration == "reduced",
            mesh.target, np.dtype(options.precision))
        _KERNELS[key] = (kernel, mesh)
    return _KERNELS[key]


def model_arrays(ball, target, kernel: Kernel, options: Options3D,
                 condition: ImpactCondition) -> HexParams:
    """Per-run parameters (NumPy float64)."""
    geom = kernel.geom
    layers = list(ball.layers) + (list(target.layers) if target is not None else [])
    rho = np.array([layer.density_kg_m3 for layer in layers])
    wave = np.array([layer.material.wave_modulus_pa() for layer in layers])
    shear = np.array([layer.material.shear_modulus_pa() for layer in layers])
    c_d = np.sqrt(wave / rho)
    group = np.concatenate([np.full(b - a, i) for i, (a, b) in enumerate(geom.group_slices)])
    mass = rho @ np.asarray(geom.nodal_volume_m3, np.float64)
    s = kernel.contact_nodes
    m_s = mass[s]
    length = np.asarray(geom.characteristic_length_m, np.float64)
    penalty = options.penalty_scale * m_s * (c_d[len(ball.layers) - 1]
                                             / np.asarray(geom.node_length_m, np.float64)[s]) ** 2
    return HexParams(
        mass_kg=mass, ball_mass_kg=float(np.sum(mass[kernel.ball_nodes])),
        outer_radius_m=float(ball.outer_radius_m),
        penalty_n_m=penalty, stick_n_m=options.stick_scale * penalty,
        contact_damping_n_s_m=options.contact_damping * 2.0 * np.sqrt(penalty * m_s),
        contact_spring_factor=_contact_spring_factors(ball, target, kernel, mass, condition,
                                                      options),
        friction=float(condition.friction),
        hourglass_n_m=(options.hourglass_scale * shear[group]
                       * np.asarray(geom.hourglass_length_m, np.float64)),
        bv_linear_pa_s=options.bulk_viscosity_linear * rho[group] * c_d[group] * length,
        bv_quadratic_pa_s2=rho[group] * (options.bulk_viscosity_quadratic * length) ** 2,
        energy_error_limit=float(options.energy_error_limit),
        increment_factor=increment_factor(options.time_step_scale,
                                          options.bulk_viscosity_linear),
        groups=[layer.material.constants() for layer in layers],
        # arange(n_el) as data: `element.materialized`'s fusion boundary
        element_index=np.arange(geom.n_elements, dtype=np.int32))


def _contact_spring_factors(ball, target, kernel: Kernel, mass: np.ndarray,
                            condition: ImpactCondition, options: Options3D) -> np.ndarray:
    """Per contact node, the factor on its contact springs in the stable increment's estimate
    (n_contact,): a ball node of mass m pressed on target nodes of mass m_t makes a two-mass
    spring, 1 + m / m_t times stiffer than one tied to the ground (1 on the rigid plane).

    Only the ball nodes that can meet the target get it, with m_t the lightest target surface
    node they can meet (`_contact_reach`: within the reach angle of the first touch, and on
    the slab's cells under them give or take the travel). The bound over every pair (the
    heaviest ball node on the lightest target node) made a run on a slab matched to the contact
    take ten times the steps it needs."""
    s = np.asarray(kernel.contact_nodes)
    factors = np.ones(len(s))
    if target is None:
        return factors
    reach_rad, travel_m = _contact_reach(ball, target, kernel, mass, condition, options)
    top_mass = mass[np.asarray(kernel.target["top"])]
    xs, ys = (np.asarray(kernel.target[k], np.float64) for k in ("x_m", "y_m"))
    x = np.asarray(kernel.geom.nodes_m, np.float64)[s]
    radius = ball.outer_radius_m
    from_pole = np.arccos(np.clip((radius - x[:, 2]) / np.linalg.norm(
        x - np.array([0.0, 0.0, radius]), axis=1), -1.0, 1.0))
    for i in np.flatnonzero(from_pole <= reach_rad):
        box = [(x[i, k] - travel_m, x[i, k] + travel_m) for k in (0, 1)]
        factors[i] += mass[s[i]] / _lightest_partner_kg(xs, ys, top_mass, *box)
    return factors


def _lightest_partner_kg(xs, ys, top_mass, x_range, y_range) -> float:
    """The smallest effective mass (kg) a point pressed anywhere in the box x_range x y_range
    meets on a target surface of node lines `xs`, `ys` and node masses `top_mass`: with the
    bilinear weights w_j of the four corners, 1 / m = sum w_j^2 / m_j. That sum is convex along
    each axis within a cell, so its largest value is at a corner of the box cut by the cells:
    the box's corners and edges on the lines and the nodes inside."""
    def points(line, low, high):
        low, high = max(low, line[0]), min(high, line[-1])
        return np.unique(np.concatenate([[low, high], line[(line > low) & (line < high)]]))

    def cell_weights(line, p):
        i = np.clip(np.searchsorted(line, p, "right") - 1, 0, len(line) - 2)
        f = (p - line[i]) / (line[i + 1] - line[i])
        return i, f

    (ix, fx), (iy, fy) = (cell_weights(line, points(line, *span))
                          for line, span in ((xs, x_range), (ys, y_range)))
    ix, iy, fx, fy = ix[:, None], iy[None, :], fx[:, None], fy[None, :]
    inverse = sum((wx * wy) ** 2 / top_mass[ix + dx, iy + dy]
                  for dx, wx in ((0, 1 - fx), (1, fx)) for dy, wy in ((0, 1 - fy), (1, fy)))
    return float(1.0 / np.max(inverse))


#: the reach's margin on the Hertz contact radius and on the contact time
REACH_MARGIN = 1.5


def _contact_reach(ball, target, kernel: Kernel, mass: np.ndarray, condition: ImpactCondition,
                   options: Options3D) -> tuple[float, float]:
    """(angle rad, travel m): the angle from the first touch within which the ball's surface
    can meet a target, and how far a point of it can move along the target while in contact.

    From the Hertz contact (the ball's and the target's softest moduli in series) with
    `REACH_MARGIN` on its radius and time: the contact's half angle plus the rotation over the
    contact at the initial spin plus the most friction can add, plus two pole spacings; the
    travel is the tangential speed and that rotation over the contact, plus a pole spacing."""
    theta = math.radians(condition.angle_deg)
    v_n, v_t = condition.speed_m_s * math.cos(theta), abs(condition.speed_m_s * math.sin(theta))
    materials = [layer.material for layer in target.layers]
    radius = ball.outer_radius_m
    y_max, _, contact_time = hertz_series_impact(ball, v_n, materials)
    a, contact_time = REACH_MARGIN * math.sqrt(radius * y_max), REACH_MARGIN * contact_time
    ball_nodes = np.asarray(kernel.ball_nodes)
    x = np.asarray(kernel.geom.nodes_m, np.float64)[ball_nodes]
    inertia = float(np.sum(mass[ball_nodes] * (x[:, 0] ** 2 + (x[:, 2] - radius) ** 2)))
    spin = float(np.linalg.norm(condition.spin_vector_rad_s))
    k = inertia / (float(np.sum(mass[ball_nodes])) * radius ** 2)
    # friction's impulse over m: at most mu (1 + 1) v_n, and at most what reverses the contact
    # point's initial speed fully (a tangential COR of 1)
    impulse = min(2.0 * condition.friction * v_n, 2.0 * (v_t + spin * radius) / (1.0 + 1.0 / k))
    spin += impulse / (k * radius)
    pole = pole_spacing_m(radius, options.divisions, options.pole_grading)
    rotation = spin * contact_time
    return (math.asin(min(1.0, a / radius)) + rotation + 2.0 * pole / radius,
            (v_t + spin * radius) * contact_time + pole)


_STRESS: dict[Any, Any] = {}  # jitted stress recovery per kernel


def simulate_oblique(ball, condition: ImpactCondition, options: Options3D = Options3D(),
                     target=None, progress=None, *, allow=()) -> ObliqueResult:
    """An oblique impact of `ball` on a rigid plane (or a `target.Target` slab).

    An impact speed (`condition.speed_m_s`, m/s) outside `plausibility.FE_3D_SPEED_RANGE_M_S`
    (the speeds checked) raises `InputError` before anything is meshed or compiled; with
    `allow={"speed-range"}` it runs, with an `InputWarning` starting "speed-range:". So does a run
    whose memory estimate exceeds the memory available (`check_oblique_memory`, "large-run"),
    and a target narrower than the ball. `progress(t_s)` is called after every
    chunk of steps (`fe.progress.RunProgress` prints the time reached and the time left)."""
    return simulate_oblique_batch(ball, [condition], options, target, progress, allow=allow)[0]


#: elements x steps above which a run is flagged as very long (`estimate_oblique`): about 1.5
#: min at `SECONDS_PER_ELEMENT_STEP` (about 36 divisions, half model; the default 16 is 1.5e7 by
#: the estimate, 1.1e7 run)
ELEMENT_STEPS_WARNING = 3e8
#: wall time of one hexahedron update on a 2-core CPU (s; float64, reduced integration, after
#: issue 28: 3.1e-7 at 1408, 2.5e-7 at 7424 and 2.4e-7 at 22,464 hexahedra, the last 3.0e-7 on a
#: slow minute of the machine; benchmarks/bench_oblique.py, docs/oblique.md "Cost"; 9.3e-7 before)
SECONDS_PER_ELEMENT_STEP = 3e-7
#: the stable increment over the smallest element's L / c_d at time_step_scale 0.8 (0.84 at 8
#: and 0.66 at 16 divisions on the universal ball; lower is safer)
INCREMENT_OVER_SMALLEST_ELEMENT = 0.66


def _checked(ball, conditions, options: Options3D, target) -> tuple[list, bool, Options3D]:
    """The conditions as a list, checked, whether a half model serves, and the options with the
    pole grading set for `contact_elements` (when given); a target narrower than the ball
    refused (`target.check_target_width`)."""
    if target is not None:
        check_target_width(target, ball)
    conditions = list(conditions)
    if not conditions:
        raise InputError("conditions: need at least one impact condition")
    for c in conditions:
        if not isinstance(c, ImpactCondition):
            raise InputError(f"conditions: expected ImpactCondition, got {type(c).__name__}")
    symmetric = all(c.symmetric for c in conditions)
    half = symmetric if options.half is None else bool(options.half)
    if half and not symmetric:
        raise InputError("half = True: out-of-plane spin (spin_x_rad_s, spin_z_rad_s) needs the "
                         "full model (half = False or None)")
    if options.contact_elements is not None:
        slowest = min(c.speed_m_s * math.cos(math.radians(c.angle_deg)) for c in conditions)
        grading, _ = grading_for_contact(ball, slowest, options.divisions,
                                         options.contact_elements)
        options = replace(options, pole_grading=grading, contact_elements=None)
    return conditions, half, options


def estimate_oblique(ball, conditions, options: Options3D = Options3D(),
                     target=None, *, allow=()) -> RunEstimate:
    """The cost of a run (`fe.progress.RunEstimate`), estimated from the mesh (built and cached
    as the run would) before anything is compiled: steps to a Hertz contact time at the normal
    speed (the ball's softest long-term modulus) plus the end margin, at an increment from the
    smallest element; memory of the histories and of the frames kept for output (`frames`).
    `RunEstimate.warning` flags runs above `ELEMENT_STEPS_WARNING` element updates or
    `fe.progress.MEMORY_WARNING_BYTES`. Speeds are not range-checked here.

    The mesh is built only after the same estimate from the mesh's counting rules fits in the
    available memory (`check_oblique_memory`: the `large-run` check, overridden by `allow`)."""
    conditions, half, options = _checked(ball, conditions, options, target)
    check_oblique_memory(ball, conditions, options, target, half, allow)
    kernel, _ = kernel_for(ball, target, options, half)
    return _estimate(ball, target, conditions, options, kernel)


#: memory of a run (bytes): the process with JAX and the compiled program, and per hexahedron and
#: run held at once (measured on the universal ball, reduced integration, half models of 8 to
#: 32 divisions: docs/oblique.md; full integration's eight points assumed to double it)
BASE_MEMORY_BYTES = 0.8 * 2 ** 30
MEMORY_PER_ELEMENT_BYTES = 16e3
_HINT = ("a coarser mesh: fewer divisions, --divisions (a slab: a thinner or narrower --target, "
         "whose cells follow the ball's pole spacing)")


def check_oblique_memory(ball, conditions, options: Options3D, target, half: bool,
                         allow=()) -> RunEstimate:
    """The `large-run` check before anything is meshed: the run's memory estimated from the
    mesh's counting rules (`_mesh_size`) against the available memory
    (`fe.progress.RunEstimate.check_memory`: the memory the run adds to this process's, judged
    once per size in a process)."""
    elements, smallest = _mesh_size(ball, target, options, half)
    estimate = _run_estimate(ball, target, conditions, options, elements, smallest)
    estimate.check_memory(check_allow(allow))
    return estimate


def _estimate(ball, target, conditions, options: Options3D, kernel: Kernel) -> RunEstimate:
    geom = kernel.geom
    return _run_estimate(ball, target, conditions, options, int(geom.n_elements),
                         float(np.min(np.asarray(geom.characteristic_length_m))),
                         int(kernel.n_nodes))


def _run_estimate(ball, target, conditions, options: Options3D, elements: int, smallest: float,
                  nodes: int | None = None) -> RunEstimate:
    """The cost of runs of `conditions` on a mesh of `elements` hexahedra (and `nodes`, default
    about as many) whose smallest is `smallest` m long."""
    nodes = elements if nodes is None else nodes
    layers = list(ball.layers) + (list(target.layers) if target is not None else [])
    c_d = max(math.sqrt(layer.material.wave_modulus_pa() / layer.density_kg_m3)
              for layer in layers)
    dt = (INCREMENT_OVER_SMALLEST_ELEMENT * options.time_step_scale / 0.8) * smallest / c_d
    slack = 1.0 if target is None else 4.0  # a slab lengthens the contact
    end = max(min(slack * hertz_contact_time_s(ball, c.speed_m_s * math.cos(math.radians(
        c.angle_deg))) * (1.0 + options.end_margin), options.time_limit_s or math.inf)
        for c in conditions)
    steps = math.ceil(end / dt)
    memory = 8.0 * steps * len(HISTORY) * len(conditions)
    if options.frames and len(conditions) == 1:  # displacement, velocity, contact force, stress
        frames = steps / (options.chunk_steps * options.frames)
        memory += 8.0 * frames * (9 * nodes + 6 * elements)
    per_element = MEMORY_PER_ELEMENT_BYTES * (2.0 if options.integration == "full" else 1.0)
    return RunEstimate(elements=int(elements), steps=steps, end_time_s=end,
                       memory_bytes=memory, element_steps_limit=ELEMENT_STEPS_WARNING,
                       seconds_per_element_step=SECONDS_PER_ELEMENT_STEP, hint=_HINT,
                       model_bytes=BASE_MEMORY_BYTES + per_element * elements * len(conditions),
                       runs=len(conditions), base_bytes=BASE_MEMORY_BYTES)


def simulate_oblique_batch(ball, conditions, options: Options3D = Options3D(), target=None,
                           progress=None, *, allow=()) -> list[ObliqueResult]:
    """Several impact conditions of one ball (and target) as one vmapped run. Speeds are
    checked as in `simulate_oblique`; a run estimated above `ELEMENT_STEPS_WARNING` element
    updates or `fe.progress.MEMORY_WARNING_BYTES` gets an `InputWarning` before it starts."""
    conditions, half, options = _checked(ball, conditions, options, target)
    impact_speeds([c.speed_m_s for c in conditions], len(conditions), allow, "3d")
    check_oblique_memory(ball, conditions, options, target, half, allow)  # before meshing
    normal_speeds = [c.speed_m_s * math.cos(math.radians(c.angle_deg)) for c in conditions]
    warn_unresolved_contact([ball] * len(conditions), normal_speeds,
                            pole_spacing_m(ball.outer_radius_m, options.divisions,
                                           options.pole_grading),
                            refine="more divisions, pole_grading or contact_elements: --divisions, "
                                   "--pole-grading, --contact-elements")
    start = time.perf_counter()
    kernel, mesh = kernel_for(ball, target, options, half)
    message = _estimate(ball, target, conditions, options, kernel).warning()
    if message is not None:
        warnings.warn(message, InputWarning, stacklevel=2)
    per_run = [model_arrays(ball, target, kernel, options, c) for c in conditions]
    batched = len(conditions) > 1
    params = jax.tree_util.tree_map(lambda *xs: np.stack(xs), *per_run) if batched else per_run[0]
    speeds = np.array([c.speed_m_s for c in conditions])
    angles = np.radians([c.angle_deg for c in conditions])
    spins = np.array([c.spin_vector_rad_s for c in conditions])
    slack = 1.0 if target is None else 4.0
    limits = np.array([options.time_limit_s or slack * time_limit_default(ball, vn)
                       for vn in normal_speeds])
    frames: list = []

    def keep_frame(chunk: int, params, state) -> None:
        if options.frames and not batched and chunk % options.frames == 0:
            frames.append(_frame(kernel, params, state))

    run = run_chunks(kernel, params, [speeds, angles, spins], options, batched=batched,
                     limits_s=limits, labels=[f"ball {ball.name}, {c}" for c in conditions],
                     final_keys=_FINAL, refine="more divisions", progress=progress,
                     on_chunk=keep_frame)
    wall = time.perf_counter() - start
    out = []
    for i, c in enumerate(conditions):
        run_frames = frames if not batched else []
        out.append(_result(ball, target, c, run.history[i],
                           {k: v[i] for k, v in run.final.items()}, per_run[i], run.t_end_s[i],
                           kernel, mesh, half, wall / len(conditions), run_frames, options))
    return out


#: the state's values a result is made of
_FINAL = ("peak_force", "t_peak", "dt0", "dt", "stretch_min", "stretch_max", "ke0")


def _frame(kernel: Kernel, params, state) -> dict[str, np.ndarray]:
    """A snapshot for output (one run): time (s), displacement and velocity (3, n_nodes), Cauchy
    stress (6, n_el; xx, yy, zz, xy, yz, zx, elements sorted by group) and contact forces
    (3, n_nodes)."""
    key = ("stress", id(kernel))
    if key not in _STRESS:
        _STRESS[key] = jax.jit(kernel.cauchy_stress)
    return {"time_s": float(state.t),
            "displacement_m": np.asarray(state.u, np.float64),
            "velocity_m_s": np.asarray(state.v, np.float64),
            "stress_pa": np.asarray(_STRESS[key](params, state.u, state.mat), np.float64),
            "contact_force_n": np.asarray(state.f_contact, np.float64)}


def _result(ball, target, condition, history, final, arrays, t_end, kernel, mesh, half, wall,
            frames, options: Options3D) -> ObliqueResult:
    n = int(np.searchsorted(history[:, 0], t_end * (1 + 1e-6))) + 1
    factor = 2.0 if half else 1.0
    h = {name: history[:n, j] for j, name in enumerate(HISTORY)}
    for name in HISTORY:
        if name.endswith("_n") or name.endswith("_j"):
            h[name] = factor * h[name]
    mass = factor * float(arrays.ball_mass_kg)
    v, theta, w = condition.speed_m_s, math.radians(condition.angle_deg), condition.spin_rad_s
    vx, vz = v * math.sin(theta), -v * math.cos(theta)
    ke0 = factor * float(final["ke0"])
    balance = h["kinetic_energy_j"] + h["internal_work_j"] - h["contact_work_j"] - ke0
    h["energy_balance_error"] = balance / ke0
    h["frictional_dissipation_j"] = -h["tangential_work_j"] - h["stick_energy_j"]
    h["viscous_dissipation_j"] = (h["internal_work_j"] - h["strain_energy_j"]
                                  - h["bulk_viscous_dissipation_j"] - h["hourglass_energy_j"])
    energies = {name: float(values[-1]) for name, values in h.items() if name.endswith("_j")}
    energies["initial_kinetic_energy_j"] = float(ke0)
    energies["peak_hourglass_energy_j"] = float(np.max(h["hourglass_energy_j"]))
    vx_out, vz_out = h["centre_velocity_x_m_s"][-1], h["centre_velocity_z_m_s"][-1]
    vy_out = h["centre_velocity_y_m_s"][-1]
    w_out = h["spin_y_rad_s"][-1]
    radius = ball.outer_radius_m
    contact_in = vx - w * radius
    return ObliqueResult(
        ball_name=ball.name, condition=condition, history=h,
        normal_cor=float(vz_out / -vz),
        tangential_cor=float(vx_out / vx) if vx != 0 else float("nan"),
        contact_point_tangential_cor=(float(-(vx_out - w_out * radius) / contact_in)
                                      if abs(contact_in) > 1e-9 * v else float("nan")),
        rebound_angle_deg=float(math.degrees(math.atan2(math.hypot(vx_out, vy_out), vz_out))),
        rebound_spin_rad_s=float(w_out), rebound_speed_m_s=float(math.sqrt(vx_out ** 2 + vy_out ** 2 + vz_out ** 2)),
        peak_force_n=factor * float(final["peak_force"]), time_of_peak_s=float(final["t_peak"]),
        contact_time_s=contact_end_time(h["time_s"], h["normal_force_n"]),
        energy_balance_error=float(np.max(np.abs(balance)) / ke0), energies_j=energies,
        stable_time_increment_s=float(final["dt0"]), final_time_increment_s=float(final["dt"]),
        steps=n, elements=int(kernel.geom.n_elements), nodes=int(kernel.n_nodes), mass_kg=mass,
        outer_radius_m=radius, half_model=half,
        target="rigid plane" if target is None else target.name, wall_time_s=wall,
        stretch_range=(float(final["stretch_min"]), float(final["stretch_max"])),
        pole_grading=float(options.pole_grading),
        pole_spacing_m=pole_spacing_m(radius, options.divisions, options.pole_grading),
        frames=frames, mesh=mesh, geometry=kernel.geom)
