"""`ballimpact bat`: a ball on a flexible bat (`bats.ball_on_bat`): the
collision efficiency, batted-ball speed, energy split and bending stress at one impact point,
or along the bat with its sweet spot; docs/equipment.md, "Ball on bat"."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from ..errors import InputError
from .common import add_allow, add_json, print_lines

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
    from ..bats.text import ball_on_bat_lines

    grip = None if args.grip is None else tuple(_numbers(args.grip, "--grip", 2))
    out = ball_on_bat(args.bat, ball_of(args.ball), args.speed_m_s, impact_points(args.impact_m),
                      bat_speed_m_s=args.bat_speed_m_s, pivot_m=args.pivot_m,
                      support=args.support, grip=grip, modes=args.modes,
                      ball_model=args.ball_model, allow=args.allow, plot=args.plot,
                      progress=True)
    if not args.json:
        print_lines(ball_on_bat_lines(out))
    return out
