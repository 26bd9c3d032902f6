"""Pictures of the ball-bat collision, drawn on an Axes the caller gives (the conventions of
`ballimpact.plotting`): the sweet spot along the bat and one collision's contact force; and
either as a PNG (`save_plot`)."""

from __future__ import annotations

from pathlib import Path


def plot_sweet_spot(ax, sweep):
    """The collision efficiency e_A (left axis) and the bat's vibration energy (right axis)
    against the impact point's distance from the barrel end (mm), for an `ImpactSweep`; the two
    sweet spots marked. Returns `ax`."""
    d_mm = sweep.from_barrel_end_m * 1e3
    length = sweep.bat_length_m
    line_e, = ax.plot(d_mm, sweep.collision_efficiency, "o-", color="C0", ms=3,
                      label="collision efficiency e_A")
    ax.axvline((length - sweep.max_efficiency_m) * 1e3, color="C0", ls=":", lw=1)
    ax.set_xlabel("impact point from the barrel end (mm)")
    ax.set_ylabel("collision efficiency e_A", color="C0")
    other = ax.twinx()
    line_v, = other.plot(d_mm, sweep.vibration_energy_j, "s-", color="C3", ms=3,
                         label="bat vibration energy")
    other.axvline((length - sweep.least_vibration_m) * 1e3, color="C3", ls=":", lw=1)
    other.set_ylabel("bending-mode energy after the impact (J)", color="C3")
    other.set_ylim(bottom=0.0)
    first = sweep.results[0]
    ax.set_title(f"{first.bat}, ball at {first.speed_m_s:g} m/s")
    ax.legend(handles=[line_e, line_v], loc="lower center", fontsize="small")
    ax.grid(alpha=0.3)
    return ax


def plot_contact_force(ax, result):
    """One collision's contact force against time (ms), with the hands' force if it has one.
    Returns `ax`."""
    ax.plot(result.contact_time_s * 1e3, result.contact_force_n, color="C0",
            label="ball on bat")
    if result.hands_force_n is not None:
        ax.plot(result.history_time_s * 1e3, result.hands_force_n, color="C2",
                label="bat on the hands")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("force (N)")
    ax.set_title(f"{result.bat} at {result.impact_m:g} m from the knob: "
                 f"e_A {result.collision_efficiency:.3f}")
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    return ax


def save_plot(result, path: str | Path) -> Path:
    """`plot_sweet_spot` of an `ImpactSweep`, else `plot_contact_force` of one collision, written
    as a PNG to `path` (7 x 4.5 in). Returns the path written."""
    from ..plotting import save_and_close, subplots
    from .sweep import ImpactSweep

    figure, ax = subplots(figsize=(7, 4.5), layout="constrained")
    (plot_sweet_spot if isinstance(result, ImpactSweep) else plot_contact_force)(ax, result)
    return save_and_close(figure, path)
