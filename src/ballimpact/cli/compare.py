"""`ballimpact compare`: two or more FE balls side by side at the same impact speeds, without
tests (a ball against its calibrated version, two presets, two ball files)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from .common import add_allow, add_json, print_lines
from .simulate import add_solver_options, given_speeds, solver_options, speed_list, start_run


def add_parser(verbs) -> None:
    compare = verbs.add_parser(
        "compare", help="two or more balls side by side at the same speeds (FE, no tests)",
        description="Normal FE impacts on a rigid plane of two or more balls at the same speeds "
                    "(each ball's speeds one batched run): per speed the COR, peak force, "
                    "contact time, centre deflection, rebound speed and dynamic stiffness "
                    "F^2/(m v^2) of each ball, and each ball against the first (COR difference "
                    "absolute, the others in %).")
    compare.add_argument("--ball", action="append", required=True,
                         help="preset (see `ballimpact balls`) or ball specification JSON/TOML; "
                              "give two or more, the first is the reference")
    compare.add_argument("--speed-m-s", type=speed_list, required=True,
                         help="impact speeds (m/s), separated by commas (e.g. 10,20,30)")
    compare.add_argument("--moduli", choices=("long_term", "instantaneous"),
                         help="override every ball's moduli convention")
    add_allow(compare)
    add_solver_options(compare)
    add_json(compare)
    compare.add_argument("--table", type=Path,
                         help="CSV: a row per speed and ball, with the differences from the "
                              "first ball (SI)")
    compare.add_argument("--plot", type=Path,
                         help="PNG: force-time overlays per speed, and COR, peak force and "
                              "contact time against speed")


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..fe.output import RunFiles
    from ..fe.runs import compare_balls
    from ..fe.text import comparison_lines

    comparison = compare_balls(args.ball, given_speeds(args), solver_options(args),
                               moduli=args.moduli, allow=args.allow,
                               files=RunFiles(table=args.table, plot=args.plot), start=start_run)
    out = comparison.to_dict()
    if not args.json:
        print_lines(comparison_lines(out))
    return out
