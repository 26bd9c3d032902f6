"""FE runs as the command line makes them, callable from Python with SI arguments: a ball loaded
with its moduli convention overridden, each run's cost estimated before anything is meshed or
compiled, a `start(cost)` hook between the estimate and the run (to warn and announce; it
returns the run's progress callback), and the JSON summaries of one impact and of a speed sweep.

`ballimpact simulate` prints what these return; `sweep` and `oblique.sweep` hold the sweeps'
science (rows, tables, figures).
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..balls.ball import BallModel, load_ball
from ..checks import check_allow, check_range
from ..errors import InputError
from .engine import Axisymmetric, Geometry, Hexahedral, default_group_size, estimate, simulate
from .options import ImpactCondition, SolverOptions
from .output import RunFiles, write_run_files
from .speed_range import check_fe_speed
from .progress import RunEstimate
from .result import ImpactResult
from .sweep import (
    BallComparison,
    check_balls,
    compare_rows,
    run_sweep,
    sweep_balls,
    sweep_figure,
    sweep_json_row,
    write_table,
)

#: a run's hook between its estimate and its start: gets the estimate, returns the progress
#: callback of the run (`fe.RunProgress`) or None
Start = Callable[[RunEstimate], Any]
#: frames kept of a run that keeps them for a time series or an animation (about this many)
ANIMATION_FRAMES = 40


def load_model(spec, speed_m_s: float | None = None, *, moduli: str | None = None,
               allow=()) -> BallModel:
    """`fe.load_ball(spec, impact_speed_m_s=speed_m_s)` with `moduli` ("long_term" or
    "instantaneous") overriding the ball's convention when given."""
    ball = load_ball(spec, impact_speed_m_s=speed_m_s, allow=allow)
    return ball if moduli is None else ball.with_moduli(moduli)


def check_sweep_speeds(speeds_m_s: Sequence[float], allow=()) -> None:
    """Each speed of a sweep (m/s) against the axisymmetric FE speed range
    (`fe.speed_range.check_fe_speed`) before anything is loaded; a non-positive or non-finite
    speed is left to `load_ball`, which names the field."""
    for speed in speeds_m_s:
        if math.isfinite(speed) and speed > 0:
            check_fe_speed(speed, allow)


def started(start: Start | None, ball, conditions, geometry: Geometry, *, target=None,
            allow=(), announce: str = ""):
    """`start(estimate)` of a run of `ball` under `conditions` on `geometry`: the estimate is
    made (and a run that would not fit in memory refused) before anything is meshed, `announce`
    (what is about to run) put in it; None without `start`."""
    if start is None:
        return None
    cost = estimate(ball, conditions, geometry=geometry, target=target, allow=allow)
    return start(replace(cost, announce=announce))


def run_impact(ball: BallModel, condition, geometry: Geometry | None = None, *, target=None,
               allow=(), start: Start | None = None, frames: int = ANIMATION_FRAMES,
               announce: str = "") -> ImpactResult:
    """One impact (`fe.simulate`: `condition` an `ImpactCondition` or a normal speed in m/s,
    `geometry` default `Axisymmetric()`, `target` a slab or None) after its estimate and
    `start` (`started`, with `announce`). Frames kept for output (`Options3D.frames`) are thinned to about
    `frames`, evenly spread over the run."""
    geometry = Axisymmetric() if geometry is None else geometry
    progress = started(start, ball, condition, geometry, target=target, allow=allow,
                       announce=announce)
    result = simulate(ball, condition, progress=progress, geometry=geometry, target=target,
                      allow=allow)
    if len(result.frames) > frames:
        keep = np.unique(np.linspace(0, len(result.frames) - 1, frames).astype(int))
        result.frames[:] = [result.frames[i] for i in keep]
    return result


def run_speed_sweep(spec, speeds_m_s: Sequence[float], options=None, *,
                    moduli: str | None = None, label: str = "", allow=(),
                    start: Start | None = None, announce: str = ""):
    """Ball `spec` at each of `speeds_m_s` (m/s; ascending) in one batched axisymmetric run
    (`sweep.sweep_balls`, `sweep.run_sweep`): the speeds checked first (`check_sweep_speeds`),
    the cost estimated with the ball of the slowest speed (the longest run) before meshing, then
    `start` (`started`, with `announce`); its progress callback is used when the sweep runs as one vmapped group. Returns
    the `sweep.Sweep`."""
    check_sweep_speeds(speeds_m_s, allow)
    balls = sweep_balls(spec, speeds_m_s, moduli=moduli, allow=allow)
    geometry = Axisymmetric(SolverOptions() if options is None else options)
    slowest = balls[int(np.argmin(speeds_m_s))]
    progress = started(start, slowest, list(speeds_m_s), geometry, allow=allow,
                       announce=announce)
    one_group = len(speeds_m_s) <= default_group_size(len(speeds_m_s))
    return run_sweep(balls, speeds_m_s, geometry.options, label=label, allow=allow,
                     progress=progress if one_group else None)


def impact_summary(result: ImpactResult, ball: BallModel, target=None) -> dict[str, Any]:
    """One run's JSON object (SI): `result.summary()`, the 19 features of its pulse, the ball's
    specification, and for the axisymmetric solver the material constants it used
    (instantaneous), for a slab target its specification."""
    from ..protect.headform import backing_figures
    from ..records.features import extract_features

    out = result.summary()
    out["features"] = extract_features(result.record()).to_dict()["features"]
    out["materials"] = ball.to_dict()
    if result.geometry == "axisymmetric":
        out["material_constants_used"] = [
            {"layer": layer.name, "model": layer.material.model,
             **{k: (v.tolist() if hasattr(v, "tolist") else v)
                for k, v in layer.material.constants().flat().items()}} for layer in ball.layers]
    if target is not None and hasattr(target, "to_dict"):
        out["target_specification"] = target.to_dict()
        energies = result.energies_j
        out["target_layers"] = [
            {"name": layer.name, "work_j": energies[f"target_{layer.name}_work_j"],
             "max_compression": energies[f"target_{layer.name}_max_compression"]}
            for layer in target.layers if f"target_{layer.name}_work_j" in energies]
    backing = backing_figures(result)
    if backing is not None:
        out["backing"] = backing
    return out


def speed_sweep_summary(sweep) -> dict[str, Any]:
    """A speed sweep's JSON object (SI): its label, speeds and rows (`sweep_json_row`), the
    moduli, elements, integration and precision of its runs, the batch's wall time and the
    balls' specifications."""
    first = sweep.results[0].summary()
    return {"ball": sweep.label, "speeds_m_s": list(sweep.speeds_m_s),
            "sweep": [sweep_json_row(r) for r in sweep.results], "moduli": first["moduli"],
            "elements": first["elements"], "integration": first["integration"],
            "precision": first["precision"], "wall_time_s": sweep.wall_time_s,
            "materials": [b.to_dict() for b in sweep.balls]}


def load_checked_target(target, ball):
    """`target`: a preset or file name (`fe.hex.target.load_target`, at least the ball's width),
    a loaded target, or None (the rigid plane)."""
    from .hex.target import check_target_width, load_target

    if target is None or not isinstance(target, (str, Path)):
        return target
    slab = load_target(target)
    try:
        check_target_width(slab, ball)
    except InputError as error:
        raise InputError(f"--target {target}: {error}") from None
    return slab


def checked_speed(speed_m_s: float, allow=(), *, solver: str = "axisymmetric") -> frozenset:
    """The `allow` names, checked, and `speed_m_s` against the FE speed range of `solver`, before
    anything is loaded (a non-positive or non-finite speed is left to `load_ball`)."""
    allow = check_allow(allow)
    if math.isfinite(speed_m_s) and speed_m_s > 0:
        check_fe_speed(speed_m_s, allow, solver=solver)
    return allow


def impact_inputs(spec, speed_m_s: float, geometry: Geometry, files: RunFiles, *, friction=0.0,
                  target=None, moduli: str | None = None, allow=()):
    """The checked inputs of an impact on `geometry` (every check before anything is printed,
    meshed or compiled): (allow, ball, target, geometry), the 3D geometry's frames set by
    `files` (`RunFiles.frames`) and its slab settings refused without a target."""
    files.check()
    check_range("--friction", friction, 0.0)
    three_d = isinstance(geometry, Hexahedral)
    allow = checked_speed(speed_m_s, allow, solver="3d" if three_d else "axisymmetric")
    ball = load_model(spec, speed_m_s, moduli=moduli, allow=allow)
    slab = load_checked_target(target, ball)
    if three_d:
        options = geometry.options
        for flag, value in (("--slab-depth-growth", options.slab_depth_growth),
                            ("--slab-depth-cell-m", options.slab_depth_cell_m)):
            if value is not None and target is None:
                raise InputError(f"{flag}: sets a target slab's cells; give --target FILE")
        geometry = Hexahedral(replace(options, chunk_steps=50 if files.frames else 200,
                                      frames=1 if files.frames else 0))
    return allow, ball, slab, geometry


def simulate_impact(spec, speed_m_s: float, geometry: Geometry | None = None, *,
                    angle_deg: float = 0.0, spin_rad_s: float = 0.0, spin_x_rad_s: float = 0.0,
                    spin_z_rad_s: float = 0.0, friction: float = 0.0, target=None,
                    moduli: str | None = None, allow=(), files: RunFiles = RunFiles(),
                    start: Start | None = None) -> tuple[ImpactResult, dict[str, Any]]:
    """One impact as `ballimpact simulate` makes it: ball `spec` (a preset, a file or a
    `BallModel`) at `speed_m_s` (m/s) on `geometry` (default `Axisymmetric()`; the angle (deg
    from the normal), spins (rad/s) and friction are the 3D geometry's, `fe.ImpactCondition`),
    on `target` (a preset or file, or None: the rigid plane), with `moduli` overriding the
    ball's convention. Every input is checked first (`impact_inputs`; `files.table` is a
    sweep's, refused for a 3D run), then `start` gets the estimate, the run runs and `files`
    are written. Returns the result and its JSON object (`impact_summary` and the files)."""
    geometry = Axisymmetric() if geometry is None else geometry
    three_d = isinstance(geometry, Hexahedral)
    if three_d and files.table is not None:
        raise InputError("--table: the sweep table of the axisymmetric solver; a 3d run's "
                         "figures are in --json")
    allow, ball, slab, geometry = impact_inputs(spec, speed_m_s, geometry, files,
                                                friction=friction, target=target, moduli=moduli,
                                                allow=allow)
    condition, announce = speed_m_s, ""
    if three_d:
        condition = ImpactCondition(speed_m_s, angle_deg, spin_rad_s, friction, spin_x_rad_s,
                                    spin_z_rad_s)
        announce = f"simulating {ball.name} in 3D at {speed_m_s:g} m/s, {angle_deg:g} deg ..."
    result = run_impact(ball, condition, geometry, target=slab, allow=allow, start=start,
                        announce=announce)
    out = impact_summary(result, ball, slab)
    out.update(write_run_files(result, files))
    return result, out


def simulate_speeds(spec, speeds_m_s: Sequence[float], options: SolverOptions | None = None, *,
                    moduli: str | None = None, allow=(), files: RunFiles = RunFiles(),
                    target=None, start: Start | None = None) -> dict[str, Any]:
    """A speed sweep as `ballimpact simulate --speed-m-s 5,10,20` makes it: ball `spec` at each of
    `speeds_m_s` (m/s) in one batched axisymmetric run on the rigid plane (`run_speed_sweep`;
    `target` and a history file are refused), its JSON object (`speed_sweep_summary`) with the
    row table and the plot of `files` written."""
    from ..plotting import save_and_close

    files.refuse("csv", why="a sweep writes a row per speed with --table (or give one speed)")
    if target is not None:
        raise InputError("--target: a speed sweep runs on the rigid plane; give one speed per "
                         "run on a target")
    files.check()
    allow = check_allow(allow)
    label = spec if isinstance(spec, str) else ""
    sweep = run_speed_sweep(spec, sorted(speeds_m_s), options, moduli=moduli, label=label,
                            allow=allow, start=start,
                            announce=f"simulating {label} at {len(speeds_m_s)} speeds in one "
                                     "batched run ...")
    out = speed_sweep_summary(sweep)
    if files.table is not None:
        out["table"] = write_table(out["sweep"], files.table)
    if files.plot is not None:
        figure = sweep_figure([sweep], title=f"{label}: speed sweep (FE, rigid plane)")
        out["plot"] = str(save_and_close(figure, files.plot))
    return out


def compare_balls(specs: Sequence[str], speeds_m_s: Sequence[float], options=None, *,
                  moduli: str | None = None, allow=frozenset(), files=None,
                  start=None) -> BallComparison:
    """Normal FE impacts on a rigid plane of the balls `specs` (presets or ball files, two or
    more, `sweep.check_balls`; the first the reference) at each of `speeds_m_s` (m/s), each ball's
    speeds one batched run (`run_speed_sweep`, `options` a `fe.SolverOptions`, `start` its
    hook: `fe.runs.Start`), `moduli` overriding every ball's convention: every ball loaded and
    its run estimated before any runs. `files` (`fe.output.RunFiles`): its `table` (the long
    table) and `plot` (force-time overlays and the figures against speed) are written, their
    paths in the result's `written`."""
    from ..plotting import save_and_close
    files = RunFiles() if files is None else files
    files.check()
    allow = check_allow(allow)
    specs = check_balls(specs)
    speeds = tuple(float(s) for s in speeds_m_s)
    options = SolverOptions() if options is None else options
    check_sweep_speeds(speeds, allow)
    slowest = min(range(len(speeds)), key=speeds.__getitem__)
    for spec in specs:  # a bad ball, or one too large to run, stops the comparison here
        estimate(sweep_balls(spec, speeds, moduli=moduli, allow=allow)[slowest], speeds, options,
                 allow=allow)
    started = time.perf_counter()
    sweeps = [run_speed_sweep(spec, speeds, options, moduli=moduli, label=spec, allow=allow,
                              start=start,
                              announce=f"simulating {spec} at {len(speeds)} speed(s) ...")
              for spec in specs]
    comparison = BallComparison(specs, speeds, sweeps, compare_rows(sweeps),
                                time.perf_counter() - started)
    if files.table is not None:
        comparison.written["table"] = write_table(comparison.rows, files.table)
    if files.plot is not None:
        figure = sweep_figure(sweeps, overlays=True, title="compare: FE impacts on a rigid plane")
        comparison.written["plot"] = str(save_and_close(figure, files.plot))
    return comparison
