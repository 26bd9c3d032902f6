"""Pictures of an impact: force-time (raw and filtered) and force-displacement.

matplotlib is used with the Agg backend, so plots are written to files with no display.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .features import ImpactFeatures  # noqa: E402
from .records import ImpactRecord  # noqa: E402


def plot_impact(
    raw: ImpactRecord,
    filtered: ImpactRecord,
    features: ImpactFeatures,
    path: str | Path,
    *,
    title: str | None = None,
    fit=None,
) -> Path:
    """Write a two-panel PNG: force-time (raw, filtered, contact window, peak, and a lumped-model
    `fit` if given) and the force-displacement loop of the ball centre. Axes in ms, mm and kN."""
    path = Path(path)
    start = features.window.start_s
    figure, (ax_time, ax_loop) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    margin = 0.3 * features.values["P1"]
    shown = (raw.time_s >= start - margin) & (raw.time_s <= features.window.end_s + margin)
    ax_time.plot((raw.time_s[shown] - start) * 1e3, raw.force_n[shown] / 1e3,
                 color="0.6", lw=0.8, label="raw (baseline removed)")
    name = filtered.metadata.get("filter", "none")
    if name != "none":
        ax_time.plot((filtered.time_s[shown] - start) * 1e3, filtered.force_n[shown] / 1e3,
                     color="C0", lw=1.6, label=f"filtered ({name})")
    ax_time.plot(features.values["P5"] * 1e3, features.values["P6"] / 1e3, "v", color="C3",
                 label=f"peak {features.values['P6'] / 1e3:.3g} kN")
    if fit is not None:
        ax_time.plot((fit.time_s - start) * 1e3, fit.fitted_force_n / 1e3, color="C1", lw=1.4,
                     ls="-.", label=f"{fit.model} fit (NRMSE {fit.nrmse:.1%})")
    for edge in (0.0, features.values["P1"]):
        ax_time.axvline(edge * 1e3, color="C2", lw=0.8, ls="--")
    ax_time.plot([], [], color="C2", ls="--", label=f"contact {features.values['P1'] * 1e3:.3g} ms")
    ax_time.set(xlabel="time from contact start (ms)", ylabel="normal force (kN)",
                title="force-time")
    ax_time.legend(fontsize=8)
    ax_time.grid(alpha=0.3)

    ax_loop.plot(features.displacement_m * 1e3, features.force_n / 1e3, color="C0")
    ax_loop.set(xlabel="ball-centre displacement (mm)", ylabel="normal force (kN)",
                title=f"force-displacement: energy lost {features.energy_lost_j:.3g} J, "
                      f"COR {features.values['P17']:.3f}")
    ax_loop.grid(alpha=0.3)
    return save_and_close(figure, path, title)


def plot_fit(result, path: str | Path, *, title: str | None = None) -> Path:
    """A lumped-model fit (`lumped.FitResult`): measured and fitted force-time, and the search's
    convergence (best and mean fitness per generation, as thesis fig. 4-2)."""
    path = Path(path)
    figure, (ax_force, ax_history) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    _plot_fit_curves(ax_force, result, "C0")
    ax_force.set(xlabel="time from model onset (ms)", ylabel="normal force (kN)",
                 title=f"{result.model}: RMSE {result.rmse_n:.4g} N (NRMSE {result.nrmse:.2%})")
    ax_force.legend(fontsize=8)
    ax_force.grid(alpha=0.3)
    generations = range(1, len(result.history_best) + 1)
    ax_history.semilogy(generations, result.history_mean, color="0.5", label="mean of population")
    ax_history.semilogy(generations, result.history_best, color="C3", label="best so far")
    ax_history.axhline(result.fitness, color="C2", ls="--", lw=0.8,
                       label=f"after polish {result.fitness:.4g}" if result.polished
                       else f"final {result.fitness:.4g}")
    ax_history.set(xlabel="generation", ylabel="fitness (NRMSE + weighted terms)",
                   title=f"convergence ({result.method.upper()}, seed {result.seed})")
    ax_history.legend(fontsize=8)
    ax_history.grid(alpha=0.3, which="both")
    return save_and_close(figure, path, title)


def plot_speed_fits(results, path: str | Path, *, title: str | None = None) -> Path:
    """Measured and fitted force-time curves of several fits (one per impact speed)."""
    path = Path(path)
    figure, ax = plt.subplots(figsize=(7.5, 4.5), constrained_layout=True)
    for i, result in enumerate(results):
        _plot_fit_curves(ax, result, f"C{i}",
                         label=f"{result.measured['impact_speed_m_s']:g} m/s")
    ax.set(xlabel="time from model onset (ms)", ylabel="normal force (kN)",
           title=title or f"{results[0].model} fitted at {len(results)} speeds")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return save_and_close(figure, path, None)


def _plot_fit_curves(ax, result, color: str, label: str | None = None) -> None:
    time_ms = (result.time_s - result.onset_s) * 1e3
    ax.plot(time_ms, result.measured_force_n / 1e3, ".", ms=2.5, color="0.55",
            label=None if label else "measured")
    ax.plot(time_ms, result.fitted_force_n / 1e3, color=color, lw=1.6,
            label=label or f"{result.model} fit")


def save_and_close(figure, path: Path, title: str | None) -> Path:
    if title:
        figure.suptitle(title)
    figure.savefig(path, dpi=120)
    plt.close(figure)
    return path


def plot_fe(results, path: str | Path, *, title: str | None = None) -> Path:
    """FE impacts: contact force against time for each result, and for each the deformed
    cross-section at peak force (meridian mirrored about the axis, coloured by layer)."""
    from matplotlib.collections import PolyCollection

    import numpy as np

    results = list(results)
    figure, axes = plt.subplots(1, 1 + len(results), figsize=(4.6 * (1 + len(results)), 4.2),
                                layout="constrained")
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, result in enumerate(results):
        h = result.history
        axes[0].plot(h["time_s"] * 1e3, h["contact_force_n"] / 1e3, color=colors[i % 10],
                     label=f"{result.ball_name}, {result.impact_speed_m_s:g} m/s")
        ax = axes[1 + i]
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
    axes[0].set(xlabel="time (ms)", ylabel="contact force (kN)", title="contact force")
    axes[0].legend(fontsize=8)
    axes[0].grid(alpha=0.3)
    return save_and_close(figure, Path(path), title)
