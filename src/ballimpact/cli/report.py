"""`ballimpact report`: every model against every test, as an HTML page, JSON and CSV tables."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..fileio import check_distinct_files
from ..verdict import add_tolerance_flags, tolerances_from
from .common import (add_json, add_filtering, add_record_options, load, process_record,
                     use_compilation_cache)

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
    from ..report import build_report, builtin_files, parse_models
    from ..report.build import raise_if_unmatched
    from ..report.inputs import builtin_ball, builtin_note, check_test_record, label_tests
    from ..report.models import check_balls

    tolerances = tolerances_from(args)
    if bool(args.files) == bool(args.builtin):
        raise InputError("report: give test files or --builtin sample|speeds (one of the two)")
    if not args.out.parent.is_dir():
        raise InputError(f"--out: folder {args.out.parent} does not exist")
    if args.out.exists() and not args.out.is_dir():
        raise InputError(f"--out: {args.out} is a file, not a folder")
    if args.seed < 0:
        raise InputError(f"--seed: must be an integer >= 0, got {args.seed}")
    check_distinct_files(args.files, "TEST")  # each once, and each with its own speed
    for flag, value in (("--impact-speed-m-s", args.impact_speed_m_s),
                        ("--rebound-speed-m-s", args.rebound_speed_m_s)):
        if value is not None and len(args.files) > 1:
            raise InputError(f"{flag}: one speed for {len(args.files)} test files; each test "
                             "has its own: give it in the file's side file (FILE.json with "
                             "impact_speed_m_s and rebound_speed_m_s)")
    # the generating ball of a built-in set joins the default models
    ball = builtin_ball(args.builtin) if args.builtin and args.models is None else None
    # an empty --models is a mistake, not a request for the default
    models = parse_models(args.models if args.models is not None
                          else DEFAULT_MODELS + (f",{ball}" if ball is not None else ""))
    files = builtin_files(args.builtin) if args.builtin else args.files
    processed = [process_record(check_test_record(load(path, args), path, len(files)), args)
                 for path in files]
    tests = label_tests([str(f) for f in files], processed)
    check_balls(models, tests[len(tests) // 2].speed_m_s, args.allow)
    universal = None
    if any(m.kind == "universal" for m in models):
        from ..universal.model import load_model

        universal = load_model(args.universal_model)
    use_compilation_cache()
    note = builtin_note(args.builtin, ball) if args.builtin else ""
    result = build_report(tests, models, args.out, seed=args.seed, universal_model=universal,
                          note=note, progress=not args.quiet, allow=args.allow,
                          tolerances=tolerances)
    if not args.json:
        _print(result)
    raise_if_unmatched(result)
    return result


def _print(result: dict[str, Any]) -> None:
    tables = result["tables"]
    for key in ("nrmse", "cor_error"):
        table = tables[key]
        print(table["title"])
        print("  " + "".join(f"{c:>20}" for c in table["columns"]))
        for row in table["rows"]:
            cells = [f"{row[0]:>20}"] + [_cell(v, key) for v in row[1:]]
            print("  " + "".join(cells))
    for model in dict.fromkeys(r["model"] for r in result["runs"]):
        mine = [r for r in result["runs"] if r["model"] == model]
        passed = sum(r["check"]["passed"] for r in mine)
        print(f"  check {model}: passed on {passed} of {len(mine)} tests")
    for failure in result["failures"]:
        print(f"failed: {failure['model']} at {failure['test']}: {failure['error']}")
    print(f"report: {result['report_html']} ({result['wall_time_s']:.1f} s)")


def _cell(value: Any, key: str) -> str:
    if isinstance(value, str):  # "failed"
        return f"{value:>20}"
    return f"{value:>20.2%}" if key == "nrmse" else f"{value:>+20.4f}"
