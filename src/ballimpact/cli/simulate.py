"""`ballimpact simulate`: an FE impact (axisymmetric or 3D), a speed sweep or an angle sweep, and
the solver flags other verbs share (`add_solver_options`, `SolverDefaults`). The runs are the
library's (`fe.runs.simulate_impact`, `fe.runs.simulate_speeds`, `oblique.sweep.simulate_angles`);
here the flags are turned into their arguments, and the text is `fe.text`'s and
`oblique.text`'s."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..fe.sweep import parse_speeds
from .common import (add_allow, add_json, finite_float, parsed, print_lines,
                     use_compilation_cache)


class SolverDefaults:
    """FE defaults shown in --help (kept equal to `fe.SolverOptions` by a test)."""

    element_size_m = 1.5e-3
    penalty_scale = 1.0
    integration = "reduced"
    precision = "float64"


def add_parser(verbs) -> None:
    simulate = verbs.add_parser(
        "simulate", help="FE impact of a ball on a surface or a target (normal: axisymmetric; "
                         "oblique, spin: 3d)",
        description="Explicit FE (hyper-viscoelastic layers, penalty contact) of a ball hitting a "
                    "flat surface: contact force history, COR, contact time, energies and the 19 "
                    "features. --solver axisymmetric (default) runs normal impacts on a rigid "
                    "plane or a layered target (--target: a pad, a helmet; flat or a spherical "
                    "cap; its base fixed or backed by a headform's mass); --solver 3d runs "
                    "oblique impacts with Coulomb friction and spin, on a rigid plane or a flat "
                    "target, and adds normal_cor, "
                    "tangential_cor, rebound_angle_deg and rebound_spin_rad_s. Runs longer than "
                    "a few seconds print their progress on stderr; a mesh estimated above "
                    "2e9 element updates (elements x steps; 3d: 3e8), about 5 min on a 2-core "
                    "CPU, or 4 GiB of histories and frames gets a warning before the run starts, "
                    "and a run whose memory estimate (made before meshing) exceeds the memory "
                    "available is refused unless --allow large-run (docs/fe.md).")
    simulate.add_argument("--ball", required=True,
                          help="preset (see `ballimpact balls`) or ball specification JSON/TOML")
    simulate.add_argument("--speed-m-s", type=speed_list, required=True,
                          help="impact speed (m/s), or several separated by commas (5,10,20,30: "
                               "a speed sweep, one batched run, axisymmetric solver only)")
    simulate.add_argument("--angle-deg", type=angle_list, default=0.0,
                          help="angle of the incoming velocity from the surface normal (deg; "
                               "3d solver), or several in [0, 89] separated by commas "
                               "(5,10,20,30,45,60: an angle sweep, one batched run at one speed, "
                               "with a table, --table CSV and --plot of the gripping regime "
                               "against the rigid-body lines and, for a one-layer elastic ball, "
                               "the elastic-sphere reference; docs/oblique.md)")
    simulate.add_argument("--spin-rad-s", type=float, default=0.0,
                          help="spin about the axis parallel to the surface and normal to the "
                               "incoming tangential velocity (rad/s; + topspin; 3d solver)")
    simulate.add_argument("--friction", type=float, default=0.0,
                          help="Coulomb coefficient (3d solver; irrelevant at normal incidence)")
    simulate.add_argument("--solver", choices=("axisymmetric", "3d"), default="axisymmetric",
                          help="axisymmetric (normal impacts, default) or 3d (hexahedra)")
    add_allow(simulate)
    add_solver_options(simulate)
    # given or not: the 3d solver refuses an axisymmetric mesh size (None: the default)
    simulate.set_defaults(element_size_m=None)
    simulate.add_argument("--target",
                          help="a layered target: a preset (cricket-helmet, foam-pad) or a "
                               "target file (JSON; docs/equipment.md); default: a rigid plane")
    three = simulate.add_argument_group("3d solver")
    three.add_argument("--spin-x-rad-s", type=float, default=0.0,
                       help="out-of-plane spin about the incoming tangential velocity (rad/s, "
                            "right-handed; needs the full model, chosen automatically)")
    three.add_argument("--spin-z-rad-s", type=float, default=0.0,
                       help="out-of-plane spin about the surface normal (rad/s, right-handed)")
    three.add_argument("--divisions", type=int,
                       help="hexahedra along each 90 degrees of arc (even, 4 to 64; default 16)")
    three.add_argument("--pole-grading", type=float,
                       help="arc spacing at the equator over that at the contact pole "
                            "(1 to 40; default 2, or finer until 3 elements span the expected "
                            "contact)")
    three.add_argument("--contact-elements", type=float,
                       help="grade the mesh so that this many elements span the Hertz contact "
                            "radius expected at the (slowest) normal speed; sets the pole "
                            "grading (0.5 to 50; docs/oblique.md, 'Gripping regime')")
    three.add_argument("--full-model", action="store_true", help="mesh the whole ball "
                       "(default: the half on the plane of incidence, unless spun out of it)")
    three.add_argument("--stick-scale", type=float,
                       help="friction stick-spring stiffness over the normal penalty (default 8)")
    three.add_argument("--slab-depth-growth", type=float,
                       help="match a --target slab's cells to the contact: the ball's pole "
                            "spacing at its centre, growing as the ball's cells do in plane and "
                            "by this a cell through the depth (over 1, up to 2)")
    three.add_argument("--slab-depth-cell-m", type=float, help="a --target slab's cells "
                       "through the depth (m; default 4 pole spacings): finer for liners")
    three.add_argument("--vtk", type=Path,
                       help="write a time series for ParaView: FILE.pvd (binary .vtu files "
                            "beside it) or FILE.xdmf; displacement, velocity, stresses, contact "
                            "pressure")
    three.add_argument("--animate", type=Path,
                       help="write an animation (.gif, or .mp4 with ffmpeg) of the mid-plane "
                            "section")
    simulate.add_argument("--moduli", choices=("long_term", "instantaneous"),
                          help="override the balls' moduli convention: long_term or "
                               "instantaneous")
    add_json(simulate)
    simulate.add_argument("--csv", type=Path, help="write the histories (one row per step)")
    simulate.add_argument("--plot", type=Path,
                          help="PNG: force-time curve and deformed shape at peak force (a sweep: "
                               "COR, peak force and contact time against speed)")
    simulate.add_argument("--table", type=Path,
                          help="CSV: a row per speed (COR, peak force, contact time, deflection, "
                               "rebound speed, dynamic stiffness; SI)")


def add_solver_options(parser: argparse.ArgumentParser) -> None:
    """The mesh and solver flags of every verb that runs the FE engine."""
    parser.add_argument("--element-size-m", type=float, default=SolverDefaults.element_size_m,
                        help=f"element length on the outer surface (m; default "
                             f"{SolverDefaults.element_size_m:g})")
    parser.add_argument("--pole-element-size-m", type=float,
                        help="refine toward the contact pole to this element length (m)")
    parser.add_argument("--integration", choices=("reduced", "full"),
                        default=SolverDefaults.integration,
                        help="reduced: one point with hourglass control (default); full: 2x2 "
                             "(3d: 2x2x2) points with F-bar")
    parser.add_argument("--precision", choices=("float64", "float32"),
                        default=SolverDefaults.precision,
                        help="arithmetic of the explicit steps (default float64)")
    parser.add_argument("--penalty-scale", type=float,
                        help="contact penalty scale (default 1; 3d: 3 where fewer than 4 "
                             "elements span the expected contact, else 1)")


def speed_list(text: str) -> float | tuple[float, ...]:
    """argparse type of `--speed-m-s`: one speed (a float, as before the sweeps) or a tuple of
    several (`sweep.parse_speeds`)."""
    speeds = parsed(parse_speeds, text)
    return speeds[0] if len(speeds) == 1 else speeds


def angle_list(text: str) -> float | tuple[float, ...]:
    """argparse type of `--angle-deg`: one angle (a float, checked by the 3D solver) or a tuple
    of several (an angle sweep, `oblique.sweep.parse_angles`)."""
    if "," not in text:
        return finite_float(text)
    from ..oblique.sweep import parse_angles

    return parsed(parse_angles, text)


def _values(given) -> tuple[float, ...]:
    """A flag's values: one number, or a tuple or list of them."""
    return tuple(float(v) for v in given) if isinstance(given, (tuple, list)) else (float(given),)


def given_speeds(args: argparse.Namespace) -> tuple[float, ...]:
    """The `--speed-m-s` values (m/s), ascending."""
    return tuple(sorted(_values(args.speed_m_s)))


def solver_options(args: argparse.Namespace):
    from ..fe import SolverOptions

    size = SolverDefaults.element_size_m if args.element_size_m is None else args.element_size_m
    penalty = SolverDefaults.penalty_scale if args.penalty_scale is None else args.penalty_scale
    return SolverOptions(element_size_m=size, pole_element_size_m=args.pole_element_size_m,
                         penalty_scale=penalty, integration=args.integration,
                         precision=args.precision)


def _options_3d(args: argparse.Namespace):
    """The 3D flags as `fe.Options3D` (None: its defaults)."""
    from ..fe import Options3D

    given = {"divisions": args.divisions, "pole_grading": args.pole_grading,
             "stick_scale": args.stick_scale}
    return Options3D(**{k: v for k, v in given.items() if v is not None},
                     contact_elements=args.contact_elements,
                     half=False if args.full_model else None, integration=args.integration,
                     penalty_scale=args.penalty_scale, slab_depth_growth=args.slab_depth_growth,
                     slab_depth_cell_m=args.slab_depth_cell_m, precision=args.precision)


#: flags of one solver only (attribute: the flag's name in snake case)
FLAGS_3D = ("--angle-deg", "--spin-rad-s", "--spin-x-rad-s", "--spin-z-rad-s", "--vtk",
            "--animate", "--divisions", "--pole-grading", "--contact-elements", "--full-model",
            "--stick-scale", "--slab-depth-growth", "--slab-depth-cell-m")
FLAGS_AXISYMMETRIC = ("--element-size-m", "--pole-element-size-m")


def _check_solver_flags(args: argparse.Namespace, speeds, angles) -> None:
    """No flag of the other solver (it would be ignored silently: refused, naming the solver),
    and one list at a time: several speeds run axisymmetric, several angles in 3D."""
    def given(flag):
        return getattr(args, flag[2:].replace("-", "_"))

    if len(angles) > 1:
        if args.solver != "3d":
            raise InputError("--angle-deg: a sweep of angles needs --solver 3d")
        if len(speeds) > 1:
            raise InputError("--speed-m-s: an angle sweep runs at one speed; give one speed with "
                             "a list of --angle-deg (or one angle with a list of speeds)")
    elif len(speeds) > 1 and args.solver == "3d":
        raise InputError("--speed-m-s: a list of speeds (a sweep) runs with the axisymmetric "
                         "solver only; with --solver 3d give one speed per run")
    if args.solver == "3d":
        for flag in FLAGS_AXISYMMETRIC:
            if given(flag) is not None:
                raise InputError(f"{flag}: sets the axisymmetric mesh; the 3d solver's mesh is "
                                 "set by --divisions and --pole-grading")
        return
    for flag in FLAGS_3D:
        if given(flag) not in (None, 0.0, False):
            raise InputError(f"{flag}: oblique and spinning impacts, 3D output and the 3D mesh "
                             "need --solver 3d")


def start_run(cost):
    """The `start` hook of the library's runs (`fe.runs.Start`): JAX's compilation cache, then
    what is about to run and the estimate's warning (also in the end's list) on stderr, and the
    run's progress lines on stderr."""
    from ..fe import RunProgress

    use_compilation_cache()
    warning = cost.warning()
    for line in (cost.announce, None if warning is None else f"warning: {warning}"):
        if line:
            print(line, file=sys.stderr, flush=True)
    return RunProgress(cost.end_time_s, cost.chunk_steps)


def run_simulate(args: argparse.Namespace) -> dict[str, Any]:
    from ..fe import Axisymmetric, Hexahedral
    from ..fe.output import RunFiles

    speeds, angles = given_speeds(args), _values(args.angle_deg)
    _check_solver_flags(args, speeds, angles)
    three_d = args.solver == "3d"
    files = RunFiles(csv=args.csv, table=args.table, vtk=getattr(args, "vtk", None),
                     animation=getattr(args, "animate", None), plot=args.plot)
    common = {"moduli": args.moduli, "allow": args.allow, "files": files, "start": start_run}
    spins = {"spin_rad_s": args.spin_rad_s, "spin_x_rad_s": args.spin_x_rad_s,
             "spin_z_rad_s": args.spin_z_rad_s, "friction": args.friction,
             "target": args.target}
    if len(angles) > 1:  # several angles: one batched 3D run
        from ..oblique.sweep import simulate_angles
        from ..oblique.text import angle_sweep_lines

        out = simulate_angles(args.ball, speeds[0], angles, Hexahedral(_options_3d(args)),
                              **spins, **common)
        lines = angle_sweep_lines(out)
    elif len(speeds) > 1:  # several speeds: one batched axisymmetric run
        from ..fe.runs import simulate_speeds
        from ..fe.text import speed_sweep_lines

        out = simulate_speeds(args.ball, speeds, solver_options(args), target=args.target,
                              **common)
        lines = speed_sweep_lines(out)
    else:  # the run of one impact
        from ..fe.runs import simulate_impact
        from ..fe.text import impact_3d_lines, impact_lines

        geometry = (Hexahedral(_options_3d(args)) if three_d
                    else Axisymmetric(solver_options(args)))
        result, out = simulate_impact(args.ball, speeds[0], geometry, angle_deg=angles[0],
                                      **spins, **common)
        lines = (impact_3d_lines if three_d else impact_lines)(result, out)
    if not args.json:
        print_lines(lines)
    return out
