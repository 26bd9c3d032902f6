"""The 3D solver's side of `ballimpact simulate` (its inputs and text), and the checks and the
start hook that every `simulate` run shares (one impact, a speed sweep, an angle sweep); here so
that `simulate` and `angle_sweep` both import them without importing each other."""

from __future__ import annotations

import argparse
import math
import sys
from typing import Any

from ..checks import check_range
from ..errors import InputError
from ..checks import check_allow
from ..fe.speed_range import check_fe_speed
from .common import check_output_folder, check_plot_path, use_compilation_cache

#: flags of one solver only (attribute: the flag's name in snake case)
FLAGS_3D = ("--angle-deg", "--spin-rad-s", "--spin-x-rad-s", "--spin-z-rad-s", "--vtk", "--animate", "--divisions", "--pole-grading", "--contact-elements",
            "--full-model", "--stick-scale", "--slab-depth-growth", "--slab-depth-cell-m")
FLAGS_AXISYMMETRIC = ("--element-size-m", "--pole-element-size-m")


def _given(args: argparse.Namespace, flag: str):
    return getattr(args, flag[2:].replace("-", "_"))


def check_flags(args: argparse.Namespace) -> None:
    """The checks every run shares: output paths, friction, and no flag of the other solver
    (it would be ignored silently: refused, naming the solver)."""
    check_plot_path(args.plot)
    check_output_folder(getattr(args, "table", None), "--table")
    check_range("--friction", args.friction, 0.0)
    if args.solver == "3d":
        for flag in FLAGS_AXISYMMETRIC:
            if _given(args, flag) is not None:
                raise InputError(f"{flag}: sets the axisymmetric mesh; the 3d solver's mesh is "
                                 "set by --divisions and --pole-grading")
        return
    for flag in FLAGS_3D:
        if _given(args, flag) not in (None, 0.0, False):
            raise InputError(f"{flag}: oblique and spinning impacts, 3D output and the 3D mesh "
                             "need --solver 3d")


def checked_allow(args: argparse.Namespace) -> frozenset[str]:
    """The --allow names, checked, and the impact speed against the FE speed range (before
    anything is loaded, meshed or compiled; a non-positive speed is left to `load_ball`)."""
    allow = check_allow(args.allow)
    if math.isfinite(args.speed_m_s) and args.speed_m_s > 0:
        check_fe_speed(args.speed_m_s, allow, solver=args.solver)
    return allow


def starter(chunk_steps: int, announce: str | None = None, *, warn_first: bool = False):
    """The `start` hook of the library's runs (`fe.runs.Start`): JAX's compilation cache, then
    `announce` and the estimate's warning on stderr at once (the warning is also in the end's
    list; `warn_first`: in the other order), and the run's progress lines on stderr."""
    def start(cost):
        from ..fe import RunProgress

        use_compilation_cache()
        warning = cost.warning()
        lines = [announce, None if warning is None else f"warning: {warning}"]
        for line in lines[::-1] if warn_first else lines:
            if line is not None:
                print(line, file=sys.stderr, flush=True)
        return RunProgress(cost.end_time_s, chunk_steps)
    return start


def load_checked_target(args: argparse.Namespace, ball):
    """--target: a preset or file (`fe.hex.target.load_target`), at least the ball's width, or
    None."""
    from ..fe.hex.target import check_target_width, load_target

    if args.target is None:
        return None
    target = load_target(args.target)
    try:
        check_target_width(target, ball)
    except InputError as error:
        raise InputError(f"--target {args.target}: {error}") from None
    return target


def inputs_3d(args: argparse.Namespace, allow: frozenset[str]) -> tuple:
    """The 3D run's inputs, checked before anything is meshed: (ball, `ImpactCondition`, target
    or None, `Options3D`). `check_flags` has checked --plot, --table and --friction."""
    from ..fe import ImpactCondition, Options3D
    from ..fe.runs import load_model
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
    ball = load_model(args.ball, args.speed_m_s, moduli=args.moduli, allow=allow)
    target = load_checked_target(args, ball)
    for flag in ("--slab-depth-growth", "--slab-depth-cell-m"):
        if getattr(args, flag[2:].replace("-", "_")) is not None and args.target is None:
            raise InputError(f"{flag}: sets a target slab's cells; give --target FILE")
    frames = args.vtk is not None or args.animate is not None
    given = {"divisions": args.divisions, "pole_grading": args.pole_grading,
             "stick_scale": args.stick_scale}  # None: Options3D's default
    options = Options3D(**{k: v for k, v in given.items() if v is not None},
                        contact_elements=args.contact_elements,
                        half=False if args.full_model else None, integration=args.integration,
                        penalty_scale=args.penalty_scale,
                        slab_depth_growth=args.slab_depth_growth,
                        slab_depth_cell_m=args.slab_depth_cell_m, precision=args.precision,
                        chunk_steps=50 if frames else 200, frames=1 if frames else 0)
    return ball, condition, target, options


def print_3d(result, out: dict[str, Any]) -> None:
    """One 3D run's text."""
    condition, e = result.condition, result.energies_j
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
    print(f"  energy balance error {result.energy_balance_error:.2e}; viscous "
          f"{e['viscous_dissipation_j']:.4g} J, friction {e['frictional_dissipation_j']:.4g} J,"
          f" bulk viscous {e['bulk_viscous_dissipation_j']:.4g} J of "
          f"{e['initial_kinetic_energy_j']:.4g} J")
    print(f"  {result.elements} hexahedra ({'half' if result.half_model else 'full'} model, "
          f"pole grading {result.pole_grading:.3g}, {result.pole_spacing_m * 1e3:.3g} mm at the "
          f"pole, penalty scale {result.penalty_scale:g}),\n  "
          f"{result.steps} steps of {result.stable_time_increment_s:.3g} s, "
          f"{result.wall_time_s:.2f} s wall")
