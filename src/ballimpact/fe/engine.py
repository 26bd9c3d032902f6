"""The explicit FE engine's one host driver, the geometry a plug-in (as diffrax takes `solver=`).

    fe.simulate(ball, condition, geometry=Axisymmetric(SolverOptions(...)))    # normal impacts
    fe.simulate(ball, condition, geometry=Hexahedral(Options3D(...)), target=slab)  # 3D

A geometry (`fe.axi.geometry.Axisymmetric`, `fe.hex.geometry.Hexahedral`) holds its element,
mesh, kernel and parameter builder and its cost constants; this driver reaches it only through
the object passed to it. For every run it checks the conditions and speeds once, estimates the
cost and memory once (before anything is meshed, from the mesh's counting rules), caches kernels
by the geometry's key, groups and pads batches so that every group runs one compiled program,
runs `driver.run_chunks` (which checks the energy balance between chunks) and returns one result
type (`result.ImpactResult`) per run, or a `result.FailedRun`.

Energy balance error: max |KE + internal work - contact work - KE0| / KE0 over the run; viscous
dissipation = internal work - strain energy - bulk-viscous dissipation - hourglass energy.
"""

from __future__ import annotations

import math
import time
import warnings
from typing import Any

import jax
import numpy as np

from ..checks import check_integer, check_range, shown
from ..errors import InputError, InputWarning
from ..checks import check_allow
from .speed_range import check_fe_speed
from .axi.geometry import Axisymmetric
from .driver import run_chunks
from .estimates import hertz_contact_radius_m, hertz_contact_time_s, time_limit_default
from .hex.geometry import Hexahedral
from .options import ImpactCondition, Options3D, SolverOptions
from .progress import RunEstimate
from .result import FailedRun, ImpactResult

__all__ = ["Axisymmetric", "Hexahedral", "estimate", "impact_conditions", "kernel_for", "simulate",
           "simulate_batch"]

#: the contact patch must span this many elements at the contact pole (Hertz contact radius over
#: the pole's element size) for the pulse to be resolved: on a homogeneous elastic ball the
#: contact time is then within 5% and the peak force within 1% of Hertz; at 1.2 elements the
#: contact time reads 7% long, at 0.8 elements 18% (docs/fe.md, tests/fe/test_fe_low_speed.py)
CONTACT_RESOLUTION_ELEMENTS = 2.0

Geometry = Axisymmetric | Hexahedral
_KERNELS: dict[Any, Any] = {}


def default_group_size(runs: int, geometry: Geometry | None = None) -> int:
    """Runs per vmapped group on this backend, as `geometry` (default `Axisymmetric()`) says."""
    return (geometry or Axisymmetric()).default_group_size(runs, jax.default_backend() == "cpu")


def kernel_for(ball, geometry: Geometry, target=None):
    """(kernel, mesh or None) of a ball (and target) structure on `geometry`, cached by the
    geometry's key."""
    key = geometry.kernel_key(ball, target)
    if key not in _KERNELS:
        _KERNELS[key] = geometry.build(ball, target)
    return _KERNELS[key]


def _items(conditions) -> list:
    """The conditions as a list of `ImpactCondition`s and speeds (m/s, checked finite > 0)."""
    if isinstance(conditions, (ImpactCondition, int, float, np.number)) or (
            isinstance(conditions, np.ndarray) and conditions.ndim == 0):
        conditions = [conditions]
    out = []
    for c in list(conditions):
        if not isinstance(c, ImpactCondition):
            try:
                c = float(c)
            except (TypeError, ValueError):
                raise InputError(f"impact_speed_m_s = {shown(c)}: expected numbers (m/s) or "
                                 "ImpactCondition") from None
            c = check_range("impact_speed_m_s", c, 0.0, low_open=True, unit="m/s")
        out.append(c)
    if not out:
        raise InputError("conditions: need at least one impact condition")
    return out


def impact_conditions(conditions, n: int | None = None) -> list[ImpactCondition]:
    """Impact conditions (an `ImpactCondition`, a speed in m/s for a normal impact, or a
    sequence of them), checked; `n` of them when given (one is repeated)."""
    out = [c if isinstance(c, ImpactCondition) else ImpactCondition(c)
           for c in _items(conditions)]
    if n is not None and len(out) == 1:
        out *= n
    if n is not None and len(out) != n:
        raise InputError(f"impact_speeds_m_s: expected one speed or {n} (one per ball), got "
                         f"{len(out)}")
    return out


def check_speeds(conditions, geometry: Geometry, allow=()) -> None:
    """Every impact speed (of `ImpactCondition`s, or speeds in m/s) inside the speeds
    `geometry` was checked at (`fe.speed_range.check_fe_speed`; "speed-range" in `allow`: a
    warning), one message for the first outside."""
    speeds = [c.speed_m_s if isinstance(c, ImpactCondition) else c for c in _items(conditions)]
    for speed in np.unique(speeds):
        check_fe_speed(float(speed), check_allow(allow), solver=geometry.solver)


def _normal_speed(condition: ImpactCondition) -> float:
    return condition.speed_m_s * math.cos(math.radians(condition.angle_deg))


def run_estimate(geometry: Geometry, balls: list, conditions: list, target, elements: int,
                 smallest_m: float, held: int, nodes: int | None = None,
                 columns: int | None = None) -> RunEstimate:
    """The cost of runs of `balls` under `conditions` on a mesh of `elements` (and `nodes`,
    default about as many) whose smallest element is `smallest_m` long, `held` runs in memory
    at once: steps to a Hertz contact time at the normal speed (the ball's softest long-term
    modulus; a slab's geometry slack on it) plus the end margin, at an increment from the
    smallest element and the fastest wave. `columns`: the history's (default the geometry's
    plain `HISTORY`; a built kernel's `history_names` count a target's and a backing's)."""
    options = geometry.options
    layers = list(getattr(target, "layers", ()))  # a slab's layers; a backing has none
    steps, end = 0, 0.0
    for ball, condition in zip(balls, conditions):
        end_s = (geometry.slack(target) * hertz_contact_time_s(ball, _normal_speed(condition))
                 * (1.0 + options.end_margin))
        if options.time_limit_s is not None:
            end_s = min(end_s, options.time_limit_s)
        c_d = max(math.sqrt(layer.material.wave_modulus_pa() / layer.density_kg_m3)
                  for layer in list(ball.layers) + layers)
        dt = (geometry.INCREMENT_OVER_SMALLEST_ELEMENT * options.time_step_scale / 0.8
              * smallest_m / c_d)
        steps, end = max(steps, math.ceil(end_s / dt)), max(end, end_s)
    runs = len(balls)
    memory = (8.0 * steps * (columns or len(geometry.HISTORY)) * runs
              + geometry.frames_bytes(steps, elements, elements if nodes is None else nodes, runs))
    per_element = geometry.MEMORY_PER_ELEMENT_BYTES * (2.0 if options.integration == "full"
                                                       else 1.0)
    return RunEstimate(elements=int(elements), steps=steps, end_time_s=end, memory_bytes=memory,
                       element_steps_limit=geometry.ELEMENT_STEPS_WARNING,
                       seconds_per_element_step=geometry.SECONDS_PER_ELEMENT_STEP,
                       hint=geometry.HINT, chunk_steps=options.chunk_steps,
                       model_bytes=geometry.BASE_MEMORY_BYTES + per_element * float(elements)
                       * held, runs=runs, base_bytes=geometry.BASE_MEMORY_BYTES)


def check_memory(geometry: Geometry, balls: list, conditions: list, target=None, allow=(),
                 group_size: int | None = None) -> RunEstimate:
    """The `large-run` check before anything is meshed: the run's memory estimated from the
    mesh's counting rules (`geometry.mesh_size`) against the available memory
    (`progress.RunEstimate.check_memory`: the memory the run adds to this process's, judged once
    per size in a process). Returns that estimate. `conditions`: one per ball, or speeds (m/s)."""
    conditions = impact_conditions(conditions, len(balls))
    elements, smallest = geometry.mesh_size(balls[0], target)
    held = len(balls) if group_size is None else min(len(balls), group_size)
    estimate = run_estimate(geometry, balls, conditions, target, elements, smallest, held)
    estimate.check_memory(check_allow(allow))
    return estimate


def _kernel_estimate(geometry: Geometry, kernel, balls: list, conditions: list,
                     target) -> RunEstimate:
    geom = kernel.geom
    return run_estimate(geometry, balls, conditions, target, int(geom.n_elements),
                        float(np.min(np.asarray(geom.characteristic_length_m))), len(balls),
                        len(geom.nodes_m), len(kernel.history_names))


def contact_resolution_note(ball, speed_m_s: float, pole_element_m: float,
                            refine: str = Axisymmetric.REFINE_POLE) -> str | None:
    """A note when the contact patch at `speed_m_s` (m/s) spans fewer than
    `CONTACT_RESOLUTION_ELEMENTS` elements of `pole_element_m` (m) at the contact pole (a Hertz
    estimate with the ball's softest long-term plane-strain modulus,
    `estimates.hertz_contact_radius_m`); None when it spans enough. A slow impact on a coarse
    mesh: the contact time reads long. `refine` names the options that refine the pole."""
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


def _warn_unresolved_contact(geometry: Geometry, balls: list, conditions: list) -> None:
    """One `contact_resolution_note` warning, for the slowest run of a batch."""
    speeds = [_normal_speed(c) for c in conditions]
    i = int(np.argmin(speeds))
    note = contact_resolution_note(balls[i], float(speeds[i]), geometry.pole_element_m(balls[i]),
                                   geometry.REFINE_POLE)
    if note is not None:
        warnings.warn(note, InputWarning, stacklevel=4)


def _targets(target, runs: int) -> list:
    """One target per run: `target` (None, one target, or a list or tuple of one per run)."""
    if not isinstance(target, (list, tuple)):
        return [target] * runs
    if len(target) != runs:
        raise InputError(f"target: expected one target or {runs} (one per run), got "
                         f"{len(target)}")
    return list(target)


def _prepared(balls, conditions, geometry, target, allow, group_size=None, speeds=True):
    """The runs as (balls, conditions, geometry, group size, targets), checked once:
    conditions, speeds (unless not `speeds`), structure, each run's target (one compiled
    program for all: the same kernel key), the target's width, and the memory of a group
    before anything is meshed."""
    geometry = Axisymmetric() if geometry is None else geometry
    if not isinstance(geometry, (Axisymmetric, Hexahedral)):
        raise InputError(f"geometry = {shown(geometry)}: expected fe.Axisymmetric(...) or "
                         "fe.Hexahedral(...)")
    single_ball = not isinstance(balls, (list, tuple))
    balls = [balls] if single_ball else list(balls)
    if not balls:
        raise InputError("balls: need at least one ball")
    if speeds:  # before the conditions are built: a speed outside is named as such
        check_speeds(conditions, geometry, allow)
    conditions = impact_conditions(conditions)
    if isinstance(target, (list, tuple)) and len(conditions) == 1 and len(balls) == 1:
        conditions = conditions * max(len(target), 1)  # one ball, one speed, several targets
    if single_ball:
        balls = balls * len(conditions)
    elif len(conditions) == 1:
        conditions = conditions * len(balls)
    if len(conditions) != len(balls):
        raise InputError(f"impact_speeds_m_s: expected one speed or {len(balls)} (one per "
                         f"ball), got {len(conditions)}")
    targets = _targets(target, len(balls))
    for t in {id(t): t for t in targets}.values():  # each distinct target once
        geometry = geometry.checked(balls[0], conditions, t)
    target = targets[0]
    if any(geometry.structure(b, target) != geometry.structure(balls[0], target) for b in balls):
        raise InputError("balls: a batch must share layer radii, material models and Prony terms")
    if any(geometry.kernel_key(balls[0], t) != geometry.kernel_key(balls[0], target)
           for t in targets):
        raise InputError("target: a batch's targets must share one structure (a backing's "
                         "number of modes; a target's layers, materials, width and backing)")
    group_size = group_size or default_group_size(len(balls), geometry)
    check_memory(geometry, balls, conditions, target, allow, group_size)
    return balls, conditions, geometry, group_size, targets


def estimate(ball, conditions, options=None, *, geometry: Geometry | None = None, target=None,
             allow=()) -> RunEstimate:
    """The cost of a run (`progress.RunEstimate`) of `ball` under `conditions` (one or a
    sequence: `ImpactCondition`s or normal-impact speeds in m/s) on `geometry` (default
    `Axisymmetric()`), estimated from the mesh (built and cached as the run would) before
    anything is compiled: steps to a Hertz contact time (the ball's softest long-term modulus)
    plus the end margin, at an increment from the smallest element. `RunEstimate.warning` flags
    runs above the geometry's `ELEMENT_STEPS_WARNING` element updates or
    `progress.MEMORY_WARNING_BYTES`.

    The mesh is built only after the same estimate made from the mesh's counting rules fits in
    the available memory: else the `large-run` check fails (`InputError`, or with "large-run"
    in `allow` an `InputWarning` and the mesh is built). Speeds are not range-checked here."""
    balls, conditions, geometry, _, targets = _prepared(
        ball, conditions, _geometry(geometry, options), target, allow, speeds=False)
    kernel, _ = kernel_for(balls[0], geometry, targets[0])
    return _kernel_estimate(geometry, kernel, balls, conditions, targets[0])


def _geometry(geometry, options):
    """The geometry from `geometry` or from `options` (its settings: `SolverOptions` ->
    `Axisymmetric`, `Options3D` -> `Hexahedral`), default `Axisymmetric()`."""
    if options is None:
        return geometry
    if geometry is not None:
        raise InputError("options: give the settings inside geometry=... or as options, not both")
    if isinstance(options, Options3D):
        return Hexahedral(options)
    if isinstance(options, SolverOptions):
        return Axisymmetric(options)
    raise InputError(f"options = {shown(options)}: expected SolverOptions or Options3D")


def simulate(ball, condition, options=None, progress=None, *, geometry: Geometry | None = None,
             target=None, allow=()) -> ImpactResult:
    """One impact of `ball` under `condition` (an `ImpactCondition`, or a speed in m/s for a
    normal impact without spin) on the rigid plane (or a `fe.hex.target.Target` slab, 3D only)
    with `geometry` (default `Axisymmetric()`: normal impacts; `Hexahedral(...)` for oblique,
    spinning and slab impacts). `options` (`SolverOptions` or `Options3D`) is short for the
    geometry with those settings.

    A speed outside the speeds the geometry was checked at (`fe.speed_range.FE_SPEED_RANGE_M_S`,
    `FE_3D_SPEED_RANGE_M_S`, docs/fe.md) raises `InputError` before anything is meshed or
    compiled; with `allow={"speed-range"}` it runs, with an `InputWarning` starting
    "speed-range:". So does a run whose memory estimate exceeds the memory available
    (`check_memory`, "large-run"). A run estimated above the geometry's `ELEMENT_STEPS_WARNING`
    element updates gets an `InputWarning` before it starts, and so does a contact patch
    narrower than `CONTACT_RESOLUTION_ELEMENTS` pole elements (`contact_resolution_note`).
    `progress(t_s)` is called after every chunk of steps (`progress.RunProgress` prints the
    time reached and the time left)."""
    if isinstance(condition, (list, tuple)) or (isinstance(condition, np.ndarray)
                                                and condition.ndim > 0):
        raise InputError("condition: one impact condition (a batch is fe.simulate_batch)")
    return simulate_batch(ball, condition, progress=progress,
                          geometry=_geometry(geometry, options), target=target, allow=allow)[0]


def simulate_batch(balls, conditions, options=None, progress=None, group_size: int | None = None,
                   on_failure: str = "raise", *, geometry: Geometry | None = None, target=None,
                   allow=()) -> list:
    """Several impacts as vmapped runs: one ball under several `conditions`, several balls of
    one layer structure under one condition each (or all under one), on `geometry` (default
    `Axisymmetric()`). Balls may differ in every material constant and density, not in the
    layer radii, material models or number of Prony terms.

    Runs are grouped by their expected number of steps, so that members of a group end close
    together; each group of `group_size` runs (default `default_group_size`) is one vmapped run,
    the last padded so that every group uses the same compiled program. Results come back in
    the order of the runs. `progress(t_s)` is called between chunks.

    `on_failure`: "raise" (a `SimulationError` for the first failed run) or "return" (a failed
    run gets a `FailedRun` with the reason in its place, and the others run on: a design of
    experiments keeps the runs that did not fail and records the reason of those that did).
    `target`: one for every run, or a list of one per run that share one compiled program
    (e.g. `PlaneBacking`s of as many modes: a bat at several impact points). Checks, warnings
    and `options` as `simulate`'s."""
    if on_failure not in ("raise", "return"):
        raise InputError(f"on_failure = {on_failure!r}: allowed 'raise' or 'return'")
    if group_size is not None:
        group_size = check_integer("group_size", group_size, 1)
    balls, conditions, geometry, group_size, targets = _prepared(
        balls, conditions, _geometry(geometry, options), target, allow, group_size)
    _warn_unresolved_contact(geometry, balls, conditions)
    kernel, mesh = kernel_for(balls[0], geometry, targets[0])
    message = _kernel_estimate(geometry, kernel, balls, conditions, targets[0]).warning()
    if message is not None:
        warnings.warn(message, InputWarning, stacklevel=3)
    if len(balls) <= group_size:
        return _run_group(geometry, balls, conditions, targets, kernel, mesh, progress,
                          on_failure)
    smallest = float(np.min(np.asarray(kernel.geom.characteristic_length_m)))
    order = np.argsort([_expected_steps(b, c, smallest) for b, c in zip(balls, conditions)],
                       kind="stable")
    results: list[Any] = [None] * len(balls)
    for start in range(0, len(balls), group_size):
        members = list(order[start:start + group_size])
        padded = members + [members[-1]] * (group_size - len(members))
        runs = _run_group(geometry, [balls[i] for i in padded], [conditions[i] for i in padded],
                          [targets[i] for i in padded], kernel, mesh, progress, on_failure)
        for i, result in zip(members, runs):
            results[i] = result
    return results


def _expected_steps(ball, condition: ImpactCondition, smallest_m: float) -> float:
    """A cheap estimate of a run's steps (Hertz contact time over an element-size increment),
    to put runs that end together into the same group."""
    c_d = max(math.sqrt(layer.material.wave_modulus_pa() / layer.density_kg_m3)
              for layer in ball.layers)
    return time_limit_default(ball, _normal_speed(condition)) * c_d / smallest_m


def _stack(trees: list) -> Any:
    return jax.tree_util.tree_map(lambda *xs: np.stack(xs), *trees)


def _run_group(geometry: Geometry, balls: list, conditions: list, targets: list, kernel, mesh,
               progress, on_failure: str = "raise") -> list:
    """One vmapped run of balls of one structure, each on its target (checked by the
    caller)."""
    start = time.perf_counter()
    per_run = [geometry.params(b, t, kernel, c) for b, c, t in zip(balls, conditions, targets)]
    batched = len(balls) > 1
    params = _stack(per_run) if batched else per_run[0]
    options = geometry.options
    limits = np.array([options.time_limit_s
                       or geometry.slack(t) * time_limit_default(b, _normal_speed(c))
                       for b, c, t in zip(balls, conditions, targets)])
    frames: list = []

    def keep_frame(chunk: int, params, state) -> None:
        if chunk % options.frames == 0:
            frames.append(geometry.frame(kernel, params, state))

    run = run_chunks(kernel, params, geometry.initial(conditions), options, batched=batched,
                     limits_s=limits,
                     labels=[geometry.label(b, c) for b, c in zip(balls, conditions)],
                     final_keys=geometry.FINAL, refine=geometry.REFINE, progress=progress,
                     on_failure=on_failure,
                     on_chunk=keep_frame if not batched and getattr(options, "frames", 0) else None)
    wall = time.perf_counter() - start
    failed = run.failed
    return [FailedRun(ball.name, c.speed_m_s, failed[i]) if i in failed else
            geometry.result(ball, t, c, run.history[i],
                            {k: v[i] for k, v in run.final.items()}, per_run[i], run.t_end_s[i],
                            kernel, mesh, wall / len(balls), frames if not batched else [])
            for i, (ball, c, t) in enumerate(zip(balls, conditions, targets))]
