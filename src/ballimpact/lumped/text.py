"""The text of the lumped models' results, as `ballimpact fit` and `ballimpact models` print it:
each function returns the lines (without their line ends), so that a Python user gets the
command's text."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..verdict import verdict_line
from .fit import FitResult
from .fit_records import RecordFits
from .speed_table import SpeedTable


def fits_lines(fits: RecordFits) -> list[str]:
    """`fit_records.fit_files`' fits: each fit with its model check (`fit_lines`), then with
    several tests the speed table (CSV) and the parameters' scatter over repeats."""
    lines = [line for f, file, check in zip(fits.fits, fits.labels, fits.checks)
             for line in fit_lines(f, Path(file), check)]
    if fits.table is not None:
        lines += fits.table.to_csv().removesuffix("\n").split("\n")
    for group in fits.repeats:
        spread = ", ".join(f"{k} {group['params_mean'][k]:.5g} +/- {group['params_sd'][k]:.3g}"
                           for k in group["params_mean"])
        lines.append(f"repeats at {group['speed_m_s']:g} m/s ({group['count']} tests): {spread}")
    return lines


def fit_lines(fitted: FitResult, path: Path, check: dict[str, Any]) -> list[str]:
    """One fit of the test `path`: how it ran, the parameters with their standard errors, the
    misfit, the model's and the test's figures and its model check (`verdict.judge`)."""
    m = fitted.measured
    lines = [f"{path.name}: {fitted.model} by {fitted.method.upper()} (seed {fitted.seed}), "
             f"{fitted.evaluations} model runs, {fitted.wall_time_s:.2f} s"]
    for name, value in fitted.params.items():
        error = fitted.standard_errors.get(name, 0.0)
        spread = f" +/- {error:.3g}" if error > 0 else " (fixed)" if name not in fitted.bounds \
            else ""
        unknown = "  not identified" if name in fitted.notes else ""
        lines.append(f"  {name:<10} {value:.6g}{spread} {fitted.units[name]}{unknown}")
    lines += [
        f"  RMSE {fitted.rmse_n:.4g} N, NRMSE {fitted.nrmse:.2%} of the measured peak",
        f"  model:    peak {fitted.peak_force_n:.5g} N, contact "
        f"{fitted.contact_time_s * 1e3:.4g} ms, COR {fitted.cor:.4f}",
        f"  measured: peak {m['peak_force_n']:.5g} N, contact "
        f"{m['contact_time_s'] * 1e3:.4g} ms, COR {m['cor']:.4f}",
        f"  model check {verdict_line(check)}"]
    if fitted.reproduction:
        lines.append("  note: a reproduction of the thesis' appendix code, not a recommended "
                     "model")
    return lines


def repeats_note_lines(table: SpeedTable | None) -> list[str]:
    """The note (one line, or none) naming the tests of a speed table repeated at one speed:
    each keeps its row and the table interpolates between their mean."""
    if table is None:
        return []
    files: dict[float, list[str]] = {}
    for speed, file in zip(table.speeds_m_s, table.labels):
        files.setdefault(speed, []).append(Path(file).name)
    repeated = [f"{speed:g} m/s: {', '.join(names)}" for speed, names in files.items()
                if len(names) > 1]
    if not repeated:
        return []
    return [f"note: tests repeated at one speed ({'; '.join(repeated)}) keep one row each; "
            "the table interpolates between their mean"]


def models_lines(models: list[dict[str, Any]]) -> list[str]:
    """The lumped models (`registry.describe_models`): each with its parameters, their units
    and what they are."""
    lines = []
    for model in models:
        lines.append(f"{model['name']}: {model['summary']}")
        for name, spec in model["params"].items():
            fixed = f" (fixed, default {spec['default']:g})" if "default" in spec else ""
            lines.append(f"    {name:<18} [{spec['unit']}] {spec['description']}{fixed}")
    return lines


__all__ = ["fit_lines", "fits_lines", "models_lines", "repeats_note_lines"]
