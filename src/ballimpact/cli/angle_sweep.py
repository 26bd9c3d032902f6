"""`ballimpact simulate --solver 3d --angle-deg 5,10,20,30,45,60`: an angle sweep of the 3D solver.

The sweep is `oblique.sweep.angle_sweep` (one vmapped 3D batch, a row per angle in Maw, Barber &
Fawcett's normalised axes, the elastic-sphere reference where it applies); here the flags are
checked, the sweep run, and its table, plot and text written.
"""

from __future__ import annotations

import argparse
from typing import Any

from ..checks import allowed_range, check_range
from ..errors import InputError
from ..fe.sweep import write_table
from .simulate_3d import check_flags, checked_allow, inputs_3d, starter

#: the angles a sweep accepts (deg from the normal; `ImpactCondition.angle_deg`'s range)
ANGLE_RANGE_DEG = (0.0, 89.0)
_RANGE = f"allowed range {allowed_range(*ANGLE_RANGE_DEG, unit='deg')}"


def parse_angles(text: str) -> tuple[float, ...]:
    """Angles from the surface normal (deg) from a comma-separated list ("5,10,20"): each item a
    number in `ANGLE_RANGE_DEG` (`checks.check_range`), none empty, none given twice (a repeated
    angle would look like two points). Their order is kept. Raises `InputError` naming the item
    and the allowed range."""
    items = text.split(",")
    angles: list[float] = []
    for k, item in enumerate(items, 1):
        where = f"item {k} of {text!r}"
        if not item.strip():
            raise InputError(f"{where}: empty; give angles separated by commas, e.g. 5,10,20 "
                             f"({_RANGE})")
        try:
            value = float(item)
        except ValueError:
            raise InputError(f"{where}: {item.strip()!r} is not a number ({_RANGE})") from None
        check_range(f"{where}: angle_deg", value, *ANGLE_RANGE_DEG, unit="deg")
        if value in angles:
            raise InputError(f"{where}: {value:g} deg is given twice; give each angle once "
                             f"({_RANGE})")
        angles.append(value)
    return tuple(angles)


def _checked_sweep(args: argparse.Namespace) -> tuple[argparse.Namespace, tuple[float, ...]]:
    """The checks only a sweep has, before the shared ones: the solver, one speed, no per-run
    output. Returns the namespace with one speed (a float) and the angles, ascending."""
    angles = tuple(sorted(float(a) for a in args.angle_deg))
    if args.solver != "3d":
        raise InputError("--angle-deg: a sweep of angles needs --solver 3d")
    speed = args.speed_m_s
    if isinstance(speed, (tuple, list)):
        if len(speed) > 1:
            raise InputError("--speed-m-s: an angle sweep runs at one speed; give one speed with "
                             "a list of --angle-deg (or one angle with a list of speeds)")
        speed = float(speed[0])
    for flag, name, what in (("--vtk", "vtk", "the time series of one run"),
                             ("--animate", "animate", "the animation of one run"),
                             ("--csv", "csv", "the histories of one run")):
        if getattr(args, name, None) is not None:
            raise InputError(f"{flag}: writes {what}; an angle sweep writes a row per angle "
                             "with --table (or give one angle)")
    return argparse.Namespace(**{**vars(args), "speed_m_s": speed}), angles


def run_angle_sweep(args: argparse.Namespace) -> dict[str, Any]:
    """Several `--angle-deg` of one ball at one speed in one batched 3D run
    (`oblique.sweep.angle_sweep`): a row per angle, a table, a plot in Maw et al.'s normalised
    axes and, where it applies, the elastic reference."""
    from ..fe import Hexahedral
    from ..oblique.sweep import angle_sweep, angle_sweep_summary, plot_angle_sweep

    # every check on the input before anything is printed (progress, warnings) or meshed
    args, angles = _checked_sweep(args)
    check_flags(args)
    allow = checked_allow(args)
    ball, first, target, options = inputs_3d(
        argparse.Namespace(**{**vars(args), "angle_deg": angles[0]}), allow)
    if args.plot is not None and first.friction <= 0.0:
        raise InputError("--plot: the normalised axes of an angle sweep divide by the friction; "
                         "give --friction > 0")
    announce = (f"simulating {ball.name} in 3D at {first.speed_m_s:g} m/s, {len(angles)} angles "
                f"({', '.join(f'{a:g}' for a in angles)} deg) in one batched run ...")
    sweep = angle_sweep(ball, first, angles, geometry=Hexahedral(options), target=target,
                        allow=allow, start=starter(options.chunk_steps, announce))
    out = angle_sweep_summary(sweep, ball)
    if args.table is not None:
        out["table"] = write_table(sweep.rows, args.table)
    if args.plot is not None:
        out["plot"] = plot_angle_sweep(sweep, args.plot, ball)
    if not args.json:
        _print_angle_sweep(out)
    return out


def _print_angle_sweep(out: dict[str, Any]) -> None:
    print(f"{out['ball']} in 3D at {out['speed_m_s']:g} m/s, friction {out['friction']:g}, spin "
          f"{out['spin_rad_s']:g} rad/s on {out['target']}: {len(out['runs'])} angles in one "
          "batched run")
    print(f"{'angle deg':>10}{'Psi':>8}{'normal COR':>11}{'tang COR':>9}{'cp COR':>8}"
          f"{'rebound deg':>12}{'spin rad/s':>11}{'norm spin':>10}")
    for r in out["runs"]:
        print(f"{r['angle_deg']:>10.4g}{r['psi']:>8.3f}{r['normal_cor']:>11.4f}"
              f"{r['tangential_cor']:>9.4f}{r['contact_point_tangential_cor']:>8.4f}"
              f"{r['rebound_angle_deg']:>12.2f}{r['rebound_spin_rad_s']:>11.1f}"
              f"{r['normalised_spin']:>10.3f}")
    steps = [r["steps"] for r in out["runs"]]
    print(f"  {out['wall_time_s']:.2f} s wall for the batch, {out['elements']} hexahedra "
          f"({'half' if out['half_model'] else 'full'} model, pole grading "
          f"{out['pole_grading']:.3g}, penalty scale {out['penalty_scale']:g}), "
          f"{min(steps)}-{max(steps)} steps")
    print(f"  {out['reference_note']}")
    for key in ("table", "plot"):
        if out.get(key) is not None:
            print(f"{key} written to {out[key]}")
