"""The text of a calibration, as `ballimpact calibrate` prints it: the lines (without their line
ends), so that a Python user gets the command's text."""

from __future__ import annotations

from typing import Any


def calibration_lines(result: dict[str, Any], stage_results: list) -> list[str]:
    """`files.calibrate_from_files`' result and its `StageResult`s: per stage its free
    parameters and tests, how the design was chosen or refined, the values found (with their
    standard errors after a refinement) and the objectives; then the FE runs and the ball file
    written."""
    lines = []
    for r in stage_results:
        d = r.to_dict()
        lines.append(f"{r.stage.name}: {len(r.problem.free)} free, tests "
                     f"{', '.join(d['tests'])}; {r.fe_runs} FE runs, {r.wall_time_s:.0f} s")
        if r.decision is not None:
            lines.append(f"  chosen from {len(d['pareto'])} Pareto designs by "
                         f"{r.decision.reason}")
        if r.refinement is not None:
            f = r.refinement
            lines.append(f"  gradient refinement: misfit {f.start_misfit:.4g} -> {f.misfit:.4g} "
                         f"in {f.residual_evaluations} misfit and {f.jacobian_evaluations} "
                         f"Jacobian evaluations ({f.message})")
        for path, value in r.values.items():
            extra = ""
            if r.refinement is not None:
                extra = f"  +/- {r.refinement.standard_error[path]:.3g} (1 s.e.)"
                if path in r.refinement.not_identified:
                    extra += "  not identified"
            lines.append(f"  {path:<40} {value:12.5g}{extra}")
        lines.append("  objectives: " + ", ".join(f"{k} {v:.4g}"
                                                  for k, v in r.objectives.items()))
    lines.append(f"{result['evaluations']} FE runs in {result['wall_time_s']:.1f} s")
    if "ball_file" in result:
        lines.append(f"calibrated ball: {result['ball_file']}")
    return lines


__all__ = ["calibration_lines"]
