"""`ballimpact compare`: two or more FE balls side by side at the same impact speeds, without
tests (a ball against its calibrated version, two presets, two ball files)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from .common import add_allow, add_json
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
    from ..fe.sweep import compare_balls

    comparison = compare_balls(args.ball, given_speeds(args), solver_options(args),
                               moduli=args.moduli, allow=args.allow,
                               files=RunFiles(table=args.table, plot=args.plot), start=start_run)
    out = comparison.to_dict()
    if not args.json:
        _print(out)
    return out


def _print(out: dict[str, Any]) -> None:
    from .simulate_text import print_written

    reference = out["reference_ball"]
    width = max(12, *(len(b) + 2 for b in out["balls"]))
    print(f"compare: {len(out['balls'])} balls at {len(out['speeds_m_s'])} speed(s), FE on a "
          f"rigid plane; differences from {reference} (COR absolute, others %)")
    print(f"{'speed m/s':>10}  {'ball':<{width}}{'COR':>8}{'peak kN':>9}{'contact ms':>11}"
          f"{'stiff MN/m':>11}{'dCOR':>9}{'dpeak %':>9}{'dcontact %':>11}{'dstiff %':>10}")
    for r in out["comparison"]:
        same = r["ball"] == reference
        diffs = (f"{'':>9}{'':>9}{'':>11}{'':>10}" if same else
                 f"{r['cor_difference']:>+9.4f}{r['peak_force_difference_percent']:>+9.2f}"
                 f"{r['contact_time_difference_percent']:>+11.2f}"
                 f"{r['dynamic_stiffness_difference_percent']:>+10.2f}")
        print(f"{r['impact_speed_m_s']:>10.4g}  {r['ball']:<{width}}{r['cor']:>8.4f}"
              f"{r['peak_force_n'] / 1e3:>9.3f}{r['contact_time_s'] * 1e3:>11.4f}"
              f"{r['dynamic_stiffness_n_m'] / 1e6:>11.4g}{diffs}")
    print_written(out)
    print(f"{out['wall_time_s']:.2f} s wall")
