"""Pictures of an impact: force-time (raw and filtered), force-displacement, lumped-model fits and
FE runs.

Each picture is a `draw_*(ax, ...)` function that draws on a matplotlib Axes the caller gives
and returns it, so it can go into any figure; the `plot_*` functions are thin wrappers that lay
out a figure of such panels and write it to a file. Figures are bare `matplotlib.figure.Figure`s
(no pyplot): any backend saves them, and nothing here chooses or changes the user's backend.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from .records.features import ImpactFeatures
from .records.record import ImpactRecord
from .records.repeats import plot_pulse_bands, pulse_bands


def subplots(nrows: int = 1, ncols: int = 1, *, figsize, layout: str | None = None, **kwargs):
    """`pyplot.subplots` without pyplot: a bare `Figure` and its Axes (`Figure.subplots`'s
    keywords, e.g. `squeeze`). Saving it needs no backend and nothing has to close it."""
    figure = Figure(figsize=figsize, layout=layout)
    return figure, figure.subplots(nrows, ncols, **kwargs)


def save_and_close(figure, path: str | Path, title: str | None = None) -> Path:
    """Write `figure` (PNG at 120 dpi, or the format of the suffix) with `title` above its
    panels, and let it go; returns the path."""
    if title:
        figure.suptitle(title)
    figure.savefig(path, dpi=120)
    _close(figure)
    return Path(path)


def _close(figure) -> None:
    """Drop a figure pyplot holds (one a user made with pyplot); a bare `Figure` is freed like
    any object. pyplot is imported only when it already manages the figure."""
    if figure.canvas.manager is not None:
        import matplotlib.pyplot as plt

        plt.close(figure)


def draw_force_time(ax, raw: ImpactRecord, filtered: ImpactRecord, features: ImpactFeatures,
                    fit=None):
    """Force-time around the contact on `ax` (ms, kN): raw and filtered force, the peak, the
    contact window and a lumped-model `fit` if given, with a legend. Returns `ax`."""
    start = features.window.start_s
    margin = 0.3 * features.values["P1"]
    shown = (raw.time_s >= start - margin) & (raw.time_s <= features.window.end_s + margin)
    ax.plot((raw.time_s[shown] - start) * 1e3, raw.force_n[shown] / 1e3,
            color="0.6", lw=0.8, label="raw (baseline removed)")
    name = filtered.metadata.get("filter", "none")
    if name != "none":
        ax.plot((filtered.time_s[shown] - start) * 1e3, filtered.force_n[shown] / 1e3,
                color="C0", lw=1.6, label=f"filtered ({name})")
    ax.plot(features.values["P5"] * 1e3, features.values["P6"] / 1e3, "v", color="C3",
            label=f"peak {features.values['P6'] / 1e3:.3g} kN")
    if fit is not None:
        ax.plot((fit.time_s - start) * 1e3, fit.fitted_force_n / 1e3, color="C1", lw=1.4,
                ls="-.", label=f"{fit.model} fit (NRMSE {fit.nrmse:.1%})")
    for edge in (0.0, features.values["P1"]):
        ax.axvline(edge * 1e3, color="C2", lw=0.8, ls="--")
    # the window's edges as one legend entry
    ax.plot([], [], color="C2", ls="--", label=f"contact {features.values['P1'] * 1e3:.3g} ms")
    ax.set(xlabel="time from contact start (ms)", ylabel="normal force (kN)", title="force-time")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return ax


def draw_force_displacement(ax, features: ImpactFeatures):
    """The force-displacement loop of the ball centre on `ax` (mm, kN), the energy lost and the
    COR in the title. Returns `ax`."""
    ax.plot(features.displacement_m * 1e3, features.force_n / 1e3, color="C0")
    ax.set(xlabel="ball-centre displacement (mm)", ylabel="normal force (kN)",
           title=f"force-displacement: energy lost {features.energy_lost_j:.3g} J, "
                 f"COR {features.values['P17']:.3f}")
    ax.grid(alpha=0.3)
    return ax


def plot_impact(
    raw: ImpactRecord,
    filtered: ImpactRecord,
    features: ImpactFeatures,
    path: str | Path,
    *,
    title: str | None = None,
    fit=None,
) -> Path:
    """Write a two-panel PNG: `draw_force_time` and `draw_force_displacement`."""
    figure, (ax_time, ax_loop) = subplots(1, 2, figsize=(11, 4.2), layout="constrained")
    draw_force_time(ax_time, raw, filtered, features, fit)
    draw_force_displacement(ax_loop, features)
    return save_and_close(figure, path, title)


def plot_repeats(processed_list, groups, path: str | Path) -> Path:
    """Write the mean pulse of each speed group with its band (`repeats.pulse_bands` of the
    `ProcessedImpact`s and their speed groups, m/s, drawn by `repeats.plot_pulse_bands`) as a
    PNG."""
    figure, ax = subplots(figsize=(7.5, 4.5), layout="constrained")
    plot_pulse_bands(ax, pulse_bands(processed_list, groups))
    return save_and_close(figure, path)


def draw_fit(ax, result):
    """A lumped-model fit (`lumped.FitResult`) on `ax`: measured and fitted force-time (ms, kN),
    the RMSE in the title. Returns `ax`."""
    _draw_fit_curves(ax, result, "C0")
    ax.set(xlabel="time from model onset (ms)", ylabel="normal force (kN)",
           title=f"{result.model}: RMSE {result.rmse_n:.4g} N (NRMSE {result.nrmse:.2%})")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return ax


def draw_fit_convergence(ax, result):
    """The search's convergence of a lumped-model fit on `ax`: best and mean fitness per
    generation (as thesis fig. 4-2) and the final fitness. Returns `ax`."""
    generations = range(1, len(result.history_best) + 1)
    ax.semilogy(generations, result.history_mean, color="0.5", label="mean of population")
    ax.semilogy(generations, result.history_best, color="C3", label="best so far")
    ax.axhline(result.fitness, color="C2", ls="--", lw=0.8,
               label=f"after polish {result.fitness:.4g}" if result.polished
               else f"final {result.fitness:.4g}")
    ax.set(xlabel="generation", ylabel="fitness (NRMSE + weighted terms)",
           title=f"convergence ({result.method.upper()}, seed {result.seed})")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    return ax


def plot_fit(result, path: str | Path, *, title: str | None = None) -> Path:
    """Write a two-panel PNG of a lumped-model fit: `draw_fit` and `draw_fit_convergence`."""
    figure, (ax_force, ax_history) = subplots(1, 2, figsize=(11, 4.2), layout="constrained")
    draw_fit(ax_force, result)
    draw_fit_convergence(ax_history, result)
    return save_and_close(figure, path, title)


def draw_speed_fits(ax, results, title: str | None = None):
    """Measured and fitted force-time curves of several fits (one per impact speed, a colour
    each) on `ax`; `title` or one naming the model and the number of speeds. Returns `ax`."""
    for i, result in enumerate(results):
        _draw_fit_curves(ax, result, f"C{i}", label=f"{result.measured['impact_speed_m_s']:g} m/s")
    ax.set(xlabel="time from model onset (ms)", ylabel="normal force (kN)",
           title=title or f"{results[0].model} fitted at {len(results)} speeds")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return ax


def plot_speed_fits(results, path: str | Path, *, title: str | None = None) -> Path:
    """Write `draw_speed_fits` as a PNG (`title` on the panel, as there is one)."""
    figure, ax = subplots(figsize=(7.5, 4.5), layout="constrained")
    draw_speed_fits(ax, results, title)
    return save_and_close(figure, path)


def _draw_fit_curves(ax, result, color: str, label: str | None = None) -> None:
    time_ms = (result.time_s - result.onset_s) * 1e3
    ax.plot(time_ms, result.measured_force_n / 1e3, ".", ms=2.5, color="0.55",
            label=None if label else "measured")
    ax.plot(time_ms, result.fitted_force_n / 1e3, color=color, lw=1.6,
            label=label or f"{result.model} fit")


def draw_fe_forces(ax, results):
    """The contact force against time of FE results (`fe.ImpactResult`s) on `ax`, one colour each
    (ms, kN), with a legend. Returns `ax`."""
    # the property cycle's colours, as the sections of `plot_fe` are drawn in other Axes
    colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, result in enumerate(results):
        h = result.history
        ax.plot(h["time_s"] * 1e3, h["contact_force_n"] / 1e3, color=colors[i % 10],
                label=f"{result.ball_name}, {result.impact_speed_m_s:g} m/s")
    ax.set(xlabel="time (ms)", ylabel="contact force (kN)", title="contact force")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return ax


def draw_fe_section(ax, result):
    """The deformed cross-section of an FE result at peak force on `ax` (mm): the meridian
    mirrored about the axis, coloured by layer, on the plane. Returns `ax`."""
    from matplotlib.collections import PolyCollection

    layer = np.concatenate([np.full(b - a, k) for k, (a, b) in enumerate(result.layer_slices)])
    for sign in (-1.0, 1.0):
        xy = (result.nodes_m + result.displacement_at_peak_m)[result.elements_connectivity]
        xy = xy * np.array([sign, 1.0]) * 1e3
        xy[..., 1] += result.outer_radius_m * 1e3
        ax.add_collection(PolyCollection(xy, facecolors=[f"C{k}" for k in layer],
                                         edgecolors="k", linewidths=0.15, alpha=0.55))
    r = result.outer_radius_m * 1e3
    ax.axhline(0.0, color="k", lw=1.5)
    ax.set(xlim=(-1.1 * r, 1.1 * r), ylim=(-0.1 * r, 2.1 * r), aspect="equal",
           xlabel="r (mm)", ylabel="z (mm)",
           title=f"{result.ball_name}: peak {result.peak_force_n / 1e3:.2f} kN "
                 f"at {result.time_of_peak_s * 1e3:.3f} ms")
    return ax


def plot_fe(results, path: str | Path, *, title: str | None = None) -> Path:
    """Write a PNG of FE impacts: `draw_fe_forces` of all results, then `draw_fe_section` of
    each."""
    results = list(results)
    figure, axes = subplots(1, 1 + len(results), figsize=(4.6 * (1 + len(results)), 4.2),
                            layout="constrained")
    draw_fe_forces(axes[0], results)
    for ax, result in zip(axes[1:], results):
        draw_fe_section(ax, result)
    return save_and_close(figure, path, title)
