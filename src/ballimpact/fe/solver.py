"""Explicit FE normal impacts of layered balls on a rigid plane: the driver (host side).

`kernel.Kernel` holds the pure JAX step; here balls become parameters, the stable increment is
found from the assembled system (`Kernel.max_frequency_squared`), `lax.scan` advances chunks of
steps, `vmap` runs groups of balls (each with its own constants, density, impact speed and
increment) through one compiled program, and a Python loop checks between chunks whether every
member has separated, failed, or exceeded the energy-error limit.

Energy balance error: max |KE + internal work - contact work - KE0| / KE0 over the run; viscous
dissipation = internal work - strain energy - bulk-viscous dissipation - hourglass energy.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import jax
import numpy as np

from ..errors import InputError, InputWarning
from ..plausibility import FE_SPEED_RANGE_M_S, check_allow, check_fe_speed
from ..records import ImpactRecord
from .axi.element import geometry
from .axi.kernel import HISTORY, Kernel, ball_arrays
from .estimates import hertz_contact_radius_m, hertz_contact_time_s, time_limit_default
from .axi.mesh import estimate_mesh, layered_sphere_mesh
from .materials.stability import drucker_warnings
from ..checks import shown
from .options import ImpactCondition, SolverOptions
from .progress import RunEstimate
from .driver import RunFigures, run_chunks

__all__ = ["FE_SPEED_RANGE_M_S", "FEResult", "SolverOptions", "default_group_size",
           "estimate_run", "simulate", "simulate_batch"]


@dataclass(frozen=True, eq=False)
class FEResult(RunFigures):
    """One simulated normal impact (SI; `RunFigures` and the below). Histories are per step;
    `record` is an `ImpactRecord`."""

    impact_speed_m_s: float
    cor: float
    moduli: tuple[str, ...]
    nodes_m: np.ndarray = field(repr=False)
    elements_connectivity: np.ndarray = field(repr=False)
    displacement_at_peak_m: np.ndarray = field(repr=False)
    layer_slices: tuple = ()
    wall_time_s: float = 0.0
    energies_j: dict[str, float] = field(default_factory=dict)
    integration: str = "reduced"
    precision: str = "float64"

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
                "final_time_increment_s": self.final_time_increment_s,
                "principal_stretch_range": list(self.stretch_range),
                "moduli": self.moduli[0] if len(set(self.moduli)) == 1 else list(self.moduli),
                "integration": self.integration, "precision": self.precision,
                "wall_time_s": self.wall_time_s}

    def record(self):
        """The contact-force pulse as an `ImpactRecord` (with zero force before contact),
        uniformly sampled at the run's final increment (the increment may shrink during a run;
        linear interpolation between steps)."""
        steps = self.history["time_s"]
        dt = self.final_time_increment_s
        t = np.arange(1, int(np.floor(steps[-1] / dt * (1 + 1e-9))) + 1) * dt
        f = np.interp(t, steps, self.history["contact_force_n"])
        lead = np.arange(-max(3, int(0.05 * len(t))), 0) * dt
        time = np.concatenate([lead, [0.0], t])
        force = np.concatenate([np.zeros(len(lead) + 1), f])
        velocity = np.concatenate([np.full(len(lead) + 1, self.impact_speed_m_s),
                                   -np.interp(t, steps, self.history["centre_velocity_z_m_s"])])
        return ImpactRecord(time, force, velocity_m_s=velocity, mass_kg=self.mass_kg,
                            impact_speed_m_s=self.impact_speed_m_s,
                            rebound_speed_m_s=max(self.rebound_speed_m_s, 0.0),
                            metadata={"source": "fe", "ball": self.ball_name,
                                      "contact_time_s": self.contact_time_s})


@dataclass(frozen=True)
class FailedRun:
    """A run of a batch that failed (`simulate_batch(..., on_failure="return")`): why, in words."""

    ball_name: str
    impact_speed_m_s: float
    reason: str


def _structure(ball) -> tuple:
    """What a compiled run depends on: radii, material models, Prony terms, bulk relaxation."""
    return tuple((layer.outer_radius_m, type(layer.material), layer.material.sum_k > 0,
                   tuple((k, np.shape(v)) for k, v in sorted(layer.material.constants().items())))
                  for layer in ball.layers)


_KERNELS: dict[Any, Kernel] = {}


def kernel_for(ball, options: SolverOptions) -> Kernel:
    """The compiled-program data (mesh, material models, precision) of a ball structure, cached."""
    key = (_structure(ball), options.element_size_m, options.pole_element_size_m,
           options.pole_zone_deg, tuple(options.mesh_radii_m), options.integration,
           options.precision)
    if key not in _KERNELS:
        radii = np.asarray(ball.layer_radii_m)
        mesh_radii = _mesh_radii(ball, options)
        mesh = layered_sphere_mesh(tuple(mesh_radii), options.element_size_m,
                                   options.pole_element_size_m, options.pole_zone_deg)
        # mesh rings -> ball layers: a ring belongs to the first layer that reaches its radius
        ring_layer = np.searchsorted(radii, mesh_radii - 1e-12 * radii[-1])
        mesh = dataclasses.replace(mesh, element_layer=ring_layer[mesh.element_layer],
                                   layer_radii_m=tuple(radii))
        _KERNELS[key] = Kernel.build(
            geometry(mesh), [type(layer.material).energy for layer in ball.layers],
            [layer.material.sum_k > 0 for layer in ball.layers],
            reduced=options.integration == "reduced", dtype=np.dtype(options.precision))
    return _KERNELS[key]


def _mesh_radii(ball, options: SolverOptions) -> np.ndarray:
    """The node circles of a ball's mesh: its layer radii and `options.mesh_radii_m` inside."""
    radii = np.asarray(ball.layer_radii_m)
    extra = [r for r in options.mesh_radii_m if 0 < r < radii[-1]]
    return np.unique(np.concatenate([radii, extra]))


def _stack(trees: list) -> Any:
    return jax.tree_util.tree_map(lambda *xs: np.stack(xs), *trees)


def contact_end_time(time: np.ndarray, force: np.ndarray) -> float:
    """Time at which the force returns to zero, extrapolated from the last two positive samples."""
    positive = np.flatnonzero(force > 0)
    k = positive[-1]
    if k == 0 or k + 1 >= len(time) or force[k - 1] <= force[k]:
        return float(time[min(k + 1, len(time) - 1)])
    slope = (force[k - 1] - force[k]) / (time[k] - time[k - 1])
    return float(min(time[k] + force[k] / slope, time[k + 1]))


#: balls per vmapped group on a CPU, where larger groups run out of cache
CPU_GROUP_SIZE = 4
#: balls per vmapped group on an accelerator: on an H100 (benchmarks/bench_accelerator.py) groups
#: of 256, 1024 and 4096 universal balls ran 192, 204 and 219 runs/s in float32 and 121, 122 and
#: 125 in float64, so 1024 is within 7% of the largest group's rate at a quarter of its memory
ACCELERATOR_GROUP_SIZE = 1024


def default_group_size(n_balls: int) -> int:
    """Balls per vmapped group: `CPU_GROUP_SIZE` on a CPU, up to `ACCELERATOR_GROUP_SIZE` on an
    accelerator."""
    if jax.default_backend() == "cpu":
        return CPU_GROUP_SIZE
    return max(1, min(n_balls, ACCELERATOR_GROUP_SIZE))


def impact_speeds(impact_speeds_m_s, n: int, allow=(), solver: str = "axisymmetric") -> np.ndarray:
    """The impact speeds (m/s) of `n` balls, checked: finite, > 0, and inside the speeds `solver`
    was checked at (`plausibility.check_fe_speed`) unless "speed-range" is in `allow` (a
    warning)."""
    allow = check_allow(allow)
    try:
        speeds = np.asarray(impact_speeds_m_s, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"impact_speed_m_s = {shown(impact_speeds_m_s)}: expected numbers "
                         "(m/s)") from None
    if speeds.ndim == 0:
        speeds = np.full(n, float(speeds))
    if speeds.shape != (n,):
        raise InputError(f"impact_speeds_m_s: expected one speed or {n} (one per ball), got "
                         f"{speeds.shape[0] if speeds.ndim == 1 else speeds.shape}")
    bad = ~(np.isfinite(speeds) & (speeds > 0))
    if np.any(bad):
        raise InputError(f"impact_speed_m_s = {shown(speeds[np.argmax(bad)])}: must be > 0")
    for speed in np.unique(speeds):  # one error (or warning) for the first speed outside
        check_fe_speed(float(speed), allow, solver=solver)
    return speeds


#: elements x steps above which a run is flagged as very long (`estimate_run`): about 5 min at
#: `SECONDS_PER_ELEMENT_STEP` (the universal ball at 25 m/s with 0.2 mm elements; the default
#: 1.5 mm mesh is 4.6e6 by the estimate, 3.5e6 run)
ELEMENT_STEPS_WARNING = 2e9
#: wall time of one element update on a 2-core CPU (s; float64, reduced integration: 1.3-1.6e-7
#: measured with 1482 to 20590 elements on the machine of this work while shared with other jobs;
#: 8e-8 at 1482 elements when it was not, docs/fe.md "Speed")
SECONDS_PER_ELEMENT_STEP = 1.5e-7
#: the stable increment of the assembled system over the smallest element's L / c_d at
#: time_step_scale 0.8 (1.52 on the default meshes of both presets; lower is safer)
INCREMENT_OVER_SMALLEST_ELEMENT = 1.5


#: memory of a run (bytes): the process with JAX and the compiled program (peak 0.55-0.6 GB with
#: 210 to 13,110 elements), and per element and ball run at once (mesh, geometry, state,
#: Lanczos vectors: 4-6 kB measured with 13,110 to 80,370 elements, reduced integration; full
#: integration's four points are assumed to double it, not measured). On the high side. The
#: large-run check counts only the part of the base the process does not hold yet.
BASE_MEMORY_BYTES = 0.6 * 2 ** 30
MEMORY_PER_ELEMENT_BYTES = 8e3
#: the contact patch must span this many elements at the contact pole (Hertz contact radius over
#: the pole's element size) for the pulse to be resolved: on a homogeneous elastic ball the
#: contact time is then within 5% and the peak force within 1% of Hertz; at 1.2 elements the
#: contact time reads 7% long, at 0.8 elements 18% (docs/fe.md, tests/test_fe_low_speed.py)
CONTACT_RESOLUTION_ELEMENTS = 2.0
#: how to make an axisymmetric run smaller (for the warnings and the large-run check)
_HINT = ("a coarser mesh: element_size_m, --element-size-m (or a coarser pole refinement: "
         "pole_element_size_m, --pole-element-size-m)")


def estimate_run(ball, impact_speed_m_s, options: SolverOptions = SolverOptions(), *,
                 allow=()) -> RunEstimate:
    """The cost of a run of `ball` at `impact_speed_m_s` (m/s; one speed or one per run of a
    batch of this ball's structure), estimated from the mesh before anything is compiled: steps
    to a Hertz contact time (the ball's softest long-term modulus: longer than the ball's) plus
    the end margin, at an increment from the smallest element. `RunEstimate.warning` flags runs
    above `ELEMENT_STEPS_WARNING` element updates or `progress.MEMORY_WARNING_BYTES`.

    The mesh is built only after the same estimate made from the mesh's counting rules
    (`mesh.estimate_mesh`) fits in the available memory: else the `large-run` check fails
    (`InputError`, or with "large-run" in `allow` an `InputWarning` and the mesh is built)."""
    speeds = np.atleast_1d(np.asarray(impact_speed_m_s, dtype=np.float64))
    balls = [ball] * len(speeds)
    check_run_memory(balls, speeds, options, allow)
    return _estimate(kernel_for(ball, options), balls, speeds, options)


def check_run_memory(balls: list, speeds, options: SolverOptions, allow=(),
                     group_size: int | None = None) -> RunEstimate:
    """The `large-run` check before anything is meshed: the run's memory estimated from the
    ball's radii and the mesh options alone (`mesh.estimate_mesh`) against the available memory
    (`progress.RunEstimate.check_memory`: the memory the run adds to this process's, judged once
    per size in a process). Returns that estimate."""
    mesh = estimate_mesh(_mesh_radii(balls[0], options), options.element_size_m,
                         options.pole_element_size_m, options.pole_zone_deg)
    held = len(balls) if group_size is None else min(len(balls), group_size)
    estimate = _run_estimate(mesh.elements, mesh.smallest_length_m, balls, speeds, options, held)
    estimate.check_memory(check_allow(allow))
    return estimate


def _estimate(kernel: Kernel, balls: list, speeds, options: SolverOptions) -> RunEstimate:
    smallest = float(np.min(kernel.geom.characteristic_length_m))
    return _run_estimate(kernel.geom.n_elements, smallest, balls, speeds, options, len(balls))


def _run_estimate(elements: int, smallest_m: float, balls: list, speeds, options: SolverOptions,
                  held: int) -> RunEstimate:
    """The cost of runs of `balls` at `speeds` on a mesh of `elements` whose smallest element is
    `smallest_m` long; `held` runs are in memory at once (a vmapped group)."""
    steps, end = 0, 0.0
    for ball, speed in zip(balls, speeds):
        end_s = hertz_contact_time_s(ball, float(speed)) * (1.0 + options.end_margin)
        if options.time_limit_s is not None:
            end_s = min(end_s, options.time_limit_s)
        c_d = max(math.sqrt(layer.material.wave_modulus_pa() / layer.density_kg_m3)
                  for layer in ball.layers)
        dt = (INCREMENT_OVER_SMALLEST_ELEMENT * options.time_step_scale / 0.8) * smallest_m / c_d
        steps, end = max(steps, math.ceil(end_s / dt)), max(end, end_s)
    per_element = MEMORY_PER_ELEMENT_BYTES * (2.0 if options.integration == "full" else 1.0)
    return RunEstimate(elements=int(elements), steps=steps, end_time_s=end,
                       memory_bytes=8.0 * steps * len(HISTORY) * len(balls),
                       element_steps_limit=ELEMENT_STEPS_WARNING,
                       seconds_per_element_step=SECONDS_PER_ELEMENT_STEP, hint=_HINT,
                       model_bytes=BASE_MEMORY_BYTES + per_element * float(elements) * held,
                       runs=len(balls), base_bytes=BASE_MEMORY_BYTES)


def _warn_if_large(kernel: Kernel, balls: list, speeds, options: SolverOptions) -> None:
    message = _estimate(kernel, balls, speeds, options).warning()
    if message is not None:
        warnings.warn(message, InputWarning, stacklevel=3)


#: how to refine the contact pole (for the `contact_resolution_note` of the axisymmetric solver)
_REFINE_POLE = "pole_element_size_m, --pole-element-size-m"


def contact_resolution_note(ball, speed_m_s: float, pole_element_m: float,
                            refine: str = _REFINE_POLE) -> str | None:
    """A note when the contact patch at `speed_m_s` (m/s) spans fewer than
    `CONTACT_RESOLUTION_ELEMENTS` elements of `pole_element_m` (m) at the contact pole (a Hertz
    estimate with the ball's softest long-term plane-strain modulus,
    `kernel.hertz_contact_radius_m`); None when it spans enough. A slow impact on a coarse mesh:
    the contact time reads long. `refine` names the options that refine the pole."""
    radius = hertz_contact_radius_m(ball, speed_m_s)
    if radius >= CONTACT_RESOLUTION_ELEMENTS * pole_element_m:
        return None
    finer = radius / CONTACT_RESOLUTION_ELEMENTS
    return (f"contact not resolved: at {speed_m_s:g} m/s the contact patch of {ball.name} "
            f"(Hertz radius about {radius * 1e3:.3g} mm) spans {radius / pole_element_m:.2g} "
            f"elements of {pole_element_m * 1e3:.3g} mm at the contact pole, fewer than "
            f"{CONTACT_RESOLUTION_ELEMENTS:g}: the contact time reads long (on an elastic ball "
            "by 7% at 1.2 elements, 18% at 0.8, docs/fe.md); refine the pole to about "
            f"{finer:.2g} m ({refine})")


def warn_unresolved_contact(balls: list, speeds, pole_element_m: float,
                            refine: str = _REFINE_POLE) -> None:
    """One `contact_resolution_note` warning, for the slowest run of a batch."""
    i = int(np.argmin(speeds))
    note = contact_resolution_note(balls[i], float(speeds[i]), pole_element_m, refine)
    if note is not None:
        warnings.warn(note, InputWarning, stacklevel=3)


def _expected_steps(ball, speed: float, kernel: Kernel) -> float:
    """A cheap estimate of a run's steps (Hertz contact time over an element-size increment),
    to put balls that end together into the same group."""
    c_d = max(math.sqrt(layer.material.wave_modulus_pa() / layer.density_kg_m3)
              for layer in ball.layers)
    return time_limit_default(ball, speed) * c_d / float(np.min(kernel.geom.characteristic_length_m))


def simulate_batch(balls: Sequence, impact_speeds_m_s, options: SolverOptions = SolverOptions(),
                   progress=None, group_size: int | None = None,
                   on_failure: str = "raise", *, allow=()) -> list:
    """Normal impacts of several balls with the same layer structure, vmapped in groups.

    `impact_speeds_m_s` (m/s) is one speed for all, or one per ball. The balls may differ in every
    material constant and density, not in the layer radii, material models or number of Prony
    terms. Balls are grouped by their expected number of steps, so that members of a group end
    close together; each group of `group_size` balls (default `default_group_size`) is one
    vmapped run, the last padded so that every group uses the same compiled program. Results come
    back in the order of `balls`. `progress(t_s)` is called between chunks.

    `on_failure`: "raise" (a `SimulationError` for the first failed ball) or "return" (a failed
    ball gets a `FailedRun` with the reason in its place, and the others run on: a design of
    experiments keeps the runs that did not fail and records the reason of those that did).

    Speeds outside `FE_SPEED_RANGE_M_S` (the speeds checked, docs/fe.md) raise `InputError`
    before anything is meshed or compiled, unless `allow` holds "speed-range" (then an
    `InputWarning` starting "speed-range:"). So does a batch whose memory estimate, made before
    meshing, exceeds the memory available (`check_run_memory`; "large-run" in `allow`: a
    warning). A batch whose runs are estimated above `ELEMENT_STEPS_WARNING` element updates
    each gets an `InputWarning` before it runs (`estimate_run`), and one whose slowest contact
    patch spans fewer than `CONTACT_RESOLUTION_ELEMENTS` pole elements another.
    """
    if on_failure not in ("raise", "return"):
        raise InputError(f"on_failure = {on_failure!r}: allowed 'raise' or 'return'")
    balls = list(balls)
    if not balls:
        raise InputError("balls: need at least one ball")
    speeds = impact_speeds(impact_speeds_m_s, len(balls), allow)
    if group_size is None:
        group_size = default_group_size(len(balls))
    if not (isinstance(group_size, int) and group_size >= 1):
        raise InputError(f"group_size = {group_size!r}: must be an integer >= 1")
    if any(_structure(b) != _structure(balls[0]) for b in balls):
        raise InputError("balls: a batch must share layer radii, material models and Prony terms")
    check_run_memory(balls, speeds, options, allow, group_size)  # before anything is meshed
    warn_unresolved_contact(balls, speeds, options.pole_element_size_m or options.element_size_m)
    kernel = kernel_for(balls[0], options)
    _warn_if_large(kernel, balls, speeds, options)
    if len(balls) <= group_size:
        return _simulate_group(balls, speeds, options, progress, on_failure)
    order = np.argsort([_expected_steps(b, s, kernel) for b, s in zip(balls, speeds)],
                       kind="stable")
    results: list[Any] = [None] * len(balls)
    for start in range(0, len(balls), group_size):
        members = list(order[start:start + group_size])
        padded = members + [members[-1]] * (group_size - len(members))
        group = _simulate_group([balls[i] for i in padded], speeds[padded], options, progress,
                                on_failure)
        for i, result in zip(members, group):
            results[i] = result
    return results


def simulate(ball, impact_speed_m_s: float | ImpactCondition,
             options: SolverOptions = SolverOptions(), progress=None, *, allow=()) -> FEResult:
    """Normal impact of one ball on a rigid plane at `impact_speed_m_s` (m/s), or as an
    `ImpactCondition` (the 3D engine's): a normal one (angle 0, no spin), else `InputError`
    pointing to `oblique.simulate_oblique`; its friction is not modelled here (a normal impact
    slides only within the contact patch).

    A speed outside `FE_SPEED_RANGE_M_S` (m/s; the speeds the solver was checked at,
    docs/fe.md) raises `InputError` before anything is meshed or compiled; with
    `allow={"speed-range"}` it runs, with an `InputWarning` starting "speed-range:". So does a
    run whose memory estimate exceeds the memory available (`check_run_memory`, "large-run";
    judged once: not again after `estimate_run` of the same run). A run estimated above
    `ELEMENT_STEPS_WARNING` element updates (a very fine mesh) gets an `InputWarning` before it
    starts, and so does a contact patch narrower than `CONTACT_RESOLUTION_ELEMENTS` pole elements
    (`contact_resolution_note`). `progress(t_s)` is called after every chunk of steps
    (`progress.RunProgress` prints the time reached and the time left).
    """
    if isinstance(impact_speed_m_s, ImpactCondition):
        impact_speed_m_s = normal_impact_speed(impact_speed_m_s)
    speeds = impact_speeds(impact_speed_m_s, 1, allow)
    check_run_memory([ball], speeds, options, allow)  # before anything is meshed
    warn_unresolved_contact([ball], speeds, options.pole_element_size_m or options.element_size_m)
    _warn_if_large(kernel_for(ball, options), [ball], speeds, options)
    return _simulate_group([ball], speeds, options, progress)[0]


def normal_impact_speed(condition: ImpactCondition) -> float:
    """The speed (m/s) of a normal impact without spin, or `InputError`."""
    if not condition.normal:
        raise InputError(f"{condition}: the axisymmetric solver runs normal impacts without spin "
                         "(angle_deg 0, spins 0); oblique and spinning impacts are "
                         "oblique.simulate_oblique (--solver 3d)")
    return condition.speed_m_s


def _simulate_group(balls: list, speeds: np.ndarray, options: SolverOptions,
                    progress, on_failure: str = "raise") -> list:
    """One vmapped run of balls of one structure (checked by the caller)."""
    start = time.perf_counter()
    kernel = kernel_for(balls[0], options)
    geom = kernel.geom
    per_ball = [ball_arrays(b, geom, options) for b in balls]
    batched = len(balls) > 1
    params = _stack(per_ball) if batched else per_ball[0]
    limits = np.array([options.time_limit_s or time_limit_default(b, s)
                       for b, s in zip(balls, speeds)])
    run = run_chunks(kernel, params, [speeds], options, batched=batched, limits_s=limits,
                     labels=[f"ball {b.name}" for b in balls], final_keys=_FINAL,
                     refine="element size", progress=progress, on_failure=on_failure)
    wall = time.perf_counter() - start
    failed, t_end = run.failed, run.t_end_s
    results = [FailedRun(ball.name, float(speed), failed[i]) if i in failed else
               _result(ball, float(speed), run.history[i], {k: v[i] for k, v in run.final.items()},
                       per_ball[i], t_end[i], kernel, options, wall / len(balls))
               for i, (ball, speed) in enumerate(zip(balls, speeds))]
    for result, ball in zip(results, balls):
        if isinstance(result, FailedRun):
            continue
        for message in drucker_warnings(ball, *result.stretch_range):
            warnings.warn(f"{message}: principal stretches in this range occurred in the ball "
                          "(in some layer)", InputWarning, stacklevel=3)
    return results


_FINAL = ("peak_force", "t_peak", "u_peak", "dt0", "dt", "stretch_min", "stretch_max")


def _result(ball, speed: float, history: np.ndarray, end_state: dict, arrays: dict, t_end: float, kernel: Kernel, options: SolverOptions, wall: float) -> FEResult:
    n = int(np.searchsorted(history[:, 0], t_end * (1 + 1e-6))) + 1
    h = {name: history[:n, j] for j, name in enumerate(HISTORY)}
    mass = float(np.sum(arrays.mass_kg))
    ke0 = 0.5 * mass * speed ** 2
    balance = h["kinetic_energy_j"] + h["internal_work_j"] - h["contact_work_j"] - ke0
    h["viscous_dissipation_j"] = (h["internal_work_j"] - h["strain_energy_j"]
                                  - h["bulk_viscous_dissipation_j"] - h["hourglass_energy_j"])
    h["energy_balance_error"] = balance / ke0
    final = {name: float(values[-1]) for name, values in h.items() if name.endswith("_j")}
    final["peak_internal_energy_j"] = float(np.max(h["strain_energy_j"] + h["hourglass_energy_j"]))
    final["peak_hourglass_energy_j"] = float(np.max(h["hourglass_energy_j"]))
    if min(final["viscous_dissipation_j"], final["bulk_viscous_dissipation_j"]) < -1e-3 * ke0:
        warnings.warn(f"ball {ball.name}: a negative dissipation at the end of the run "
                      f"({final['viscous_dissipation_j']:.3g} J viscous): the strain-energy "
                      "split is approximate at large strains", InputWarning, stacklevel=4)
    final["initial_kinetic_energy_j"] = ke0
    geom = kernel.geom
    return FEResult(
        ball_name=ball.name, impact_speed_m_s=speed, history=h,
        cor=float(h["centre_velocity_z_m_s"][-1] / speed),
        peak_force_n=float(end_state["peak_force"]), time_of_peak_s=float(end_state["t_peak"]),
        contact_time_s=contact_end_time(h["time_s"], h["contact_force_n"]),
        energy_balance_error=float(np.max(np.abs(balance)) / ke0),
        stable_time_increment_s=float(end_state["dt0"]),
        final_time_increment_s=float(end_state["dt"]), steps=n, elements=geom.n_elements,
        nodes=len(geom.nodes_m), mass_kg=mass,
        stretch_range=(float(end_state["stretch_min"]), float(end_state["stretch_max"])),
        outer_radius_m=ball.outer_radius_m,
        moduli=tuple(layer.material.moduli for layer in ball.layers),
        nodes_m=np.asarray(geom.nodes_m, np.float64), elements_connectivity=geom.elements,
        layer_slices=geom.layer_slices, displacement_at_peak_m=end_state["u_peak"].T,
        wall_time_s=wall, energies_j=final, integration=options.integration,
        precision=options.precision)
