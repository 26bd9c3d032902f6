"""`ballimpact export` (ball models for ABAQUS, CalculiX, LS-DYNA and ParaView) and
`ballimpact import-material` (ABAQUS materials into the ball specification)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from .common import add_json, add_allow, print_lines


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
                    "of an ABAQUS input file into our material form (SI). With --ball, a deck "
                    "written by `ballimpact export` gives back the whole ball specification.")
    imp.add_argument("file", type=Path, help="ABAQUS input (.inp)")
    imp.add_argument("--units", choices=tuple(UNIT_SYSTEMS),
                     help="the file's unit system (default: its '** units' header line)")
    imp.add_argument("--ball", action="store_true",
                     help="the whole ball (radii from the mesh) of a deck written by export")
    imp.add_argument("--out", type=Path, help="write the result as JSON to this file")
    add_json(imp)
    add_allow(imp)


def run_export(args: argparse.Namespace) -> dict[str, Any]:
    from ..export import export_ball_spec
    from ..export.text import export_lines, note_lines

    out = export_ball_spec(args.ball, args.out, args.format, speed_m_s=args.speed_m_s,
                           angle_deg=args.angle_deg, friction=args.friction,
                           step_time_s=args.step_time_s, solver=args.solver,
                           ball_only=args.ball_only, units=args.units, moduli=args.moduli,
                           approximate=args.approximate, element_size_m=args.element_size_m,
                           divisions=args.divisions, pole_grading=args.pole_grading,
                           half=args.half_model, allow=args.allow)
    print_lines(note_lines(out), file=sys.stderr)
    if not args.json:
        print_lines(export_lines(out))
    return out


def run_import(args: argparse.Namespace) -> dict[str, Any]:
    from ..export.importer import import_abaqus_file, imported_json

    out = import_abaqus_file(args.file, args.units, ball=args.ball, allow=args.allow,
                             out_path=args.out)
    if not args.json:
        print(imported_json(out))
    return out
