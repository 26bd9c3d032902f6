"""Pictures of the universal model: held-out predictions against truth with their intervals, and
identified balls' FE pulses over the tests.

Each panel is a `draw_*(ax, ...)` function on a matplotlib Axes the caller gives (returned); the
`plot_*` functions write a file of them. Nothing here chooses a backend."""

from __future__ import annotations

from pathlib import Path

from ..comparison import features_pulse
from ..plotting import save_and_close, subplots
from .model import TARGETS

_SCALE = {"c10_pa": (1e-6, "MPa"), "c01_pa": (1e-6, "MPa"), "g1": (1.0, ""),
          "tau1_s": (1e6, "us"), "mu0_pa": (1e-6, "MPa")}


def draw_held_out(ax, model, name: str):
    """Inverse target `name` (one of `TARGETS`) of the held-out runs on `ax`: the estimate (with
    its 90% interval) against the true value, the coverage in the title. Returns `ax`."""
    held = model.held_out
    j = TARGETS.index(name)
    scale, unit = _SCALE[name]
    t, e = held["truth"][:, j] * scale, held["estimate"][:, j] * scale
    lo, hi = held["low"][:, j] * scale, held["high"][:, j] * scale
    inside = (lo <= t) & (t <= hi)
    ax.errorbar(t, e, yerr=[e - lo, hi - e], fmt="none", ecolor="0.8", lw=0.8)
    ax.scatter(t[inside], e[inside], s=8, label="truth inside 90% interval")
    ax.scatter(t[~inside], e[~inside], s=8, color="C3", label="outside")
    span = [min(t.min(), e.min()), max(t.max(), e.max())]
    ax.plot(span, span, "k--", lw=0.8)
    ax.set_xlabel(f"true {name} ({unit})" if unit else f"true {name}")
    ax.set_ylabel("identified")
    ax.set_title(f"{name}: coverage {inside.mean():.0%}")
    return ax


def plot_held_out(model, path: str | Path) -> Path:
    """Write `draw_held_out` of each inverse target side by side (one legend)."""
    figure, axes = subplots(1, len(TARGETS), figsize=(4 * len(TARGETS), 4))
    for ax, name in zip(axes, TARGETS):
        draw_held_out(ax, model, name)
    axes[0].legend(fontsize=7)
    return save_and_close(figure, path, f"universal model: {len(model.held_out['truth'])} "
                                        "held-out runs (never seen in training)")


def draw_identification(ax, results):
    """Force-time of each test and of its identified ball's FE run (when verified) on `ax`, a
    colour per test; `results` holds (name, processed test, identification). Returns `ax`."""
    for k, (name, processed, found) in enumerate(results):
        t, f = features_pulse(processed.features)
        ax.plot(t * 1e3, f / 1e3, color=f"C{k}", lw=1.5, label=f"{name} (test)")
        if found.simulated is not None:
            h = found.simulated.history
            nrmse = found.verification["force_nrmse"]
            ax.plot(h["time_s"] * 1e3, h["contact_force_n"] / 1e3, "--", color=f"C{k}",
                    label=f"identified universal ball (FE), NRMSE {nrmse:.1%}")
    ax.set_xlabel("time from first contact (ms)")
    ax.set_ylabel("force (kN)")
    ax.set_xlim(left=-0.02)
    ax.legend(fontsize=8)
    return ax


def plot_identification(results, path: str | Path) -> Path:
    """Write `draw_identification` as a PNG."""
    figure, ax = subplots(figsize=(7, 4.5))
    draw_identification(ax, results)
    return save_and_close(figure, path, "identify: test and identified universal FE ball")


def draw_layered(ax, name: str, layered, universal, verification: dict):
    """A layered ball's FE pulse (`layered`, named `name`) and that of the universal ball
    identified from it on `ax` (ms, kN), the force NRMSE of `verification` in the title.
    Returns `ax`."""
    for result, style, label in ((layered, "-", name), (universal, "--", "identified universal")):
        h = result.history
        ax.plot(h["time_s"] * 1e3, h["contact_force_n"] / 1e3, style, label=f"{label}: COR "
                f"{result.cor:.3f}, contact {result.contact_time_s * 1e3:.3f} ms")
    ax.set_xlabel("time from first contact (ms)")
    ax.set_ylabel("force (kN)")
    ax.set_title(f"force NRMSE {verification['force_nrmse']:.1%}", fontsize=9)
    ax.legend(fontsize=8)
    return ax


def plot_layered(name: str, layered, universal, verification: dict, path: str | Path) -> Path:
    """Write `draw_layered` as a PNG."""
    figure, ax = subplots(figsize=(7, 4.5))
    draw_layered(ax, name, layered, universal, verification)
    return save_and_close(figure, path, f"{name} reproduced by a universal ball")
