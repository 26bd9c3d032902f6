"""The ball on the bat as `ballimpact bat` runs it (`ball_on_bat`): the inputs checked against
the bat, one collision or a sweep along the bat, its summary and its plot; docs/equipment.md,
"Ball on bat"."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..checks import check_allow, check_integer, check_range
from ..errors import InputError
from ..fileio import check_plot_path
from ..progress import CountProgress, progress_line
from .ball_law import HuntCrossleyBall, ball_law
from .fe_impact import fe_bat_impact
from .impact import DEFAULT_MODES, bat_impact, bat_model
from .modes import Grip
from .spec import load_bat
from .sweep import impact_sweep

#: bat modes allowed, rigid ones included
MODES_RANGE = (2, 200)


def collider(ball, relative_speed_m_s: float, *, ball_model: str = "fe", allow=(),
             announce: bool = False):
    """The ball of a collision with the bat: a `HuntCrossleyBall` as it is; else `ball` (a
    preset name, ball file or dict) as the FE ball loaded for `relative_speed_m_s` (m/s;
    `fe.load_ball`) with `ball_model` "fe", or as its contact law (`ball_law`: one FE run on a
    rigid plane at that speed, announced on stderr with `announce`) with "law". Raises
    `InputError` for a ball that does not load."""
    if isinstance(ball, HuntCrossleyBall):
        return ball
    if ball_model == "fe":
        from ..fe import load_ball

        return load_ball(ball, impact_speed_m_s=relative_speed_m_s, allow=allow)
    if announce:
        progress_line(f"ball law: one FE run of {ball} at {relative_speed_m_s:g} m/s on a rigid "
                      "plane ...")
    return ball_law(ball, relative_speed_m_s, allow=allow)


def _millimetres(x: float, length_m: float) -> str:
    """The hint for a position on the bat typed in mm: beyond ten bat lengths, and on the bat
    read in mm (a position just past the barrel's end is a slip of another kind)."""
    typed_in_mm = 10.0 * length_m < x <= 1000.0 * length_m
    return f"; {x:g} looks like millimetres: use {x / 1000:g}" if typed_in_mm else ""


def ball_on_bat(bat, ball, speed_m_s: float, impact_points_m: Sequence[float], *,
                bat_speed_m_s: float = 0.0, pivot_m: float | None = None,
                support: str = "free", grip: tuple[float, float] | None = None,
                modes: int = DEFAULT_MODES, ball_model: str = "fe", allow=(),
                plot: Path | None = None, progress: bool = False) -> dict[str, Any]:
    """The ball at `speed_m_s` (m/s) on `bat` (anything `load_bat` takes) swung at
    `bat_speed_m_s` (m/s) at the impact point, about `pivot_m` (m from the knob end) if given,
    pinned there with `support` "pivot": at the one point of `impact_points_m` (m from the knob
    end) `bat_impact` / `fe_bat_impact`, at several `impact_sweep` with its sweet spot. `ball`:
    `collider`'s, at the relative speed; `grip`: the hands' (stiffness N/m, damping N s/m) at
    `Grip`'s positions; `modes`: the bat modes kept. `plot`: a PNG written there (the contact
    force, or the sweet-spot plot of a sweep). `progress`: the ball law's FE run and the sweep's
    points reported on stderr.

    Returns the result's `summary()`, with "plot" (the path) when written. Raises `InputError`
    (one line naming the command's flag) for a plot path that is no .png in an existing folder,
    a speed <= 0, a negative bat speed, a point off the
    bat, a pivot beyond it, support "pivot" without a pivot, `modes` outside `MODES_RANGE`, a
    negative grip stiffness or damping, or an unknown `allow` check."""
    check_plot_path(plot)
    allow = check_allow(allow)
    spec = load_bat(bat)
    length = spec.length_m
    check_range("--speed-m-s", speed_m_s, 0.0, low_open=True, unit="m/s")
    check_range("--bat-speed-m-s", bat_speed_m_s, 0.0, unit="m/s")
    for x in impact_points_m:
        if not 0.0 < x <= length:
            raise InputError(f"--impact-m: {x:g} m is off the bat (0, {length:g}] m from the knob "
                             f"end{_millimetres(x, length)}")
    if pivot_m is not None and not 0.0 <= pivot_m <= length:
        raise InputError(f"--pivot-m = {pivot_m:g}: beyond the bat, allowed [0, {length:g}] m "
                         f"from the knob end{_millimetres(pivot_m, length)}")
    if support == "pivot" and pivot_m is None:
        raise InputError("--support pivot: needs --pivot-m")
    modes = check_integer("--modes", modes, *MODES_RANGE)
    if grip is not None:
        check_range("--grip stiffness", grip[0], 0.0, unit="N/m")
        check_range("--grip damping", grip[1], 0.0, unit="N s/m")
    ball = collider(ball, speed_m_s + bat_speed_m_s, ball_model=ball_model, allow=allow,
                    announce=progress)
    bm = bat_model(spec, support=support, pivot_m=pivot_m, modes=modes,
                   grip=None if grip is None else Grip(stiffness_n_m=grip[0],
                                                       damping_n_s_m=grip[1]))
    kw = {"bat_speed_m_s": bat_speed_m_s, "pivot_m": pivot_m}
    if len(impact_points_m) > 1:
        result = impact_sweep(bm, ball, speed_m_s, impact_points_m, allow=allow, **kw,
                              progress=CountProgress("impact point") if progress else None)
    elif isinstance(ball, HuntCrossleyBall):
        result = bat_impact(bm, ball, speed_m_s, impact_points_m[0], **kw)
    else:
        result = fe_bat_impact(bm, ball, speed_m_s, impact_points_m[0], allow=allow, **kw)
    out = result.summary()
    if plot is not None:
        from .plots import save_plot

        out["plot"] = str(save_plot(result, plot))
    return out
