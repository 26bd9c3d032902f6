"""`ballimpact fit` and `ballimpact models`: lumped models identified from tests."""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings
from pathlib import Path
from typing import Any

from ..errors import InputError, InputWarning
from ..fileio import write_atomic
from ..verdict import add_tolerance_flags, raise_if_missed, tolerances_from
from ..repeats import expand_records
from .common import (
    add_processing,
    add_record_options,
    assignments,
    check_output_folder,
    check_plot_path,
    load,
    process_record,
    use_compilation_cache,
)


def add_parser(verbs) -> None:
    fit = verbs.add_parser(
        "fit", help="identify a lumped model from a test, or from tests at several speeds",
        description="Fit a lumped model (see `ballimpact models`) to the force pulse of a test by "
                    "a genetic algorithm or differential evolution and a least-squares polish. "
                    "With several files the parameters form a table against speed, as thesis "
                    "tables 7-1 and 7-2: one row per file, labelled with it; tests repeated at "
                    "one speed keep a row each (their scatter stays visible) and the table "
                    "interpolates between their mean.")
    fit.add_argument("files", type=Path, nargs="+", metavar="FILE_OR_DIR",
                     help="test record(s): CSV with unit headers or WAV, or folders of them "
                          "(their *.csv and *.wav files), or a built-in set (builtin:sample, "
                          "builtin:speed-set)")
    fit.add_argument("--model", required=True, help="lumped model name (see `ballimpact models`)")
    fit.add_argument("--method", default="ga",
                     help="ga (genetic algorithm) or de (differential evolution); default ga")
    fit.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    fit.add_argument("--population", type=int,
                     help="population size (default 4 per searched quantity, at least 32)")
    fit.add_argument("--generations", type=int,
                     help="generations (default 8 per searched quantity, at least 40)")
    fit.add_argument("--no-polish", action="store_true", help="skip the least-squares polish")
    fit.add_argument("--bound", action="append", default=[], metavar="NAME=LOW:HIGH",
                     help="search bounds of a parameter in its own SI units, as `ballimpact "
                          "models` lists them (a power-law k in N/m^alpha, not a force); the "
                          "JSON `bounds` are in the same units and can be passed back; bounds "
                          "more than 100x from the parameter's scale in the record are a unit "
                          "slip (--allow unit-slip) (repeatable)")
    fit.add_argument("--fix", action="append", default=[], metavar="NAME=VALUE",
                     help="hold a parameter at a value in SI (repeatable)")
    fit.add_argument("--cor-weight", type=float, default=0.0,
                     help="weight of the COR error in the fitness (default 0)")
    fit.add_argument("--contact-time-weight", type=float, default=0.0,
                     help="weight of the relative contact-time error in the fitness (default 0)")
    fit.add_argument("--table", type=Path,
                     help="with several files: write the speed table CSV (one row per file)")
    add_record_options(fit)
    add_processing(fit)
    add_tolerance_flags(fit)

    models = verbs.add_parser("models", help="list the lumped models and their parameters",
                              description="The lumped models, their parameters and SI units.")
    models.add_argument("--json", action="store_true", help="print one JSON object")


def run_fit(args: argparse.Namespace) -> dict[str, Any]:
    from .. import lumped  # JAX and pymoo load only for the verbs that need them

    use_compilation_cache()
    check_plot_path(args.plot)
    check_output_folder(args.table, "--table")
    model = lumped.get_model(args.model)
    tolerances = tolerances_from(args)
    options = dict(method=args.method, seed=args.seed, population=args.population,
                   generations=args.generations, polish=not args.no_polish,
                   bounds=assignments(args.bound, "--bound", bounds=True),
                   fixed=assignments(args.fix, "--fix", bounds=False),
                   cor_weight=args.cor_weight, contact_time_weight=args.contact_time_weight)
    args.files = expand_records(args.files)  # folders and built-in sets, as `features DIR`
    if args.table is not None and len(args.files) < 2:
        raise InputError("--table: needs several files")
    started = time.perf_counter()
    processed = [process_record(load(path, args), args) for path in args.files]
    for one in processed:
        check_bound_scales(model, one, options["bounds"], options["fixed"], args.allow)
    if len(processed) == 1:
        fitted = lumped.fit(processed[0], model, **options)
        result = {**fitted.to_dict(), "file": str(args.files[0]),
                  "check": model_check(fitted, processed[0], tolerances)}
        _warn_not_identified(fitted, args.files[0])
        if not args.json:
            _print_fit(fitted, args.files[0], result["check"])
        if args.plot:
            from ..plotting import plot_fit

            plot_fit(fitted, args.plot, title=str(args.files[0].name))
            result["plot"] = str(args.plot)
        result["wall_time_s"] = time.perf_counter() - started
        raise_if_missed([(args.files[0], result["check"])], result, "model check", "the model")
        return result
    table, fits = lumped.fit_speed_table(processed, model, labels=[str(p) for p in args.files],
                                         **options)
    _note_repeats(table)
    for f, file in zip(fits, table.labels):
        _warn_not_identified(f, Path(file))
    checks = [model_check(f, pr, tolerances) for f, pr in zip(fits, processed)]
    result = {"model": model.name, "units": model.units, "table": table.to_dict(),
              "fits": [{**f.to_dict(), "file": file, "check": check}
                       for f, file, check in zip(fits, table.labels, checks)]}
    repeated = parameter_scatter(table)
    if repeated:
        result["repeats"] = repeated
    if args.table is not None:
        write_atomic(args.table, table.to_csv())
        result["table_csv"] = str(args.table)
    if not args.json:
        for f, file, check in zip(fits, table.labels, checks):
            _print_fit(f, Path(file), check)
        print(table.to_csv(), end="")
        for group in repeated:
            spread = ", ".join(f"{k} {group['params_mean'][k]:.5g} +/- {group['params_sd'][k]:.3g}"
                               for k in group["params_mean"])
            print(f"repeats at {group['speed_m_s']:g} m/s ({group['count']} tests): {spread}")
    if args.plot:
        from ..plotting import plot_speed_fits

        plot_speed_fits(fits, args.plot)
        result["plot"] = str(args.plot)
    result["wall_time_s"] = time.perf_counter() - started
    raise_if_missed(list(zip(table.labels, checks)), result, "model check", "the model")
    return result


def model_check(fitted, processed, tolerances) -> dict[str, Any]:
    """The fitted model's pulse against the test (`verdict.judge`: force NRMSE, COR, contact
    time and peak force, each within its tolerance plus the test's 90% uncertainty)."""
    from ..comparison import compare
    from ..verdict import judge

    m = fitted.measured
    comparison = compare({"P1": m["contact_time_s"], "P6": m["peak_force_n"], "P17": m["cor"]},
                         {"P1": fitted.contact_time_s, "P6": fitted.peak_force_n,
                          "P17": fitted.cor}, fitted.nrmse)
    return {**comparison, **judge(comparison, tolerances, processed.features.uncertainty)}


#: The usual slips of a parameter's unit (`ballimpact models`), as (factor to SI, unit typed),
#: for the unit-slip check of --bound (`calibrate.problem.check_scale`); powers of 1000 besides.
BOUND_SLIPS = {"Pa": ((1e3, "kPa"), (1e6, "MPa"), (1e9, "GPa")),
               "N/m": ((1e3, "kN/m (or N/mm)"),), "N s/m": ((1e3, "kN s/m"),),
               "m": ((1e-3, "mm"),), "s": ((1e-3, "ms"), (1e-6, "us")), "kg": ((1e-3, "g"),)}


def typical_values(model, scale, exponents: dict | None = None) -> dict[str, float]:
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


def check_bound_scales(model, processed, bounds: dict, fixed: dict, allow) -> None:
    """--bound NAME=LOW:HIGH against the parameter's typical value in a processed record
    (`typical_values`, a power-law stiffness at the exponent given by --fix or --bound): bounds
    that leave it out by more than 100x are a unit slip (kN/m typed for N/m, mm for m, MPa for
    Pa), calibrate --free's check (`calibrate.problem.check_scale`): an `InputError` naming the
    flag, the parameter, its plausible range and the likely slip, or a warning with --allow
    unit-slip. Unknown names and unit masses are left to `lumped.fit`, which names them."""
    from ..calibrate.problem import SCALE_SLIP_FACTOR, check_scale
    from ..lumped.base import Scale

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


def _warn_not_identified(fitted, path: Path) -> None:
    """One warning per parameter the record does not determine (standard error inf or larger
    than the value), naming the file: its value is one of many that fit as well."""
    for note in fitted.notes.values():
        warnings.warn(f"{path.name}: {note}", InputWarning, stacklevel=2)


def parameter_scatter(table) -> list[dict[str, Any]]:
    """Per speed group of two or more tests (`repeats.group_by_speed`: within
    `repeats.DEFAULT_SPEED_TOLERANCE`, as identify and report group them): the mean and standard
    deviation (ddof = 1) of each fitted parameter over the repeats (`repeats.mean_sd`): the
    scatter of the tests carried into the parameters."""
    from ..repeats import group_by_speed, mean_sd

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


def _note_repeats(table) -> None:
    """One line on stderr naming the tests repeated at one speed (each keeps its row)."""
    files: dict[float, list[str]] = {}
    for speed, file in zip(table.speeds_m_s, table.labels):
        files.setdefault(speed, []).append(Path(file).name)
    repeated = [f"{speed:g} m/s: {', '.join(names)}" for speed, names in files.items()
                if len(names) > 1]
    if repeated:
        print(f"note: tests repeated at one speed ({'; '.join(repeated)}) keep one row each; "
              "the table interpolates between their mean", file=sys.stderr)


def _print_fit(fitted, path: Path, check: dict[str, Any]) -> None:
    from ..verdict import verdict_line

    m = fitted.measured
    print(f"{path.name}: {fitted.model} by {fitted.method.upper()} (seed {fitted.seed}), "
          f"{fitted.evaluations} model runs, {fitted.wall_time_s:.2f} s")
    for name, value in fitted.params.items():
        error = fitted.standard_errors.get(name, 0.0)
        spread = f" +/- {error:.3g}" if error > 0 else " (fixed)" if name not in fitted.bounds \
            else ""
        unknown = "  not identified" if name in fitted.notes else ""
        print(f"  {name:<10} {value:.6g}{spread} {fitted.units[name]}{unknown}")
    print(f"  RMSE {fitted.rmse_n:.4g} N, NRMSE {fitted.nrmse:.2%} of the measured peak")
    print(f"  model:    peak {fitted.peak_force_n:.5g} N, contact {fitted.contact_time_s * 1e3:.4g} "
          f"ms, COR {fitted.cor:.4f}")
    print(f"  measured: peak {m['peak_force_n']:.5g} N, contact {m['contact_time_s'] * 1e3:.4g} ms, "
          f"COR {m['cor']:.4f}")
    print(f"  model check {verdict_line(check)}")
    if fitted.reproduction:
        print("  note: a reproduction of the thesis' appendix code, not a recommended model")


def run_models(args: argparse.Namespace) -> dict[str, Any]:
    from ..lumped import describe_models

    models = describe_models()
    if not args.json:
        for model in models:
            print(f"{model['name']}: {model['summary']}")
            for name, spec in model["params"].items():
                fixed = f" (fixed, default {spec['default']:g})" if "default" in spec else ""
                print(f"    {name:<18} [{spec['unit']}] {spec['description']}{fixed}")
    return {"models": models}
