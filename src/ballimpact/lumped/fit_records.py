"""A lumped model fitted to processed test records, as `ballimpact fit` does: search bounds
checked against the record's scale (a unit slip), one fit per record (a speed table with
several), each fit's model check against its test, the parameters' scatter over tests repeated
at one speed, and a warning per parameter a record does not determine (docs/lumped.md)."""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..checks import check_allow
from ..errors import InputError, InputWarning
from ..fileio import check_output_folder, check_plot_path, write_atomic
from ..records.options import RecordOptions
from ..records.repeats import expand_records
from ..verdict import Tolerances
from .base import LumpedModel, Scale
from .fit import FitResult, fit
from .registry import get_model
from .speed_table import SpeedTable, fit_speed_table

#: The usual slips of a parameter's unit (`ballimpact models`), as (factor to SI, unit typed),
#: for the unit-slip check of --bound (`calibrate.problem.check_scale`); powers of 1000 besides.
BOUND_SLIPS = {"Pa": ((1e3, "kPa"), (1e6, "MPa"), (1e9, "GPa")),
               "N/m": ((1e3, "kN/m (or N/mm)"),), "N s/m": ((1e3, "kN s/m"),),
               "m": ((1e-3, "mm"),), "s": ((1e-3, "ms"), (1e-6, "us")), "kg": ((1e-3, "g"),)}


def model_check(fitted: FitResult, processed, tolerances: Tolerances = Tolerances()
                ) -> dict[str, Any]:
    """The fitted model's pulse against the test (`verdict.judge`: force NRMSE, COR, contact
    time and peak force, each within its tolerance plus the test's 90% uncertainty)."""
    from ..comparison import compare
    from ..verdict import judge

    m = fitted.measured
    comparison = compare({"P1": m["contact_time_s"], "P6": m["peak_force_n"], "P17": m["cor"]},
                         {"P1": fitted.contact_time_s, "P6": fitted.peak_force_n,
                          "P17": fitted.cor}, fitted.nrmse)
    return {**comparison, **judge(comparison, tolerances, processed.features.uncertainty)}


def typical_values(model: LumpedModel, scale: Scale, exponents: dict | None = None
                   ) -> dict[str, float]:
    """Per parameter of `model`, its typical value in a record of `scale` (`lumped.base.Scale`)
    in the parameter's own units: the middle (geometric where positive) of the model's default
    search bounds; for a power-law stiffness, the middle of its force bounds divided by the
    record's maximum compression to the exponent (from `exponents` {name: value} where given,
    else the middle of its default range); a fixed parameter's default. Unit masses are left out
    (searched as shares)."""
    defaults = model.default_bounds(scale)
    by_name = {p.name: p for p in model.parameters}
    exponents = exponents or {}

    def middle(low: float, high: float) -> float:
        return math.sqrt(low * high) if low > 0 else 0.5 * high

    out: dict[str, float] = {}
    for p in model.parameters:
        if p.search in ("mass_share", "mass_rest"):
            continue
        if p.name not in defaults:
            if p.default:
                out[p.name] = float(p.default)
            continue
        value = middle(*(float(x) for x in defaults[p.name]))
        if p.search == "stiffness":
            exponent = p.exponent
            if isinstance(exponent, str):
                exponent = exponents.get(exponent, middle(*defaults[exponent])
                                         if exponent in defaults else by_name[exponent].default)
            value /= float(scale.max_compression_m) ** float(exponent)
        out[p.name] = value
    return out


def check_bound_scales(model: LumpedModel, processed, bounds: dict, fixed: dict,
                       allow=()) -> None:
    """--bound NAME=LOW:HIGH against the parameter's typical value in a processed record
    (`typical_values`, a power-law stiffness at the exponent given by --fix or --bound): bounds
    that leave it out by more than 100x are a unit slip (kN/m typed for N/m, mm for m, MPa for
    Pa), calibrate --free's check (`calibrate.problem.check_scale`): an `InputError` naming the
    flag, the parameter, its plausible range and the likely slip, or a warning with --allow
    unit-slip. Unknown names and unit masses are left to `lumped.fit`, which names them."""
    from ..calibrate.problem import SCALE_SLIP_FACTOR, check_scale

    f = processed.features
    scale = Scale(f.mass_kg, f.values["P15"], f.values["P1"], f.values["P6"],
                  f.max_compression_m)
    exponents = {name: fixed[name] if name in fixed else 0.5 * sum(bounds[name])
                 for name in set(fixed) | set(bounds)}
    typical = typical_values(model, scale, exponents)
    units = model.units
    for name, (low, high) in bounds.items():
        value = typical.get(name, 0.0)
        if not value:
            continue
        unit = units[name]
        slips = ((1e3, "k" + unit),) if unit.startswith("N/m^") else BOUND_SLIPS.get(unit, ())
        span = f"{value / SCALE_SLIP_FACTOR:.3g}..{value * SCALE_SLIP_FACTOR:.3g} {unit}"
        check_scale(name, low, high, value, allow, option="--bound",
                    reference=f"the typical {name} of {model.name} in this record (plausible "
                              f"range {span})", units=(unit, slips))


def parameter_scatter(table: SpeedTable) -> list[dict[str, Any]]:
    """Per speed group of two or more tests (`repeats.group_by_speed`: within
    `repeats.DEFAULT_SPEED_TOLERANCE`, as identify and report group them): the mean and standard
    deviation (ddof = 1) of each fitted parameter over the repeats (`repeats.mean_sd`): the
    scatter of the tests carried into the parameters."""
    from ..records.repeats import group_by_speed, mean_sd

    rows = [dict(zip(table.params, values)) for values in zip(*table.params.values())]
    groups = group_by_speed(table.speeds_m_s).tolist()
    out = []
    for label in sorted(set(groups)):
        members = [row for row, g in zip(rows, groups) if g == label]
        if len(members) > 1:
            mean, sd = mean_sd(members)
            out.append({"speed_m_s": float(label), "count": len(members),
                        "params_mean": mean, "params_sd": sd})
    return out


@dataclass
class RecordFits:
    """The fits of `fit_records`, one per record in speed order with a table (`labels` the
    records' names, `checks` each fit's `model_check`); `table` the `SpeedTable` and `repeats`
    its `parameter_scatter` with several records, None and empty with one."""

    model: LumpedModel
    fits: list[FitResult]
    labels: list[str]
    checks: list[dict[str, Any]]
    table: SpeedTable | None = None
    repeats: list[dict[str, Any]] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """The JSON of `ballimpact fit` (without the files it wrote and its wall time)."""
        if self.table is None:
            return {**self.fits[0].to_dict(), "file": self.labels[0], "check": self.checks[0]}
        out = {"model": self.model.name, "units": self.model.units,
               "table": self.table.to_dict(),
               "fits": [{**f.to_dict(), "file": label, "check": check}
                        for f, label, check in zip(self.fits, self.labels, self.checks)]}
        if self.repeats:
            out["repeats"] = self.repeats
        return out


def fit_records(processed: Sequence, model: str | LumpedModel, labels: Sequence[str], *,
                tolerances: Tolerances = Tolerances(), allow=(), **options) -> RecordFits:
    """`model` fitted to each processed record (`pipeline.ProcessedImpact`), named by `labels`
    (file names): one `fit`, or with several records `fit_speed_table`. `options` are those of
    `fit` (`bounds` and `fixed` checked first against each record's scale,
    `check_bound_scales`, with `allow`); each fit gets its `model_check` with `tolerances`, and a
    warning names each parameter a record does not determine."""
    model = get_model(model)
    labels = [str(label) for label in labels]
    for one in processed:
        check_bound_scales(model, one, options.get("bounds") or {}, options.get("fixed") or {},
                           allow)
    if len(processed) == 1:
        result = RecordFits(model, [fit(processed[0], model, **options)], labels, [])
        ordered = list(processed)
    else:
        table, fits = fit_speed_table(processed, model, labels=labels, **options)
        order = {label: i for i, label in enumerate(labels)}
        ordered = [processed[order[label]] for label in table.labels]
        result = RecordFits(model, fits, list(table.labels), [], table, parameter_scatter(table))
    for f, label in zip(result.fits, result.labels):
        for note in f.notes.values():
            warnings.warn(f"{Path(label).name}: {note}", InputWarning, stacklevel=2)
    result.checks = [model_check(f, p, tolerances) for f, p in zip(result.fits, ordered)]
    return result


def fit_files(paths: Sequence[Path], *, model: str | LumpedModel,
              options: RecordOptions = RecordOptions(),
              tolerances: Tolerances = Tolerances(), allow=(), table_path: Path | None = None,
              plot_path: Path | None = None, **fit_options) -> tuple[RecordFits, dict[str, Any]]:
    """`fit_records` on the record files of `paths` (`repeats.expand_records`: folders and
    built-in sets too), each loaded and processed as `options` say; `fit_options` are `fit`'s.
    Writes the speed table (CSV, `table_path`, several files only) and the fit or fits over the
    tests (PNG, `plot_path`). Returns the fits and the command's result: `RecordFits.to_dict`
    with `table_csv` and `plot` where written and `wall_time_s`. `InputError`, before anything
    is loaded, for a bad output path, an unknown model and `table_path` with one file."""
    check_plot_path(plot_path)
    check_output_folder(table_path, "--table")
    model = get_model(model)
    files = expand_records(paths)
    if table_path is not None and len(files) < 2:
        raise InputError("--table: needs several files")
    started = time.perf_counter()
    options = options.allowing(check_allow(allow))
    fits = fit_records([options.process(options.load(path)) for path in files], model,
                       [str(p) for p in files], tolerances=tolerances, allow=allow,
                       **fit_options)
    result = fits.to_dict()
    if fits.table is not None and table_path is not None:
        write_atomic(table_path, fits.table.to_csv())
        result["table_csv"] = str(table_path)
    if plot_path is not None:
        from ..plotting import plot_fit, plot_speed_fits

        if fits.table is None:
            plot_fit(fits.fits[0], plot_path, title=str(files[0].name))
        else:
            plot_speed_fits(fits.fits, plot_path)
        result["plot"] = str(plot_path)
    result["wall_time_s"] = time.perf_counter() - started
    return fits, result


__all__ = ["BOUND_SLIPS", "RecordFits", "check_bound_scales", "fit_files", "fit_records",
           "model_check", "parameter_scatter", "typical_values"]
