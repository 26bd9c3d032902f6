"""`ballimpact standard METHOD`: a published ball test method (ASTM F1887 COR, F2845 dynamic
stiffness, F1888 compression) on a lab's records (per ball mean, SD, count; over the balls) or on
a ball model (`--ball`: the quantities and the model's cost), docs/standards.md. Two more methods:
`standard bbcor --bat BAT --ball BALL`, a bat's certification (ASTM F2219 / NCAA BBCOR,
`standards.bbcor`; docs/equipment.md), and `standard ball`, the ball file of a homogeneous ball
calibrated by FE runs to a specification's COR and compression (`standards.specification`;
docs/balls.md, "Presets from a specification")."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..errors import CheckFailed, InputError
from ..records.options import RecordOptions
from ..standards import METHODS, describe_methods, get_method, run_method
from ..standards.text import bbcor_lines, method_lines, methods_lines, specified_ball_lines
from .bat import add_ball_model, ball_of
from .common import (add_filtering, add_json, print_lines, record_options,
                     use_compilation_cache)
from .simulate import SolverDefaults

#: the names (lower case) of the two methods that are not `standards.METHODS`
BBCOR_NAMES = ("bbcor", "f2219", "astm f2219")
BALL_NAMES = ("ball",)
#: `standard ball`'s own options (attribute names): the other methods refuse them
BALL_OPTIONS = ("diameter_m", "cor", "compression_n", "deflection_m", "tau1_s", "name", "out")
#: the options of the other methods that `standard ball` refuses, with what they are for
NOT_BALL = (("paths", "FILES_OR_DIRS", "a lab's records"),
            ("ball", "--ball", "a ball model to test; this method writes one"),
            ("bat", "--bat", "bbcor's bat"),
            ("ball_id_pattern", "--ball-id-pattern", "records' ball ids"),
            ("table", "--table", "the methods' CSV table"))
#: the options of the ball methods that bbcor refuses, with what they are for
NOT_BBCOR = (("paths", "FILES_OR_DIRS", "a lab's records"),
             ("mass_kg", "--mass-kg", "records' mass"),
             ("ball_id_pattern", "--ball-id-pattern", "records' ball ids"),
             ("impact_speed_m_s", "--impact-speed-m-s", "the ball methods' speed; bbcor fires "
                                                        "at its own 136 mph"),
             ("element_size_m", "--element-size-m", "the ball methods' mesh"),
             ("table", "--table", "the ball methods' CSV table"))


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
    add_ball_model(standard, "bbcor: ")
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
    # `standard ball`'s own (it takes --mass-kg, --impact-speed-m-s and --element-size-m too)
    ball = standard.add_argument_group(
        "ball (a ball file calibrated to a specification's COR and compression)")
    ball.add_argument("--diameter-m", type=float, help="ball: the ball's diameter (m)")
    ball.add_argument("--cor", type=float,
                      help="ball: its COR off a rigid wall at --impact-speed-m-s (default 60 "
                           "mph), ASTM F1887")
    ball.add_argument("--compression-n", type=float,
                      help="ball: its quasi-static compression force (N; 375 lbf = 1668 N) at "
                           "--deflection-m, ASTM F1888")
    ball.add_argument("--deflection-m", type=float,
                      help="ball: the platens' approach of that force (m; default 0.00635, "
                           "F1888's 0.25 in)")
    ball.add_argument("--tau1-s", type=float,
                      help="ball: its Prony relaxation time (s; default 31.6 us x R / 36 mm, "
                           "the universal model's choice)")
    ball.add_argument("--name", help="ball: the ball's name (default: the --out file's name)")
    ball.add_argument("--out", type=Path, help="ball: the ball file to write (.json)")


def run(args: argparse.Namespace) -> dict[str, Any]:
    if args.list:
        if args.method is not None or args.paths or args.ball is not None:
            raise InputError("--list: give it alone (it lists the methods)")
        methods = describe_methods()
        if not args.json:
            print_lines(methods_lines(methods))
        return {"methods": methods}
    if args.method is None:
        raise InputError(f"METHOD: missing; one of {', '.join(METHODS)}, bbcor, ball (or "
                         "--list)")
    name = args.method.strip().lower()
    if name in BALL_NAMES:
        return _ball(args)
    for attribute in BALL_OPTIONS:
        if getattr(args, attribute) is not None:
            raise InputError(f"{_flag(attribute)}: only `standard ball` takes it, not "
                             f"{args.method}")
    if name in BBCOR_NAMES:
        return _bbcor(args)
    if args.bat is not None:
        raise InputError(f"--bat: only the bbcor method takes a bat, not {args.method}")
    try:
        method = get_method(args.method)
    except InputError as error:
        raise InputError(f"{error}; or bbcor (a bat's BBCOR: --bat, --ball), or ball (a ball "
                         "file from a specification)") from None
    if args.ball is not None:
        use_compilation_cache()
    result = run_method(method, paths=args.paths, ball=args.ball, mass_kg=args.mass_kg,
                        ball_id_pattern=args.ball_id_pattern,
                        impact_speed_m_s=args.impact_speed_m_s,
                        element_size_m=args.element_size_m, record_options=processing_only(args),
                        allow=args.allow, table=args.table)
    if not args.json:
        print_lines(method_lines(result))
    return result


def processing_only(args: argparse.Namespace) -> RecordOptions:
    """The processing flags alone: `standard`'s --impact-speed-m-s is the method's nominal
    speed and its --mass-kg goes to `from_records` itself; neither may replace a record's own."""
    return RecordOptions(**record_options(args).processing())


def _flag(attribute: str) -> str:
    return "--" + attribute.replace("_", "-")


def _refuse(args: argparse.Namespace, options, method: str, then: str = "") -> None:
    """`InputError` for the first of `options` (attribute, flag, what for) given to `method`."""
    for attribute, flag, what in options:
        if getattr(args, attribute, None) not in (None, []):
            raise InputError(f"{flag}: not taken by {method} ({what}){then}")


def _ball(args: argparse.Namespace) -> dict[str, Any]:
    from ..progress import progress_line
    from ..standards.specification import write_specified_ball

    _refuse(args, NOT_BALL, "`standard ball`")
    for attribute in ("diameter_m", "mass_kg", "cor", "compression_n", "out"):
        if getattr(args, attribute) is None:
            raise InputError(f"{_flag(attribute)}: missing; `standard ball` needs --diameter-m, "
                             "--mass-kg, --cor, --compression-n and --out")
    use_compilation_cache()
    out = write_specified_ball(
        args.out, args.diameter_m, args.mass_kg, args.cor, args.compression_n,
        compression_deflection_m=args.deflection_m, impact_speed_m_s=args.impact_speed_m_s,
        tau1_s=args.tau1_s, name=args.name, element_size_m=args.element_size_m,
        progress=progress_line)
    if not args.json:
        print_lines(specified_ball_lines(out))
    missed = out["check"]["missed"]
    if missed:  # not written: a ball that does not meet its specification
        raise CheckFailed(f"the calibration did not close ({'; '.join(missed)}); "
                          f"{args.out} not written", out)
    return out


def _bbcor(args: argparse.Namespace) -> dict[str, Any]:
    from ..standards.bbcor import bbcor_certification

    _refuse(args, NOT_BBCOR, "bbcor", "; give --bat and --ball")
    if args.bat is None:
        raise InputError("--bat: missing; bbcor needs a bat: a preset (baseball-wood-34in, "
                         "baseball-aluminium-bbcor-34in) or a bat file")
    if args.ball is None:
        raise InputError("--ball: missing; a ball preset or file, or hc:MASS_KG:STIFFNESS:"
                         "DAMPING_S_M")
    result = bbcor_certification(args.bat, ball_of(args.ball), ball_model=args.ball_model,
                                 allow=args.allow, progress=True)
    if not args.json:
        print_lines(bbcor_lines(result))
    if not result["meets_limit"]:  # a certification the bat fails: exit 3, the result printed
        raise CheckFailed(f"BBCOR {result['bbcor']:.4f} exceeds the limit "
                          f"{result['limit']:.3f} ({result['designation']})", result)
    return result
