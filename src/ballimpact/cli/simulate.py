"""`ballimpact simulate`: an FE impact of a ball model (axisymmetric or 3D), a speed sweep, and
the solver flags other verbs share (`add_solver_options`, `SolverDefaults`)."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any

from ..checks import check_range
from ..errors import InputError
from ..plausibility import check_allow, check_fe_speed
from .common import (
    add_allow,
    check_output_folder,
    check_plot_path,
    use_compilation_cache,
)

class SolverDefaults:
    """FE defaults shown in --help (kept equal to `fe.SolverOptions` by a test)."""

    element_size_m = 1.5e-3
    penalty_scale = 1.0
    integration = "reduced"
    precision = "float64"


def add_parser(verbs) -> None:
    simulate = verbs.add_parser(
        "simulate", help="FE impact of a ball on a flat surface (normal: axisymmetric; oblique, "
                         "spin, targets: 3d)",
        description="Explicit FE (hyper-viscoelastic layers, penalty contact) of a ball hitting a "
                    "flat surface: contact force history, COR, contact time, energies and the 19 "
                    "features. --solver axisymmetric (default) runs normal impacts on a rigid "
                    "plane; --solver 3d runs oblique impacts with Coulomb friction and spin, on a "
                    "rigid plane or a deformable slab (--target), and adds normal_cor, "
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
    three = simulate.add_argument_group("3d solver")
    three.add_argument("--spin-x-rad-s", type=float, default=0.0,
                       help="out-of-plane spin about the incoming tangential velocity (rad/s, "
                            "right-handed; needs the full model, chosen automatically)")
    three.add_argument("--spin-z-rad-s", type=float, default=0.0,
                       help="out-of-plane spin about the surface normal (rad/s, right-handed)")
    three.add_argument("--target", type=Path,
                       help="deformable slab specification (JSON; default: a rigid plane)")
    three.add_argument("--divisions", type=int,
                       help="hexahedra along each 90 degrees of arc (even, 4 to 64; default 16)")
    three.add_argument("--pole-grading", type=float,
                       help="arc spacing at the equator over that at the contact pole "
                            "(1 to 40; default 2)")
    three.add_argument("--contact-elements", type=float,
                       help="grade the mesh so that this many elements span the Hertz contact "
                            "radius expected at the (slowest) normal speed; sets the pole "
                            "grading (0.5 to 50; docs/oblique.md, 'Gripping regime')")
    three.add_argument("--full-model", action="store_true",
                       help="mesh the whole ball (default: the half on the plane of incidence "
                            "unless there is out-of-plane spin)")
    three.add_argument("--stick-scale", type=float,
                       help="friction stick-spring stiffness over the normal penalty (default 8)")
    three.add_argument("--slab-depth-growth", type=float,
                       help="match a --target slab's cells to the contact: the ball's pole "
                            "spacing at the centre of its surface, growing in plane as the ball's "
                            "cells do and by this a cell through the depth (over 1, up to 2; "
                            "default: uniform depth cells of 4 pole spacings)")
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
    simulate.add_argument("--json", action="store_true", help="print one JSON object")
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
    parser.add_argument("--penalty-scale", type=float, default=SolverDefaults.penalty_scale,
                        help="contact penalty scale (default 1)")


def speed_list(text: str) -> float | tuple[float, ...]:
    """argparse type of `--speed-m-s`: one impact speed (m/s; a float, as the flag was before the
    sweeps) or a comma-separated list of several (a tuple), each a finite number, none empty or
    given twice (`sweep.parse_speeds`)."""
    from ..sweep import parse_speeds

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
        from .common import finite_float

        return finite_float(text)
    from .angle_sweep import parse_angles

    try:
        return parse_angles(text)
    except InputError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def given_speeds(args: argparse.Namespace) -> tuple[float, ...]:
    """The `--speed-m-s` values (m/s), ascending: one number, or a tuple from `speed_list`."""
    speeds = args.speed_m_s
    return tuple(sorted(speeds)) if isinstance(speeds, (tuple, list)) else (float(speeds),)


def check_sweep_speeds(speeds, allow: frozenset[str]) -> None:
    """Each speed of a sweep (m/s) against the FE speed range before anything is loaded (a
    non-positive speed is left to `load_ball`, which names the field)."""
    for speed in speeds:
        if math.isfinite(speed) and speed > 0:
            check_fe_speed(speed, allow)


def solver_options(args: argparse.Namespace):
    from ..fe import SolverOptions

    size = SolverDefaults.element_size_m if args.element_size_m is None else args.element_size_m
    return SolverOptions(element_size_m=size,
                         pole_element_size_m=args.pole_element_size_m,
                         penalty_scale=args.penalty_scale, integration=args.integration,
                         precision=args.precision)


def _checked_allow(args: argparse.Namespace) -> frozenset[str]:
    """The --allow names, checked, and the impact speed against the FE speed range (before
    anything is loaded, meshed or compiled; a non-positive speed is left to `load_ball`)."""
    allow = check_allow(args.allow)
    if math.isfinite(args.speed_m_s) and args.speed_m_s > 0:
        check_fe_speed(args.speed_m_s, allow, solver=args.solver)
    return allow


def _warn_now(message: str | None) -> None:
    """A warning about the run to come, on stderr at once (it is also in the end's list)."""
    if message is not None:
        print(f"warning: {message}", file=sys.stderr, flush=True)


#: flags of one solver only: flag -> attribute
_FLAGS_3D = {"--angle-deg": "angle_deg", "--spin-rad-s": "spin_rad_s",
             "--spin-x-rad-s": "spin_x_rad_s", "--spin-z-rad-s": "spin_z_rad_s",
             "--target": "target", "--vtk": "vtk", "--animate": "animate",
             "--divisions": "divisions", "--pole-grading": "pole_grading",
             "--contact-elements": "contact_elements",
             "--full-model": "full_model", "--stick-scale": "stick_scale",
             "--slab-depth-growth": "slab_depth_growth"}
_FLAGS_AXISYMMETRIC = {"--element-size-m": "element_size_m",
                       "--pole-element-size-m": "pole_element_size_m"}


def _refuse_other_solver_flags(args: argparse.Namespace) -> None:
    """A flag of the other solver would be ignored silently: refuse it, naming the solver."""
    if args.solver == "3d":
        for flag, name in _FLAGS_AXISYMMETRIC.items():
            if getattr(args, name) is not None:
                raise InputError(f"{flag}: sets the axisymmetric mesh; the 3d solver's mesh is "
                                 "set by --divisions and --pole-grading")
        return
    for flag, name in _FLAGS_3D.items():
        if getattr(args, name) not in (None, 0.0, False):
            raise InputError(f"{flag}: oblique and spinning impacts, targets, 3D output and the "
                             "3D mesh need --solver 3d")


def run_simulate(args: argparse.Namespace) -> dict[str, Any]:
    if isinstance(args.angle_deg, (tuple, list)):
        if len(args.angle_deg) > 1:  # several angles: one batched 3D run
            from .angle_sweep import run_angle_sweep

            return run_angle_sweep(args)
        # a caller's namespace holding [angle]: the run of one impact
        args = argparse.Namespace(**{**vars(args), "angle_deg": float(args.angle_deg[0])})
    speeds = given_speeds(args)
    if len(speeds) > 1:
        return _run_sweep(args, speeds)
    if isinstance(args.speed_m_s, (tuple, list)):  # a caller's namespace holding [v]
        args = argparse.Namespace(**{**vars(args), "speed_m_s": speeds[0]})
    return _run_one(args)  # one speed: the run of one impact, as before the sweeps


def _run_one(args: argparse.Namespace) -> dict[str, Any]:
    from ..fe import RunProgress, estimate, load_ball, simulate
    from ..features import extract_features

    # every check on the input before anything is printed (progress, warnings) or meshed
    check_output_folder(args.csv, "--csv")
    if args.solver == "3d" and getattr(args, "table", None) is not None:
        raise InputError("--table: the sweep table of the axisymmetric solver; a 3d run's "
                         "figures are in --json")
    _check_flags(args)
    allow = _checked_allow(args)
    if args.solver == "3d":
        return _run_simulate_3d(args, allow)
    ball = load_ball(args.ball, impact_speed_m_s=args.speed_m_s, allow=allow)
    if args.moduli is not None:
        ball = ball.with_moduli(args.moduli)
    options = solver_options(args)
    cost = estimate(ball, args.speed_m_s, options, allow=allow)  # refused before meshing
    use_compilation_cache()
    _warn_now(cost.warning())
    result = simulate(ball, args.speed_m_s, options, allow=allow,
                      progress=RunProgress(cost.end_time_s, options.chunk_steps))
    out = result.summary()
    out["features"] = extract_features(result.record()).to_dict()["features"]
    out["materials"] = ball.to_dict()
    out["material_constants_used"] = [  # instantaneous, as the solver uses them (SI)
        {"layer": layer.name, "model": layer.material.model,
         **{k: (v.tolist() if hasattr(v, "tolist") else v)
            for k, v in layer.material.constants().items()}} for layer in ball.layers]
    if args.csv is not None:
        out["csv"] = _write_history(args.csv, result.history)
    if getattr(args, "table", None) is not None:
        from ..sweep import write_table

        out["table"] = write_table([_sweep_json_row(result)], args.table)
    if args.plot is not None:
        from ..plotting import plot_fe

        plot_fe([result], args.plot)
        out["plot"] = str(args.plot)
    if not args.json:
        print(f"{result.ball_name} at {args.speed_m_s:g} m/s ({out['moduli']} moduli): "
              f"peak force {result.peak_force_n:.5g} N at {result.time_of_peak_s * 1e3:.4g} ms, "
              f"contact time {result.contact_time_s * 1e3:.4g} ms, COR {result.cor:.4f}")
        e = result.energies_j
        print(f"  energy balance error {result.energy_balance_error:.2e}; viscous "
              f"{e['viscous_dissipation_j']:.4g} J, bulk viscous "
              f"{e['bulk_viscous_dissipation_j']:.4g} J of {e['initial_kinetic_energy_j']:.4g} J")
        print(f"  {result.elements} elements, {result.steps} steps of "
              f"{result.stable_time_increment_s:.3g} s, {result.wall_time_s:.2f} s wall")
    return out


def _check_flags(args: argparse.Namespace) -> None:
    """The checks one run and a sweep share: output paths, friction, the other solver's flags."""
    check_plot_path(args.plot)
    check_output_folder(getattr(args, "table", None), "--table")
    check_range("--friction", args.friction, 0.0)
    _refuse_other_solver_flags(args)


def _run_sweep(args: argparse.Namespace, speeds: tuple[float, ...]) -> dict[str, Any]:
    """Several speeds of one ball in one batched run (`sweep.run_sweep`): a row per speed."""
    import numpy as np

    from ..fe import RunProgress, estimate
    from ..fe.engine import default_group_size
    from ..plotting import save_and_close
    from ..sweep import run_sweep, sweep_balls, sweep_figure, write_table

    if args.solver == "3d":
        raise InputError("--speed-m-s: a list of speeds (a sweep) runs with the axisymmetric "
                         "solver only; with --solver 3d give one speed per run")
    if args.csv is not None:
        raise InputError("--csv: writes the histories of one run; a sweep writes a row per "
                         "speed with --table (or give one speed)")
    _check_flags(args)
    allow = check_allow(args.allow)
    check_sweep_speeds(speeds, allow)
    balls = sweep_balls(args.ball, speeds, moduli=args.moduli, allow=allow)
    options = solver_options(args)
    # refused before meshing; estimated with the ball of the slowest speed (the longest run)
    cost = estimate(balls[int(np.argmin(speeds))], speeds, options, allow=allow)
    use_compilation_cache()
    _warn_now(cost.warning())
    print(f"simulating {args.ball} at {len(speeds)} speeds in one batched run ...",
          file=sys.stderr, flush=True)
    # progress lines follow one vmapped group; a sweep of several groups runs without them
    one_group = len(speeds) <= default_group_size(len(speeds))
    sweep = run_sweep(balls, speeds, options, label=args.ball, allow=allow,
                      progress=RunProgress(cost.end_time_s, options.chunk_steps)
                      if one_group else None)
    rows = [_sweep_json_row(r) for r in sweep.results]
    first = sweep.results[0].summary()
    out = {"ball": args.ball, "speeds_m_s": list(speeds), "sweep": rows,
           "moduli": first["moduli"], "elements": first["elements"],
           "integration": first["integration"], "precision": first["precision"],
           "wall_time_s": sweep.wall_time_s, "materials": [b.to_dict() for b in balls]}
    if args.table is not None:
        out["table"] = write_table(rows, args.table)
    if args.plot is not None:
        figure = sweep_figure([sweep], title=f"{args.ball}: speed sweep (FE, rigid plane)")
        out["plot"] = str(save_and_close(figure, args.plot))
    if not args.json:
        _print_sweep(args.ball, out)
    return out


def _sweep_json_row(result) -> dict[str, Any]:
    """A sweep's row (`sweep.sweep_row`) with the run's ball name, energy error and steps."""
    from ..sweep import sweep_row

    return {**sweep_row(result), "energy_balance_error": result.energy_balance_error,
            "steps": result.steps, "ball_name": result.ball_name}


def _print_sweep(label: str, out: dict[str, Any]) -> None:
    print(f"{label}: {len(out['sweep'])} speeds in one batched run ({out['moduli']} moduli, "
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


def _write_history(path: Path, history: dict) -> str:
    """The histories as CSV, one row per step, SI unit suffixes in the header
    (`fileio.write_table`)."""
    from ..fileio import column_rows, write_table

    names = list(history)
    return write_table(path, names, column_rows(*(history[n] for n in names)))


#: frames kept for --vtk / --animate (about this many over a run)
ANIMATION_FRAMES = 40


def _run_simulate_3d(args: argparse.Namespace, allow: frozenset[str]) -> dict[str, Any]:
    ball, condition, target, options = _checked_3d(args, allow)
    result = _simulate_3d(ball, condition, target, options, allow)
    return _output_3d(args, result, ball, condition, target)


def _checked_3d(args: argparse.Namespace, allow: frozenset[str]) -> tuple:
    """The 3D run's inputs, checked before anything is meshed: (ball, condition, target or None,
    `Options3D`). `run_simulate` has checked --plot, --csv and --friction."""
    from ..fe import ImpactCondition, Options3D, load_ball
    from ..fe.hex.target import check_target_width, load_target
    from ..oblique.output import check_animation_path

    check_output_folder(args.vtk, "--vtk")
    if args.vtk is not None and args.vtk.suffix.lower() not in (".pvd", ".xdmf"):
        raise InputError(f"--vtk {args.vtk}: the file must end in .pvd or .xdmf")
    check_output_folder(args.animate, "--animate")
    if args.animate is not None:
        check_animation_path(args.animate)
    condition = ImpactCondition(speed_m_s=args.speed_m_s, angle_deg=args.angle_deg,
                                spin_rad_s=args.spin_rad_s, friction=args.friction,
                                spin_x_rad_s=args.spin_x_rad_s, spin_z_rad_s=args.spin_z_rad_s)
    target = load_target(args.target) if args.target is not None else None
    ball = load_ball(args.ball, impact_speed_m_s=args.speed_m_s, allow=allow)
    if args.moduli is not None:
        ball = ball.with_moduli(args.moduli)
    if target is not None:
        try:
            check_target_width(target, ball)
        except InputError as error:
            raise InputError(f"--target {args.target}: {error}") from None
    if args.slab_depth_growth is not None and args.target is None:
        raise InputError("--slab-depth-growth: grades a target slab's cells; give --target FILE")
    want_frames = args.vtk is not None or args.animate is not None
    defaults = Options3D()
    options = Options3D(
        divisions=defaults.divisions if args.divisions is None else args.divisions,
        pole_grading=defaults.pole_grading if args.pole_grading is None else args.pole_grading,
        contact_elements=args.contact_elements, half=False if args.full_model else None, integration=args.integration,
        penalty_scale=args.penalty_scale,
        stick_scale=defaults.stick_scale if args.stick_scale is None else args.stick_scale,
        slab_depth_growth=args.slab_depth_growth, precision=args.precision, chunk_steps=50 if want_frames else 200,
        frames=1 if want_frames else 0)
    return ball, condition, target, options


def _simulate_3d(ball, condition, target, options, allow: frozenset[str]):
    """The 3D run, with its estimate's warnings first and progress lines; the frames thinned to
    about `ANIMATION_FRAMES` when they are kept for output (`options.frames`)."""
    import numpy as np

    from ..fe import Hexahedral, RunProgress, estimate, simulate

    # refused before meshing; the mesh is then built and cached for the run
    geometry = Hexahedral(options)
    cost = estimate(ball, condition, geometry=geometry, target=target, allow=allow)
    use_compilation_cache()
    print(f"simulating {ball.name} in 3D at {condition.speed_m_s:g} m/s, "
          f"{condition.angle_deg:g} deg ...", file=sys.stderr, flush=True)
    _warn_now(cost.warning())
    result = simulate(ball, condition, geometry=geometry, target=target, allow=allow,
                      progress=RunProgress(cost.end_time_s, options.chunk_steps))
    if options.frames and len(result.frames) > ANIMATION_FRAMES:
        keep = np.unique(np.linspace(0, len(result.frames) - 1, ANIMATION_FRAMES).astype(int))
        result.frames[:] = [result.frames[i] for i in keep]
    return result


def _output_3d(args: argparse.Namespace, result, ball, condition, target) -> dict[str, Any]:
    """The 3D run's summary, the files asked for, and the text lines unless --json."""
    from ..features import extract_features
    from ..oblique.output import animate_section, write_series
    from ..oblique.plots import plot_oblique

    out = result.summary()
    out["features"] = extract_features(result.record()).to_dict()["features"]
    out["materials"] = ball.to_dict()
    if target is not None:
        out["target_specification"] = target.to_dict()
    if args.csv is not None:
        out["csv"] = _write_history(args.csv, result.history)
    if args.vtk is not None:
        out["vtk"] = str(write_series(result, args.vtk))
    if args.animate is not None:
        out["animation"] = str(animate_section(result, args.animate))
    if args.plot is not None:
        plot_oblique([result], args.plot)
        out["plot"] = str(args.plot)
    if not args.json:
        _print_3d(result, condition, out)
    return out


def _print_3d(result, condition, out: dict[str, Any]) -> None:
    spin = (f"spin {condition.spin_rad_s:g} rad/s" if condition.symmetric else
            f"spin (x, y, z) {', '.join(f'{w:g}' for w in condition.spin_vector_rad_s)} rad/s")
    print(f"{result.ball_name} in 3D at {condition.speed_m_s:g} m/s, "
          f"{condition.angle_deg:g} deg, {spin}, friction {condition.friction:g} on "
          f"{result.target}:")
    print(f"  normal COR {result.normal_cor:.4f}, tangential COR {result.tangential_cor:.4f}, "
          f"rebound angle {result.rebound_angle_deg:.2f} deg, rebound spin "
          f"{result.rebound_spin_rad_s:.1f} rad/s, rebound speed "
          f"{result.rebound_speed_m_s:.3f} m/s")
    if not condition.symmetric:
        print("  rebound spin (x, y, z) "
              f"{', '.join(f'{w:.1f}' for w in out['rebound_spin_vector_rad_s'])} rad/s, "
              "velocity (x, y, z) "
              f"{', '.join(f'{v:.3f}' for v in out['rebound_velocity_m_s'])} m/s")
    print(f"  peak normal force {result.peak_force_n:.5g} N, contact time "
          f"{result.contact_time_s * 1e3:.4g} ms")
    e = result.energies_j
    print(f"  energy balance error {result.energy_balance_error:.2e}; viscous "
          f"{e['viscous_dissipation_j']:.4g} J, friction {e['frictional_dissipation_j']:.4g} J,"
          f" bulk viscous {e['bulk_viscous_dissipation_j']:.4g} J of "
          f"{e['initial_kinetic_energy_j']:.4g} J")
    print(f"  {result.elements} hexahedra ({'half' if result.half_model else 'full'} model), "
          f"{result.steps} steps of {result.stable_time_increment_s:.3g} s, "
          f"{result.wall_time_s:.2f} s wall")
