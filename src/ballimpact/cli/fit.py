"""`ballimpact fit` and `ballimpact models`: lumped models identified from tests."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..verdict import add_tolerance_flags, raise_if_missed, tolerances_from
from .common import (add_json, add_processing, assignments, print_lines, record_options,
                     use_compilation_cache)


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
    add_processing(fit)
    add_tolerance_flags(fit)

    models = verbs.add_parser("models", help="list the lumped models and their parameters",
                              description="The lumped models, their parameters and SI units.")
    add_json(models)


def run_fit(args: argparse.Namespace) -> dict[str, Any]:
    from ..lumped.fit_records import fit_files  # JAX and pymoo: only for the verbs needing them
    from ..lumped.text import fits_lines, repeats_note_lines

    use_compilation_cache()
    fits, result = fit_files(
        args.files, options=record_options(args), model=args.model,
        tolerances=tolerances_from(args), allow=args.allow, table_path=args.table,
        plot_path=args.plot, method=args.method, seed=args.seed, population=args.population,
        generations=args.generations, polish=not args.no_polish,
        bounds=assignments(args.bound, "--bound", bounds=True),
        fixed=assignments(args.fix, "--fix", bounds=False), cor_weight=args.cor_weight,
        contact_time_weight=args.contact_time_weight)
    print_lines(repeats_note_lines(fits.table), file=sys.stderr)
    if not args.json:
        print_lines(fits_lines(fits))
    raise_if_missed(list(zip(fits.labels, fits.checks)), result, "model check", "the model")
    return result


def run_models(args: argparse.Namespace) -> dict[str, Any]:
    from ..lumped import describe_models
    from ..lumped.text import models_lines

    models = describe_models()
    if not args.json:
        print_lines(models_lines(models))
    return {"models": models}
