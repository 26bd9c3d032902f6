"""`ballimpact standard METHOD`: a published ball test method (ASTM F1887 COR, F2845 dynamic
stiffness, F1888 compression) on a lab's records (per ball mean, SD, count; over the balls) or on
a ball model (`--ball`: the quantities and the model's cost). docs/standards.md. `standard bbcor
--bat BAT --ball BALL`, a bat's certification, is `standard_bbcor`'s (docs/equipment.md); `standard
ball`, a ball file calibrated to a specification's COR and compression, `standard_ball`'s."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..standards import METHODS, describe_methods, get_method, run_method, stats_text
from .common import add_json, add_filtering, processing_options, use_compilation_cache
from . import standard_ball
from .simulate import SolverDefaults


def add_parser(verbs) -> None:
    listed = "; ".join(f"{name} ({m.designation}): {m.description}"
                       for name, m in METHODS.items())
    standard = verbs.add_parser(
        "standard", help="a published ball test method (COR, dynamic stiffness, compression) on "
                         "a lab's records or a ball model",
        description="Run a published ball test method on a lab's records (files or folders: "
                    "per ball mean +- SD (n) of the method's quantities and the mean and SD of "
                    "the ball means) or on a ball model (--ball: the quantities and the model's "
                    f"cost). Methods: {listed}. The ball id of a record is its file name up to "
                    "the last '_' or '-' (ballA_01.csv -> ballA) unless --ball-id-pattern says "
                    "otherwise (docs/standards.md). 'standard bbcor --bat BAT --ball BALL': the "
                    "BBCOR certification of a baseball bat (ASTM F2219 / NCAA BBCOR) on the "
                    "bat's model (docs/equipment.md, 'BBCOR'). 'standard ball --diameter-m D "
                    "--mass-kg M --cor E --compression-n F --out FILE': a ball file calibrated "
                    "by FE runs to a specification's COR and compression (docs/balls.md).")
    standard.add_argument("method", nargs="?", metavar="METHOD",
                          help=f"one of {', '.join(METHODS)} (or the designation, e.g. F1887), "
                               "or bbcor (a bat: --bat, --ball), or ball (a ball file from a "
                               "specification)")
    standard.add_argument("paths", nargs="*", type=Path, metavar="FILES_OR_DIRS",
                          help="a lab's records: impact records (CSV/WAV with JSON side files) "
                               "or compression curves (CSV), or folders of them")
    standard.add_argument("--list", action="store_true",
                          help="list the methods with a one-line description each")
    standard.add_argument("--ball",
                          help="run the method on this ball model: a preset (see `ballimpact "
                               "balls`) or a ball specification JSON/TOML; with bbcor also "
                               "hc:MASS_KG:STIFFNESS:DAMPING_S_M")
    standard.add_argument("--bat",
                          help="bbcor: the bat, a preset (baseball-wood-34in, "
                               "baseball-aluminium-bbcor-34in) or a bat file (JSON/TOML)")
    standard.add_argument("--ball-model", choices=("fe", "law"), default="fe",
                          help="bbcor: the FE ball itself on the bat's modes (default) or its "
                               "contact law (faster)")
    standard.add_argument("--mass-kg", type=float,
                          help="ball mass (kg) of every impact record, over its side file's; "
                               "with ball, the ball's")
    standard.add_argument("--ball-id-pattern", metavar="REGEX",
                          help="regular expression searched in each file name (without suffix): "
                               "its group 'ball', else its first group, else the match is the "
                               "ball id (default: the name up to its last '_' or '-')")
    standard.add_argument("--impact-speed-m-s", type=float,
                          help="run or judge the impact methods at this inbound speed (m/s) "
                               "instead of the method's 26.82 m/s (60 mph); reported as such")
    standard.add_argument("--element-size-m", type=float,
                          help=f"--ball: element length on the outer surface (m; default "
                               f"{SolverDefaults.element_size_m:g} m x R / 0.036 m: the "
                               "universal study's mesh scaled to the ball)")
    standard.add_argument("--table", type=Path,
                          help="write a CSV: a row per shot, per ball and over all balls")
    add_json(standard)
    add_filtering(standard)
    standard_ball.add_arguments(standard)


def run(args: argparse.Namespace) -> dict[str, Any]:
    if args.list:
        if args.method is not None or args.paths or args.ball is not None:
            raise InputError("--list: give it alone (it lists the methods)")
        methods = describe_methods()
        if not args.json:
            for entry in methods:
                print(f"{entry['method']:<18} {entry['designation']:<11} {entry['description']}")
        return {"methods": methods}
    if args.method is None:
        raise InputError(f"METHOD: missing; one of {', '.join(METHODS)}, bbcor, ball (or "
                         "--list)")
    from . import standard_bbcor

    if standard_ball.is_ball(args.method):
        return standard_ball.run(args)
    for attribute in standard_ball.OWN_OPTIONS:
        if getattr(args, attribute) is not None:
            raise InputError(f"--{attribute.replace('_', '-')}: only `standard ball` takes it, "
                             f"not {args.method}")
    if standard_bbcor.is_bbcor(args.method):
        return standard_bbcor.run(args)
    if args.bat is not None:
        raise InputError(f"--bat: only the bbcor method takes a bat, not {args.method}")
    try:
        method = get_method(args.method)
    except InputError as error:
        raise InputError(f"{error}; or bbcor (a bat's BBCOR: --bat, --ball), or ball (a ball "
                         "file from a specification)") from None
    if args.ball is not None:
        use_compilation_cache()
    options = {k: v for k, v in processing_options(args).items() if k != "allow"}
    result = run_method(method, paths=args.paths, ball=args.ball, mass_kg=args.mass_kg,
                        ball_id_pattern=args.ball_id_pattern,
                        impact_speed_m_s=args.impact_speed_m_s,
                        element_size_m=args.element_size_m, process_options=options,
                        allow=args.allow, table=args.table)
    if not args.json:
        (print_model if result["source"] == "model" else print_records)(result)
    return result


def print_records(result: dict[str, Any]) -> None:
    """Per ball mean +- SD (n) of each quantity, then the line over the balls."""
    quantities, overall = result["quantities"], result["overall"]
    print(f"{result['designation']} {result['method']}: {overall['shots']} records, "
          f"{overall['balls']} balls" + (f" ({result['nominal_speed_note']})"
                                         if "nominal_speed_note" in result else ""))
    for entry in result["balls"]:
        parts = [stats_text(entry[key], unit) for key, unit in quantities.items()]
        if "impact_speed_m_s" in entry:
            parts.append(f"inbound {stats_text(entry['impact_speed_m_s'], 'm/s')}")
        print(f"  {entry['ball']:<16} " + "; ".join(parts) + f" (n={entry['count']})")
    parts = [stats_text(overall[key], unit) for key, unit in quantities.items()]
    print(f"  {'all balls':<16} " + "; ".join(parts)
          + f" (mean and SD of {overall['balls']} ball means)")


def print_model(result: dict[str, Any]) -> None:
    """The method's quantities on the model, then its cost."""
    values, cost = result["result"], result["cost"]
    parts = [f"{values[key]:.5g}" + (f" {unit}" if unit else "")
             for key, unit in result["quantities"].items()]
    where = (f"at {values['impact_speed_m_s']:.4g} m/s" if "impact_speed_m_s" in values
             else f"at {values['deflection_m'] * 1e3:.3g} mm")
    print(f"{result['designation']} {result['method']} of {result['ball']} (model) {where}: "
          + "; ".join(parts))
    steps = (f"{cost['steps']} steps" if "steps" in cost
             else f"{cost['increments']} increments, {cost['newton_iterations']} Newton "
                  "iterations")
    print(f"  cost: {cost['wall_time_s']:.2f} s wall, {steps}, {cost['elements']} elements "
          f"({cost['element_size_m']:g} m)")
