"""`ballimpact export` (ball models for ABAQUS, CalculiX, LS-DYNA and ParaView) and
`ballimpact import-material` (ABAQUS materials into the ball specification)."""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path
from typing import Any

from ..errors import InputError, InputWarning
from ..checks import check_allow
from .common import add_json, add_allow


def add_parser(verbs) -> None:
    from ..export import FORMATS, SOLVERS, UNIT_SYSTEMS

    export = verbs.add_parser(
        "export", help="write a ball model for ABAQUS, CalculiX, LS-DYNA or ParaView",
        description="Write a runnable deck of the ball hitting a rigid plane (mesh, layers as "
                    "element sets and sections, materials, initial velocity, plane, contact, "
                    "step, output of the contact force and energies), or with --ball-only the "
                    "ball alone for inclusion in a larger model. The file header states the "
                    "units and every approximation; notes also go to stderr.")
    export.add_argument("--ball", required=True,
                        help="preset (see `ballimpact balls`) or ball specification JSON/TOML")
    export.add_argument("--format", required=True, help=f"one of {', '.join(FORMATS)}")
    export.add_argument("--out", type=Path, required=True,
                        help="output file: .inp (abaqus, calculix), .k (lsdyna), .vtu/.vtk/.xdmf")
    export.add_argument("--solver", choices=SOLVERS, default="axisymmetric",
                        help="axisymmetric (CAX4R / 2D axisymmetric solids) or 3d (C3D8R / "
                             "hexahedra); default axisymmetric")
    export.add_argument("--speed-m-s", type=float,
                        help="impact speed (m/s); needed for a complete deck and by "
                             "speed-dependent balls (cricket-universal)")
    export.add_argument("--angle-deg", type=float,
                        help="angle of the incoming velocity from the plane's normal (deg; 3d; "
                             "default 0); a complete deck only")
    export.add_argument("--friction", type=float,
                        help="Coulomb coefficient (default 0); a complete deck only")
    export.add_argument("--step-time-s", type=float,
                        help="simulated time (s); default 1.5 x a Hertz estimate of the contact "
                             "time")
    export.add_argument("--ball-only", action="store_true",
                        help="only the ball: mesh, sets, sections, materials")
    export.add_argument("--units", choices=tuple(UNIT_SYSTEMS),
                        help="unit system of the file (default mm-tonne-s for decks, si for VTK)")
    export.add_argument("--moduli", choices=("long_term", "instantaneous"),
                        help="override the balls' moduli convention; for CalculiX also which "
                             "elastic ball replaces a viscoelastic one")
    export.add_argument("--approximate", action="store_true",
                        help="LS-DYNA: write the nearest card for a material without an exact "
                             "counterpart (said in the header and on stderr)")
    export.add_argument("--element-size-m", type=float,
                        help="axisymmetric mesh: surface element length (m; default the solver's)")
    export.add_argument("--divisions", type=int, help="3d mesh: hexahedra per 90 deg of arc")
    export.add_argument("--pole-grading", type=float, help="3d mesh: grading toward the pole")
    export.add_argument("--half-model", action="store_true",
                        help="3d impact deck: the half y >= 0 with a symmetry plane")
    add_json(export)
    add_allow(export)

    imp = verbs.add_parser(
        "import-material", help="read ABAQUS material blocks into the ball specification",
        description="Read *MATERIAL blocks (*DENSITY, *HYPERELASTIC MOONEY-RIVLIN / NEO HOOKE / "
                    "YEOH / OGDEN, *HYPERFOAM, *ELASTIC, *VISCOELASTIC TIME=PRONY, MODULI=...) "
                    "of an ABAQUS input file into our material form (SI). With --ball, a deck written by "
                    "`ballimpact export` gives back the whole ball specification.")
    imp.add_argument("file", type=Path, help="ABAQUS input (.inp)")
    imp.add_argument("--units", choices=tuple(UNIT_SYSTEMS),
                     help="the file's unit system (default: its '** units' header line)")
    imp.add_argument("--ball", action="store_true",
                     help="the whole ball (radii from the mesh) of a deck written by export")
    imp.add_argument("--out", type=Path, help="write the result as JSON to this file")
    add_json(imp)
    add_allow(imp)


def _refuse_other_solver_mesh(args: argparse.Namespace) -> None:
    """A mesh flag of the other solver would be ignored silently: refuse it."""
    if args.solver == "3d" and args.element_size_m is not None:
        raise InputError("--element-size-m: sets the axisymmetric mesh; with --solver 3d the "
                         "mesh is set by --divisions and --pole-grading")
    if args.solver == "axisymmetric":
        for flag, value in (("--divisions", args.divisions),
                            ("--pole-grading", args.pole_grading)):
            if value is not None:
                raise InputError(f"{flag}: sets the 3D mesh; the axisymmetric mesh is set by "
                                 "--element-size-m (or give --solver 3d)")


def _warn_ignored_impact_flags(args: argparse.Namespace) -> None:
    """The impact's flags mean nothing to a file of the ball alone (--ball-only, or VTK): an
    `InputWarning` that names those given."""
    ignored = [flag for flag, value in (("--angle-deg", args.angle_deg),
                                        ("--friction", args.friction),
                                        ("--step-time-s", args.step_time_s)) if value is not None]
    if ignored:
        what = "--ball-only" if args.ball_only else "--format vtk"
        warnings.warn(f"{', '.join(ignored)}: ignored with {what} (the file holds the ball "
                      "alone, no impact); they set a complete deck's impact", InputWarning,
                      stacklevel=2)


def run_export(args: argparse.Namespace) -> dict[str, Any]:
    from ..export import ImpactSetup, check_output, export_ball
    from ..fe.runs import load_model

    check_output(args.out, args.format)
    _refuse_other_solver_mesh(args)
    allow = check_allow(args.allow)
    ball = load_model(args.ball, args.speed_m_s, moduli=args.moduli, allow=allow)
    setup = None
    if not args.ball_only and args.format != "vtk":
        if args.speed_m_s is None:
            raise InputError("--speed-m-s: needed for a complete deck (or give --ball-only)")
        setup = ImpactSetup(args.speed_m_s, args.angle_deg or 0.0, args.friction or 0.0,
                            args.step_time_s)
    else:
        _warn_ignored_impact_flags(args)
    written = export_ball(ball, args.out, args.format, solver=args.solver, setup=setup,
                          ball_only=args.ball_only, units=args.units, moduli=args.moduli,
                          approximate=args.approximate, element_size_m=args.element_size_m,
                          divisions=args.divisions, pole_grading=args.pole_grading,
                          half=args.half_model, allow=allow)
    for note in written.notes:
        print(f"note: {note}", file=sys.stderr)
    out = {"ball": ball.name, "mass_kg": ball.mass_kg, **written.summary()}
    if setup is not None:
        out.update(impact_speed_m_s=setup.speed_m_s, angle_deg=setup.angle_deg,
                   friction=setup.friction)
    if not args.json:
        what = "ball" if written.ball_only else "impact deck"
        print(f"wrote {written.path}: {args.format} {what} of {ball.name} ({written.solver}, "
              f"{written.n_nodes} nodes, {written.n_elements} elements, units {written.units})")
    return out


def run_import(args: argparse.Namespace) -> dict[str, Any]:
    from ..export import read_abaqus_file

    allow = check_allow(args.allow)
    if args.out is not None and not args.out.parent.is_dir():  # before reading anything
        raise InputError(f"--out: folder {args.out.parent} does not exist")
    out = read_abaqus_file(args.file, args.units, ball=args.ball, allow=allow)
    text = json.dumps(out.get("ball", out), indent=2)
    if args.out is not None:
        try:
            args.out.write_text(text + "\n")
        except OSError as error:
            raise InputError(f"--out: cannot write {args.out} ({error.strerror or error})") from None
    if not args.json:
        print(text)
    return out
