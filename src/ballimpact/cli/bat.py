"""`ballimpact bat`: a ball on a flexible bat (`bats.ball_on_bat`): the
collision efficiency, batted-ball speed, energy split and bending stress at one impact point,
or along the bat with its sweet spot; docs/equipment.md, "Ball on bat"."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from ..errors import InputError
from .common import add_allow, add_json

#: the hands' positions (m from the knob end) of `--grip`: `bats.Grip`'s
GRIP_POSITIONS_M = (0.05, 0.15)


def add_parser(verbs) -> None:
    bat = verbs.add_parser(
        "bat", help="a ball on a flexible bat: collision efficiency, sweet spot, vibration",
        description="The axisymmetric FE ball on a plane carried by the bat's Timoshenko-beam "
                    "modes at the impact point (--ball-model fe, the default), or a "
                    "Hunt-Crossley contact law fitted to the FE ball's impact on a rigid plane "
                    "at the collision's relative speed (--ball-model law, or given as "
                    "hc:MASS_KG:STIFFNESS:DAMPING_S_M) on those modes (docs/equipment.md, "
                    "'Ball on bat'). The bat's swing is a rigid rotation about --pivot-m if "
                    "given, else a translation.")
    bat.add_argument("--bat", required=True,
                     help="bat preset (baseball-wood-34in, baseball-aluminium-bbcor-34in, "
                          "cricket-willow-sh) or bat file (JSON/TOML)")
    bat.add_argument("--ball", required=True,
                     help="ball preset or file (its law from one FE run), or "
                          "hc:MASS_KG:STIFFNESS:DAMPING_S_M (F = k d^1.5 (1 + 1.5 c d'))")
    add_ball_model(bat)
    bat.add_argument("--speed-m-s", type=float, required=True,
                     help="the ball's speed toward the bat (m/s)")
    bat.add_argument("--impact-m", required=True, metavar="X|START:STOP:STEP",
                     help="impact point from the knob end (m), or a sweep along the bat")
    bat.add_argument("--bat-speed-m-s", type=float, default=0.0,
                     help="the bat's speed toward the ball at the impact point (m/s; default 0)")
    bat.add_argument("--pivot-m", type=float,
                     help="the swing's centre of rotation from the knob end (m); with "
                          "--support pivot the bat is pinned there")
    bat.add_argument("--support", choices=("free", "pivot"), default="free",
                     help="free bat (default) or pinned at --pivot-m")
    bat.add_argument("--grip", metavar="STIFFNESS_N_M:DAMPING_N_S_M",
                     help=f"hands at {GRIP_POSITIONS_M[0]:g} and {GRIP_POSITIONS_M[1]:g} m: a "
                          "spring and dashpot each; prints the force on the hands")
    bat.add_argument("--modes", type=int, default=12,
                     help="bat modes kept, rigid ones included (default 12)")
    add_allow(bat)
    add_json(bat)
    bat.add_argument("--plot", type=Path,
                     help="PNG: the sweet-spot plot (a sweep) or the contact force (one point)")


def add_ball_model(parser: argparse.ArgumentParser, prefix: str = "") -> None:
    """`--ball-model` (`bat`; `standard bbcor`, with `prefix` "bbcor: ")."""
    parser.add_argument("--ball-model", choices=("fe", "law"), default="fe",
                        help=f"{prefix}the FE ball itself on the bat's modes (default) or its "
                             "contact law (faster; hc:... balls are laws)")


def _numbers(text: str, flag: str, count: int) -> list[float]:
    parts = text.split(":")
    if len(parts) != count:
        raise InputError(f"{flag} = {text!r}: expected {count} numbers separated by ':'")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise InputError(f"{flag} = {text!r}: not a number") from None
    if not all(math.isfinite(v) for v in values):
        raise InputError(f"{flag} = {text!r}: not a finite number")
    return values


def impact_points(text: str) -> list[float]:
    """`--impact-m`: one point, or START:STOP:STEP (STOP included), in m from the knob end."""
    if ":" not in text:
        return _numbers(text, "--impact-m", 1)
    start, stop, step = _numbers(text, "--impact-m", 3)
    if stop < start:
        raise InputError(f"--impact-m = {text}: STOP {stop:g} is less than START {start:g}")
    if step <= 0:
        raise InputError(f"--impact-m = {text}: STEP must be > 0 m")
    count = int(math.floor((stop - start) / step + 1e-9)) + 1
    if count > 1000:
        raise InputError(f"--impact-m = {text}: {count} points; at most 1000")
    return [start + i * step for i in range(count)]


def ball_of(text: str):
    """`--ball`: a `HuntCrossleyBall` from hc:MASS_KG:STIFFNESS:DAMPING_S_M, else the text (a
    ball preset or file)."""
    if not text.startswith("hc:"):
        return text
    from ..bats.ball_law import HuntCrossleyBall

    mass, k, c = _numbers(text[3:], "--ball hc:", 3)
    try:
        return HuntCrossleyBall(mass, k, c, name=text)
    except InputError as error:
        raise InputError(f"--ball: {error}") from None


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..bats.study import ball_on_bat

    grip = None if args.grip is None else tuple(_numbers(args.grip, "--grip", 2))
    out = ball_on_bat(args.bat, ball_of(args.ball), args.speed_m_s, impact_points(args.impact_m),
                      bat_speed_m_s=args.bat_speed_m_s, pivot_m=args.pivot_m,
                      support=args.support, grip=grip, modes=args.modes,
                      ball_model=args.ball_model, allow=args.allow, plot=args.plot,
                      progress=True)
    if not args.json:
        _print(out)
    return out


def _print(out: dict) -> None:
    moi = out["bat_moment_of_inertia_kg_m2"]
    freqs = ", ".join(f"{f:.0f}" for f in out["mode_frequencies_hz"])
    print(f"{out['bat']}: {out['bat_mass_kg']:.3f} kg, centre of mass "
          f"{out['bat_centre_of_mass_m']:.3f} m, I knob {moi['knob']:.3f} / CM "
          f"{moi['centre_of_mass']:.4f} kg m^2, {out['support']}; modes {freqs} Hz")
    ball = out["ball"]
    if ball.get("model") == "fe":
        f = ball["fe"]
        print(f"ball {ball['name']} (FE, {f['elements']} elements): {ball['mass_kg']:.4g} kg; on "
              f"a rigid plane at {f['relative_speed_m_s']:g} m/s COR "
              f"{f['rigid_plane_cor']:.4f}, contact {f['rigid_plane_contact_time_s'] * 1e3:.3f} "
              f"ms ({f['rigid_plane_wall_time_s']:.2f} s); on the bat {f['bat_run_steps']} "
              f"steps, {f['modes_in_contact']} modes ({f['bat_run_wall_time_s']:.2f} s)")
    else:
        cal = ball.get("calibration") or {}
        print(f"ball {ball['name']} (law): {ball['mass_kg']:.4g} kg, k "
              f"{ball['stiffness_n_m1_5']:.4g} N/m^1.5, c {ball['damping_s_m']:.4g} s/m"
              + (f" (FE at {cal['speed_m_s']:g} m/s: COR {cal['fe_cor']:.4f}, contact "
                 f"{cal['fe_contact_time_s'] * 1e3:.3f} ms, peak force "
                 f"{cal['fe_peak_force_n']:.4g} N; law: COR {cal['law_cor']:.4f}, peak force "
                 f"{cal['law_peak_force_n']:.4g} N)" if cal else ""))
    speeds = f"ball {out['speed_m_s']:g} m/s, bat {out['bat_speed_m_s']:g} m/s"
    if "points" not in out:  # one point
        print(f"at {out['impact_m']:g} m from the knob ({out['from_barrel_end_m']:.3f} m from the "
              f"barrel end), {speeds}: e_A {out['collision_efficiency']:.4f} (rigid bat "
              f"{out['rigid_collision_efficiency']:.4f}), batted-ball speed "
              f"{out['batted_ball_speed_m_s']:.2f} m/s")
        print(f"  contact {out['contact_duration_s'] * 1e3:.3f} ms, peak force "
              f"{out['peak_force_n']:.4g} N; ball lost {out['ball_energy_lost_j']:.4g} J, bat "
              f"vibration {out['bat_vibration_energy_total_j']:.4g} J, rigid "
              f"{out['bat_rigid_energy_j']:.4g} J (energy balance error "
              f"{out['energy_balance_error']:.1e})")
        print(f"  largest bending stress {out['max_bending_stress_pa'] / 1e6:.4g} MPa at "
              f"{out['max_bending_stress_x_m']:.3f} m from the knob; the surface under the "
              f"ball tilts up to {out['max_contact_rotation_rad']:.3g} rad in contact"
              + (f"; largest force on the hands {max(map(abs, out['hands_force']['force_n'])):.4g}"
                 f" N, speed {max(map(abs, out['hands_force']['velocity_m_s'])):.3g} m/s"
                 if "hands_force" in out else ""))
        return
    print(f"{speeds}\n  x (m)  from end (m)  e_A     BBS (m/s)  vibration (J)  stress (MPa)")
    for p in out["points"]:
        print(f"  {p['impact_m']:.3f}  {p['from_barrel_end_m']:.3f}         "
              f"{p['collision_efficiency']:.4f}  {p['batted_ball_speed_m_s']:9.2f}  "
              f"{p['bat_vibration_energy_total_j']:13.3f}  "
              f"{p['max_bending_stress_pa'] / 1e6:12.1f}")
    s = out["sweet_spot"]
    print(f"sweet spot: largest e_A {s['max_collision_efficiency']:.4f} at "
          f"{s['max_efficiency_m']:.3f} m ({s['max_efficiency_from_barrel_end_m']:.3f} m from "
          f"the barrel end); least vibration at {s['least_vibration_m']:.3f} m "
          f"({s['least_vibration_from_barrel_end_m']:.3f} m from the barrel end)")
