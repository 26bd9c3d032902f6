"""Pictures of a calibration: the Pareto front (2-D, or every pair of objectives side by side for
three or more) with the chosen design, the search's convergence, and the calibrated ball's pulses
over the tests."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..plotting import save_and_close, plt

_LABELS = {"nrmse": "force NRMSE (%)", "cor": "|COR error| (x100)",
           "contact_time": "|contact time error| (%)", "peak_force": "|peak force error| (%)",
           "compression": "compression force NRMSE (%)"}


def plot_pareto(result, chosen: int | None, path: str | Path, title: str | None = None) -> Path:
    """All feasible evaluated designs (grey), the front (blue) and the chosen design (red), in
    percent; `chosen` indexes the designs of `result`."""
    names = result.problem.objectives
    f = 100.0 * result.objectives
    ok = np.all(np.isfinite(f), axis=1)
    front = result.pareto()
    m = len(names)
    if m == 1:
        figure, ax = plt.subplots(figsize=(5, 4), constrained_layout=True)
        ax.plot(result.generation[ok], f[ok, 0], ".", color="0.6")
        if chosen is not None:
            ax.plot(result.generation[chosen], f[chosen, 0], "o", color="C3", label="chosen")
        ax.set(xlabel="generation", ylabel=_LABELS[names[0]])
        return save_and_close(figure, Path(path), title)
    pairs = [(0, 1)] if m == 2 else [(i, j) for j in range(m) for i in range(m) if i < j]
    figure, axes = plt.subplots(1, len(pairs), figsize=(4.6 * len(pairs), 4.2),
                                constrained_layout=True, squeeze=False)
    for ax, (i, j) in zip(axes[0], pairs):
        ax.plot(f[ok, i], f[ok, j], ".", color="0.7", label="evaluated")
        order = front[np.argsort(f[front, i])]
        ax.plot(f[order, i], f[order, j], "o-" if m == 2 else "o", ms=4, color="C0",
                label="Pareto front")
        if chosen is not None:
            ax.plot(f[chosen, i], f[chosen, j], "*", ms=14, color="C3", label="chosen")
        ax.set(xlabel=_LABELS[names[i]], ylabel=_LABELS[names[j]],
               xscale=_scale(f[ok, i]), yscale=_scale(f[ok, j]))
    axes[0][0].legend(fontsize=8)
    return save_and_close(figure, Path(path), title)


def _scale(values: np.ndarray) -> str:
    """Log axes for objectives spanning decades, linear ones otherwise (readable ticks)."""
    positive = values[values > 0]
    return "log" if positive.size and positive.max() > 20 * positive.min() else "linear"


def plot_convergence(result, path: str | Path, title: str | None = None) -> Path:
    """Best value so far of each objective and the hypervolume of the front against the
    generation."""
    c = result.convergence()
    figure, (ax_best, ax_hv) = plt.subplots(1, 2, figsize=(10, 3.8), constrained_layout=True)
    for j, name in enumerate(result.problem.objectives):
        ax_best.semilogy(c["generation"], 100.0 * c["best"][:, j], "o-", label=_LABELS[name])
    ax_best.set(xlabel="generation", ylabel="best so far")
    ax_best.legend(fontsize=8)
    ax_hv.plot(c["generation"], c["hypervolume"], "o-")
    ax_hv.set(xlabel="generation", ylabel="hypervolume of the normalised front")
    return save_and_close(figure, Path(path), title)


def plot_pulses(tests, runs, path: str | Path, title: str | None = None) -> Path:
    """Each test's pulse with the calibrated ball's FE pulse (a compression test's
    force-deflection curve with the FE curve)."""
    from .compression import is_compression

    figure, axes = plt.subplots(1, len(tests), figsize=(4.6 * len(tests), 3.8),
                                constrained_layout=True, squeeze=False)
    for ax, test, fe in zip(axes[0], tests, runs):
        if is_compression(test):
            ax.plot(test.deflection_m * 1e3, test.force_n * 1e-3, "o", ms=3, color="0.3",
                    label=f"test {test.name}")
            ax.plot(fe.deflection_m * 1e3, fe.force_n * 1e-3, "--", color="C3",
                    label="calibrated")
            rate = "long-term" if test.rate_m_s is None else f"{test.rate_m_s:g} m/s"
            ax.set(xlabel="deflection (mm)", ylabel="force (kN)", title=f"compression, {rate}")
            ax.legend(fontsize=8)
            continue
        t, f = test.pulse
        ax.plot(t * 1e3, f * 1e-3, color="0.3", label=f"test {test.name}")
        h = fe.history
        ax.plot(h["time_s"] * 1e3, h["contact_force_n"] * 1e-3, "--", color="C3",
                label=f"calibrated (COR {fe.cor:.3f})")
        ax.set(xlabel="time from contact (ms)", ylabel="force (kN)",
               title=f"{test.impact_speed_m_s:.3g} m/s, test COR {test.features.values['P17']:.3f}")
        ax.legend(fontsize=8)
    return save_and_close(figure, Path(path), title)
