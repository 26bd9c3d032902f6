"""FE runs as the command line makes them, callable from Python with SI arguments: a ball loaded
with its moduli convention overridden, each run's cost estimated before anything is meshed or
compiled, a `start(cost)` hook between the estimate and the run (to warn and announce; it
returns the run's progress callback), and the JSON summaries of one impact and of a speed sweep.

`ballimpact simulate` prints what these return; `sweep` and `oblique.sweep` hold the sweeps'
science (rows, tables, figures).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from .speed_range import check_fe_speed
from ..balls.ball import BallModel, load_ball
from .engine import Axisymmetric, Geometry, default_group_size, estimate, simulate
from .options import SolverOptions
from .progress import RunEstimate
from .result import ImpactResult

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
            allow=()):
    """`start(estimate)` of a run of `ball` under `conditions` on `geometry`: the estimate is
    made (and a run that would not fit in memory refused) before anything is meshed; None
    without `start`."""
    if start is None:
        return None
    return start(estimate(ball, conditions, geometry=geometry, target=target, allow=allow))


def run_impact(ball: BallModel, condition, geometry: Geometry | None = None, *, target=None,
               allow=(), start: Start | None = None,
               frames: int = ANIMATION_FRAMES) -> ImpactResult:
    """One impact (`fe.simulate`: `condition` an `ImpactCondition` or a normal speed in m/s,
    `geometry` default `Axisymmetric()`, `target` a slab or None) after its estimate and
    `start` (`started`). Frames kept for output (`Options3D.frames`) are thinned to about
    `frames`, evenly spread over the run."""
    geometry = Axisymmetric() if geometry is None else geometry
    progress = started(start, ball, condition, geometry, target=target, allow=allow)
    result = simulate(ball, condition, progress=progress, geometry=geometry, target=target,
                      allow=allow)
    if len(result.frames) > frames:
        keep = np.unique(np.linspace(0, len(result.frames) - 1, frames).astype(int))
        result.frames[:] = [result.frames[i] for i in keep]
    return result


def run_speed_sweep(spec, speeds_m_s: Sequence[float], options=None, *,
                    moduli: str | None = None, label: str = "", allow=(),
                    start: Start | None = None):
    """Ball `spec` at each of `speeds_m_s` (m/s; ascending) in one batched axisymmetric run
    (`sweep.sweep_balls`, `sweep.run_sweep`): the speeds checked first (`check_sweep_speeds`),
    the cost estimated with the ball of the slowest speed (the longest run) before meshing, then
    `start`; its progress callback is used when the sweep runs as one vmapped group. Returns
    the `sweep.Sweep`."""
    from .sweep import run_sweep, sweep_balls

    check_sweep_speeds(speeds_m_s, allow)
    balls = sweep_balls(spec, speeds_m_s, moduli=moduli, allow=allow)
    geometry = Axisymmetric(SolverOptions() if options is None else options)
    slowest = balls[int(np.argmin(speeds_m_s))]
    progress = started(start, slowest, list(speeds_m_s), geometry, allow=allow)
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
                for k, v in layer.material.constants().items()}} for layer in ball.layers]
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


def sweep_json_row(result: ImpactResult) -> dict[str, Any]:
    """A speed sweep's row (`sweep.sweep_row`, SI) with the run's energy balance error, steps and
    ball name."""
    from .sweep import sweep_row

    return {**sweep_row(result), "energy_balance_error": result.energy_balance_error,
            "steps": result.steps, "ball_name": result.ball_name}


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
