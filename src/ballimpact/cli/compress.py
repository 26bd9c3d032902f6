"""`ballimpact compress`: the whole ball squeezed between two rigid platens (quasi-static FE,
`fe.compress`): the force-deflection curve, peak force and stiffness; JSON, CSV and a plot."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..progress import CountProgress
from .common import add_json, add_allow, print_lines, use_compilation_cache
from ..fe.options import COMPRESSION_PENALTY_SCALE
from .simulate import SolverDefaults

#: print progress lines only for curves that take longer than this (s)
PROGRESS_AFTER_S = 3.0


def add_parser(verbs) -> None:
    compress = verbs.add_parser(
        "compress", help="the ball squeezed between two rigid platens (force-deflection curve)",
        description="Quasi-static FE compression of the whole ball between two rigid, "
                    "frictionless platens (the ball on one, the other coming down on its top), "
                    "with the impact solver's mesh and materials: the force against the platens' "
                    "approach (the diameter change), its peak and the stiffness at the end. "
                    "Without --rate-m-s the long-term (fully relaxed) curve; with it, the Prony "
                    "terms relax over the time the platen takes (docs/materials.md).")
    compress.add_argument("--ball", required=True,
                          help="preset (see `ballimpact balls`) or ball specification JSON/TOML")
    compress.add_argument("--deflection-m", type=float, required=True,
                          help="total platen approach, the ball's diameter change (m; up to its "
                               "radius)")
    compress.add_argument("--rate-m-s", type=float,
                          help="platen speed (m/s); default: the long-term (relaxed) curve")
    compress.add_argument("--steps", type=int, default=20,
                          help="equal deflection increments (default 20)")
    compress.add_argument("--impact-speed-m-s", type=float,
                          help="for balls whose constants depend on the impact speed "
                               "(cricket-universal): the speed to take them at (m/s)")
    compress.add_argument("--solver", choices=("axisymmetric", "3d"), default="axisymmetric",
                          help="the mesh: axisymmetric (default) or 3d (hexahedra, the impact "
                               "engine's 3D geometry; slower, a check of the same ball in 3D)")
    compress.add_argument("--element-size-m", type=float,
                          help=f"axisymmetric: element length on the outer surface away from "
                               f"the platens (m; default {SolverDefaults.element_size_m:g}); "
                               "both poles are refined to resolve the platens' contact")
    compress.add_argument("--divisions", type=int,
                          help="3d: hexahedra along each 90 degrees of arc (even, 4 to 64; "
                               "default 16)")
    compress.add_argument("--pole-grading", type=float,
                          help="3d: arc spacing at the equator over that at the poles (1 to 40; "
                               "default: chosen to resolve the platens' contact)")
    compress.add_argument("--full-model", action="store_true",
                          help="3d: mesh the whole ball (default: the half, a mirror plane)")
    compress.add_argument("--integration", choices=("reduced", "full"),
                          default=SolverDefaults.integration,
                          help="reduced: one point with hourglass control (default); full: 2x2 "
                               "points with F-bar")
    compress.add_argument("--penalty-scale", type=float, default=COMPRESSION_PENALTY_SCALE,
                          help=f"platen contact penalty over the impact solver's (default "
                               f"{COMPRESSION_PENALTY_SCALE:g})")
    compress.add_argument("--moduli", choices=("long_term", "instantaneous"),
                          help="override the ball's moduli convention")
    add_allow(compress)
    add_json(compress)
    compress.add_argument("--csv", type=Path, help="write the curve (deflection_m,force_n)")
    compress.add_argument("--plot", type=Path, help="PNG: force against deflection")


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..fe.compression import compress_ball
    from ..fe.text import compression_lines

    three_d = {"--divisions": args.divisions, "--pole-grading": args.pole_grading,
               "--full-model": args.full_model or None}
    given = [flag for flag, value in three_d.items() if value is not None]
    if args.solver == "3d" and args.element_size_m is not None:
        raise InputError("--element-size-m: sets the axisymmetric mesh; the 3d mesh is set by "
                         "--divisions and --pole-grading")
    if args.solver != "3d" and given:
        raise InputError(f"{given[0]}: sets the 3d mesh; add --solver 3d")
    use_compilation_cache()
    out = compress_ball(args.ball, args.deflection_m, rate_m_s=args.rate_m_s, steps=args.steps,
                        impact_speed_m_s=args.impact_speed_m_s, solver=args.solver,
                        element_size_m=args.element_size_m or SolverDefaults.element_size_m,
                        divisions=args.divisions, pole_grading=args.pole_grading,
                        full_model=args.full_model, integration=args.integration,
                        penalty_scale=args.penalty_scale, moduli=args.moduli, allow=args.allow,
                        csv_path=args.csv, plot_path=args.plot,
                        progress=CountProgress("increment", quiet_s=PROGRESS_AFTER_S))
    if not args.json:
        print_lines(compression_lines(out))
    return out
