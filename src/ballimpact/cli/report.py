"""`ballimpact report`: every model against every test, as an HTML page, JSON and CSV tables."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..verdict import add_tolerance_flags, tolerances_from
from .common import (add_json, add_filtering, add_record_options, print_lines, record_options,
                     use_compilation_cache)

#: for the help only: `report.build.DEFAULT_MODELS` (that package loads JAX and matplotlib)
DEFAULT_MODELS = "single_element,three_element,universal"


def add_parser(verbs) -> None:
    report = verbs.add_parser(
        "report", help="compare lumped, universal and FE models against tests at several speeds",
        description="Fit each lumped model to each test, identify the universal ball from each "
                    "test and run it, run each ball file as it is, and write DIR/report.html "
                    "(self-contained: tables and inline figures), DIR/report.json and a CSV per "
                    "table: force-time overlays, NRMSE, COR and contact time against speed, "
                    "parameters against speed and the computing cost (thesis chapter 7).")
    report.add_argument("files", type=Path, nargs="*", metavar="TEST",
                        help="test record(s): CSV with unit headers or WAV, one per speed "
                             "(speeds from side files or flags)")
    report.add_argument("--builtin", choices=("sample", "speeds"),
                        help="built-in SYNTHETIC tests instead of files: the sample test at "
                             "20.8 m/s, or an FE three-layer ball at 5.5, 10, 20.8 and 25 m/s "
                             "(then its generating ball joins the models as the detailed FE model)")
    report.add_argument("--models", default=None,
                        help="comma-separated: lumped models (`ballimpact models`), universal, "
                             f"ball presets or ball files (default {DEFAULT_MODELS})")
    report.add_argument("--universal-model", help="universal model path (MODEL.json + MODEL.npz);"
                                                  " default: the built-in cricket-ball model")
    report.add_argument("--out", type=Path, required=True, metavar="DIR",
                        help="output folder (made if missing; its parent must exist)")
    report.add_argument("--seed", type=int, default=0,
                        help="seed of the lumped GA fits (default 0)")
    add_filtering(report)
    report.add_argument("--quiet", action="store_true", help="no progress bar")
    add_json(report)
    add_record_options(report)
    add_tolerance_flags(report)


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..report.build import raise_if_unmatched, report_files
    from ..report.text import report_lines

    tolerances = tolerances_from(args)
    for flag, value in (("--impact-speed-m-s", args.impact_speed_m_s),
                        ("--rebound-speed-m-s", args.rebound_speed_m_s)):
        if value is not None and len(args.files) > 1:
            raise InputError(f"{flag}: one speed for {len(args.files)} test files; each test "
                             "has its own: give it in the file's side file (FILE.json with "
                             "impact_speed_m_s and rebound_speed_m_s)")
    use_compilation_cache()
    result = report_files(args.files, args.out, options=record_options(args),
                          builtin=args.builtin, models=args.models,
                          universal_model=args.universal_model, seed=args.seed,
                          progress=not args.quiet, allow=args.allow, tolerances=tolerances)
    if not args.json:
        print_lines(report_lines(result))
    raise_if_unmatched(result)
    return result
