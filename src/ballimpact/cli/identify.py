"""`ballimpact identify`: a universal FE ball from measured impacts."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..verdict import (COMPRESSION_TOLERANCE, add_tolerance_flags, given_flags, raise_if_missed,
                       tolerances_from)
from .common import (add_processing, add_speed_grouping, print_lines, record_options,
                     use_compilation_cache)


def add_parser(verbs) -> None:
    identify = verbs.add_parser(
        "identify", help="universal FE ball (C10, C01, g1, tau1) from measured impacts",
        description="Features of the test -> the universal ball's parameters with 90% "
                    "intervals (inverse deep ensemble), optionally refined on the forward "
                    "surrogate -> one FE run of the identified ball compared with the test. "
                    "Several tests (one per speed) give a table of parameters against speed, "
                    "like thesis table 7-3. An impact speed outside the model's training speeds "
                    "is refused (--allow speed-range: a warning); estimates on the edge of the "
                    "model's training range and intervals clipped by it give warnings. The FE "
                    "check judges force NRMSE, COR, contact time and peak force together (--max-* "
                    "flags; the test's own 90%% uncertainty is added to all but the NRMSE). Exit "
                    "codes: 0 done (the FE check passed), 2 bad input, 1 failed run, 3 the FE "
                    "check missed a criterion (the result is printed and its files written all "
                    "the same).")
    identify.add_argument("files", type=Path, nargs="+", metavar="FILE",
                          help="test record(s): CSV with unit headers or WAV")
    identify.add_argument("--model", help="model path (MODEL.json + MODEL.npz), or "
                                          "sports-ball-universal-model (any homogeneous solid "
                                          "ball at 5-60 m/s); default: the built-in "
                                          "cricket-ball model")
    identify.add_argument("--verify", action=argparse.BooleanOptionalAction, default=True,
                          help="run the identified ball in the FE engine and compare (default)")
    add_tolerance_flags(identify)
    identify.add_argument("--compression", type=Path, metavar="FILE.csv",
                          help="a compression test of the ball (force-deflection CSV, as "
                               "`calibrate --compression` reads it; the slow, long-term curve): "
                               "the identified ball is squeezed as the ball was, and the FE check "
                               "adds its force NRMSE as a criterion. A miss says that one "
                               "homogeneous layer does not give both tests: see "
                               "docs/calibrate.md, 'Layered balls from tests'")
    identify.add_argument("--max-compression-error", type=float, metavar="X",
                          help="largest compression NRMSE (a fraction of the test's largest "
                               f"force) the FE check allows (default {COMPRESSION_TOLERANCE:g})")
    identify.add_argument("--refine", choices=("none", "surrogate"), default="none",
                          help="least squares on the forward surrogate after the inverse "
                               "estimate; default none: on held-out runs it made the closed loop "
                               "worse, see docs/universal.md")
    identify.add_argument("--table", type=Path, metavar="FILE.csv",
                          help="with several files (one per speed): write the speed table")
    identify.add_argument("--ball-out", type=Path, metavar="FILE.json",
                          help="write the identified ball for `simulate --ball`: with several "
                               "files (one per speed), a ball holding the speed table, "
                               "interpolated at the impact speed as the cricket-universal preset")
    identify.add_argument("--ball-diameter-m", type=float, metavar="D",
                          help="the tested ball's diameter (m); default: the model's ball's "
                               "(0.072 m for the built-in model), with a note when the test's "
                               "mass is not that ball's. Any homogeneous ball maps onto the "
                               "model's by similarity (docs/universal.md)")
    add_speed_grouping(identify)
    add_processing(identify)


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..universal.by_speed import identify_files
    from ..universal.text import identification_lines, identified_tests_lines

    tolerances = tolerances_from(args)  # a bad tolerance is refused before anything is loaded
    if args.max_compression_error is not None and args.compression is None:
        raise InputError("--max-compression-error: the tolerance of the compression criterion, "
                         "which needs --compression FILE.csv")
    if given_flags(args) and not args.verify:
        raise InputError(f"{', '.join(given_flags(args))}: the FE check's tolerances, which "
                         "--no-verify turns off")
    if args.verify:
        use_compilation_cache()
    found, out = identify_files(
        args.files, options=record_options(args), model=args.model, verify=args.verify,
        refine=args.refine, allow=args.allow, diameter_m=args.ball_diameter_m,
        nominal_m_s=args.speeds, tolerance=args.speed_tolerance, tolerances=tolerances,
        compression=args.compression, compression_tolerance=(
            COMPRESSION_TOLERANCE if args.max_compression_error is None
            else args.max_compression_error),
        table_path=args.table, ball_path=args.ball_out, plot_path=args.plot,
        each=None if args.json else lambda path, f: print_lines(identification_lines(path, f)))
    if not args.json:
        print_lines(identified_tests_lines(found, out))
    raise_if_missed([(path, f.verification) for path, _, f in found.results], out,
                    "FE check", "the identified ball")
    return out
