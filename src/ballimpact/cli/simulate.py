"""`ballimpact simulate`: an FE impact (axisymmetric or 3D), a speed sweep, and the solver flags
other verbs share (`add_solver_options`, `SolverDefaults`); runs are the library's (`fe.runs`,
`sweep`, `oblique.sweep`), the 3D inputs and text in `simulate_3d`, angles in `angle_sweep`."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..checks import check_allow
from .angle_sweep import parse_angles, run_angle_sweep
from .common import add_json, add_allow, check_output_folder, finite_float
from ..fe.sweep import parse_speeds, sweep_figure, write_table
from .simulate_3d import (check_flags, checked_allow, inputs_3d, load_checked_target, print_3d,
                          starter)


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
    """argparse type of `--speed-m-s`: one impact speed (m/s; a float, as the flag was before the
    sweeps) or a comma-separated list of several (a tuple), each a finite number, none empty or
    given twice (`sweep.parse_speeds`)."""
    try:
        speeds = parse_speeds(text)
    except InputError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    return speeds[0] if len(speeds) == 1 else speeds


def angle_list(text: str) -> float | tuple[float, ...]:
    """argparse type of `--angle-deg`: one angle (deg; a float, checked by the 3D solver as
    before the sweeps) or a comma-separated list of several (a tuple: an angle sweep,
    `angle_sweep.parse_angles`)."""
    if "," not in text:
        return finite_float(text)
    try:
        return parse_angles(text)
    except InputError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def given_speeds(args: argparse.Namespace) -> tuple[float, ...]:
    """The `--speed-m-s` values (m/s), ascending: one number, or a tuple from `speed_list`."""
    speeds = args.speed_m_s
    return tuple(sorted(speeds)) if isinstance(speeds, (tuple, list)) else (float(speeds),)


def solver_options(args: argparse.Namespace):
    from ..fe import SolverOptions

    size = SolverDefaults.element_size_m if args.element_size_m is None else args.element_size_m
    return SolverOptions(element_size_m=size,
                         pole_element_size_m=args.pole_element_size_m,
                         penalty_scale=(SolverDefaults.penalty_scale if args.penalty_scale is None
                                        else args.penalty_scale), integration=args.integration,
                         precision=args.precision)


def _with(args: argparse.Namespace, **values) -> argparse.Namespace:
    return argparse.Namespace(**{**vars(args), **values})


def run_simulate(args: argparse.Namespace) -> dict[str, Any]:
    if isinstance(args.angle_deg, (tuple, list)):
        if len(args.angle_deg) > 1:  # several angles: one batched 3D run
            return run_angle_sweep(args)
        # a caller's namespace holding [angle]: the run of one impact
        args = _with(args, angle_deg=float(args.angle_deg[0]))
    speeds = given_speeds(args)
    if len(speeds) > 1:
        return _run_sweep(args, speeds)
    if isinstance(args.speed_m_s, (tuple, list)):  # a caller's namespace holding [v]
        args = _with(args, speed_m_s=speeds[0])
    return _run_one(args)  # one speed: the run of one impact, as before the sweeps


def _run_one(args: argparse.Namespace) -> dict[str, Any]:
    """One impact (`fe.runs.run_impact`), its summary and files, and its text unless --json."""
    from ..fe import Axisymmetric, Hexahedral
    from ..fe.output import write_run_files
    from ..fe.runs import impact_summary, load_model, run_impact

    # every check on the input before anything is printed (progress, warnings) or meshed
    check_output_folder(args.csv, "--csv")
    table = getattr(args, "table", None)
    if args.solver == "3d" and table is not None:
        raise InputError("--table: the sweep table of the axisymmetric solver; a 3d run's "
                         "figures are in --json")
    check_flags(args)
    allow = checked_allow(args)
    if args.solver == "3d":
        ball, condition, target, options = inputs_3d(args, allow)
        geometry = Hexahedral(options)
        announce = (f"simulating {ball.name} in 3D at {condition.speed_m_s:g} m/s, "
                    f"{condition.angle_deg:g} deg ...")
    else:
        ball = load_model(args.ball, args.speed_m_s, moduli=args.moduli, allow=allow)
        condition, announce = args.speed_m_s, None
        target = load_checked_target(args, ball)
        geometry = Axisymmetric(solver_options(args))
    result = run_impact(ball, condition, geometry, target=target, allow=allow,
                        start=starter(geometry.options.chunk_steps, announce))
    out = impact_summary(result, ball, target)
    out.update(write_run_files(result, csv=args.csv, table=table,
                               vtk=getattr(args, "vtk", None),
                               animation=getattr(args, "animate", None), plot=args.plot))
    if not args.json:
        (print_3d if args.solver == "3d" else _print_one)(result, out)
    return out


def _print_one(result, out: dict[str, Any]) -> None:
    """One axisymmetric run's text."""
    e = result.energies_j
    on = "" if result.target == "rigid plane" else f" on {result.target}"
    print(f"{result.ball_name} at {result.impact_speed_m_s:g} m/s{on} ({out['moduli']} moduli): "
          f"peak force {result.peak_force_n:.5g} N at {result.time_of_peak_s * 1e3:.4g} ms, "
          f"contact time {result.contact_time_s * 1e3:.4g} ms, COR {result.cor:.4f}")
    print(f"  energy balance error {result.energy_balance_error:.2e}; viscous "
          f"{e['viscous_dissipation_j']:.4g} J, bulk viscous "
          f"{e['bulk_viscous_dissipation_j']:.4g} J of {e['initial_kinetic_energy_j']:.4g} J")
    print(f"  {result.elements} elements, {result.steps} steps of "
          f"{result.stable_time_increment_s:.3g} s, {result.wall_time_s:.2f} s wall")
    print_target(out)


def print_target(out: dict[str, Any]) -> None:
    """A target's and a backing's figures (`fe.runs.impact_summary`), if any."""
    for layer in out.get("target_layers", []):
        print(f"  target layer {layer['name']}: took {layer['work_j']:.4g} J, largest "
              f"compression {layer['max_compression']:.1%} of its thickness")
    b = out.get("backing")
    if b is not None:
        print(f"  backing: {b['backing_speed_m_s']:.3f} m/s after, peak acceleration "
              f"{b['backing_peak_acceleration_g']:.1f} g, HIC15 {b['hic15']:.1f}, Gadd "
              f"{b['gadd_severity_index']:.1f}, peak transmitted force "
              f"{b['peak_transmitted_force_n']:.4g} N")


def _run_sweep(args: argparse.Namespace, speeds: tuple[float, ...]) -> dict[str, Any]:
    """Several speeds of one ball in one batched run (`fe.runs.run_speed_sweep`): a row per
    speed, the table and plot, and the text unless --json."""
    from ..fe.runs import run_speed_sweep, speed_sweep_summary
    from ..plotting import save_and_close

    if args.solver == "3d":
        raise InputError("--speed-m-s: a list of speeds (a sweep) runs with the axisymmetric "
                         "solver only; with --solver 3d give one speed per run")
    if args.csv is not None:
        raise InputError("--csv: writes the histories of one run; a sweep writes a row per "
                         "speed with --table (or give one speed)")
    if args.target is not None:
        raise InputError("--target: a speed sweep runs on the rigid plane; give one speed per "
                         "run on a target")
    check_flags(args)
    allow = check_allow(args.allow)
    options = solver_options(args)
    announce = f"simulating {args.ball} at {len(speeds)} speeds in one batched run ..."
    sweep = run_speed_sweep(args.ball, speeds, options, moduli=args.moduli, label=args.ball,
                            allow=allow, start=starter(options.chunk_steps, announce,
                                                       warn_first=True))
    out = speed_sweep_summary(sweep)
    if args.table is not None:
        out["table"] = write_table(out["sweep"], args.table)
    if args.plot is not None:
        figure = sweep_figure([sweep], title=f"{args.ball}: speed sweep (FE, rigid plane)")
        out["plot"] = str(save_and_close(figure, args.plot))
    if not args.json:
        _print_sweep(out)
    return out


def _print_sweep(out: dict[str, Any]) -> None:
    print(f"{out['ball']}: {len(out['sweep'])} speeds in one batched run ({out['moduli']} moduli, "
          f"{out['elements']} elements, {out['wall_time_s']:.2f} s wall)")
    print(f"{'speed m/s':>10}{'COR':>8}{'peak kN':>9}{'contact ms':>11}{'deflect mm':>11}"
          f"{'rebound m/s':>12}{'stiff MN/m':>11}{'energy err':>11}")
    for r in out["sweep"]:
        print(f"{r['impact_speed_m_s']:>10.4g}{r['cor']:>8.4f}{r['peak_force_n'] / 1e3:>9.3f}"
              f"{r['contact_time_s'] * 1e3:>11.4f}{r['max_deflection_m'] * 1e3:>11.3f}"
              f"{r['rebound_speed_m_s']:>12.3f}{r['dynamic_stiffness_n_m'] / 1e6:>11.4g}"
              f"{r['energy_balance_error']:>11.1e}")
    for key in ("table", "plot"):
        if key in out:
            print(f"{key} written to {out[key]}")
