"""Pictures of a calibration: the Pareto front (2-D, or every pair of objectives side by side for
three or more) with the chosen design, the search's convergence, and the calibrated ball's pulses
over the tests.

Each panel is a `draw_*(ax, ...)` function on a matplotlib Axes the caller gives (returned); the
`plot_*` functions lay the panels out and write a file. Nothing here chooses a backend."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..plotting import save_and_close, subplots

_LABELS = {"nrmse": "force NRMSE (%)", "cor": "|COR error| (x100)",
           "contact_time": "|contact time error| (%)", "peak_force": "|peak force error| (%)",
           "compression": "compression force NRMSE (%)"}


def objective_pairs(result) -> list[tuple[int, int]]:
    """The pairs of objectives (indices) `plot_pareto` draws a panel for: every pair i < j."""
    m = len(result.problem.objectives)
    return [(0, 1)] if m == 2 else [(i, j) for j in range(m) for i in range(m) if i < j]


def draw_single_objective(ax, result, chosen: int | None = None):
    """A one-objective calibration on `ax`: every feasible design's objective (percent) against
    its generation (grey), and the `chosen` design (red). Returns `ax`."""
    f = 100.0 * result.objectives
    ok = np.all(np.isfinite(f), axis=1)
    ax.plot(result.generation[ok], f[ok, 0], ".", color="0.6")
    if chosen is not None:
        ax.plot(result.generation[chosen], f[chosen, 0], "o", color="C3", label="chosen")
    ax.set(xlabel="generation", ylabel=_LABELS[result.problem.objectives[0]])
    return ax


def draw_pareto(ax, result, chosen: int | None = None, pair: tuple[int, int] = (0, 1)):
    """Objectives `pair` (indices) of a calibration against each other on `ax`, in percent: all
    feasible evaluated designs (grey), the front (blue; joined for two objectives) and the
    `chosen` design (red star); `chosen` indexes the designs of `result`. Returns `ax`."""
    names = result.problem.objectives
    i, j = pair
    f = 100.0 * result.objectives
    ok = np.all(np.isfinite(f), axis=1)
    front = result.pareto()
    ax.plot(f[ok, i], f[ok, j], ".", color="0.7", label="evaluated")
    order = front[np.argsort(f[front, i])]
    ax.plot(f[order, i], f[order, j], "o-" if len(names) == 2 else "o", ms=4, color="C0",
            label="Pareto front")
    if chosen is not None:
        ax.plot(f[chosen, i], f[chosen, j], "*", ms=14, color="C3", label="chosen")
    ax.set(xlabel=_LABELS[names[i]], ylabel=_LABELS[names[j]],
           xscale=_scale(f[ok, i]), yscale=_scale(f[ok, j]))
    return ax


def plot_pareto(result, chosen: int | None, path: str | Path, title: str | None = None) -> Path:
    """Write `draw_pareto` for each pair of objectives side by side (one legend), or
    `draw_single_objective` for one objective."""
    if len(result.problem.objectives) == 1:
        figure, ax = subplots(figsize=(5, 4), layout="constrained")
        draw_single_objective(ax, result, chosen)
        return save_and_close(figure, path, title)
    pairs = objective_pairs(result)
    figure, axes = subplots(1, len(pairs), figsize=(4.6 * len(pairs), 4.2),
                            layout="constrained", squeeze=False)
    for ax, pair in zip(axes[0], pairs):
        draw_pareto(ax, result, chosen, pair)
    axes[0][0].legend(fontsize=8)
    return save_and_close(figure, path, title)


def _scale(values: np.ndarray) -> str:
    """Log axes for objectives spanning decades, linear ones otherwise (readable ticks)."""
    positive = values[values > 0]
    return "log" if positive.size and positive.max() > 20 * positive.min() else "linear"


def draw_best_so_far(ax, convergence: dict, objectives):
    """The best value so far of each objective (percent, log scale) against the generation on
    `ax`; `convergence` is `result.convergence()`, `objectives` the objectives' names. Returns
    `ax`."""
    for j, name in enumerate(objectives):
        ax.semilogy(convergence["generation"], 100.0 * convergence["best"][:, j], "o-",
                    label=_LABELS[name])
    ax.set(xlabel="generation", ylabel="best so far")
    ax.legend(fontsize=8)
    return ax


def draw_hypervolume(ax, convergence: dict):
    """The hypervolume of the normalised front so far against the generation on `ax`;
    `convergence` is `result.convergence()`. Returns `ax`."""
    ax.plot(convergence["generation"], convergence["hypervolume"], "o-")
    ax.set(xlabel="generation", ylabel="hypervolume of the normalised front")
    return ax


def plot_convergence(result, path: str | Path, title: str | None = None) -> Path:
    """Write `draw_best_so_far` and `draw_hypervolume` side by side."""
    c = result.convergence()  # computed once: the hypervolumes are the costly part
    figure, (ax_best, ax_hv) = subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    draw_best_so_far(ax_best, c, result.problem.objectives)
    draw_hypervolume(ax_hv, c)
    return save_and_close(figure, path, title)


def draw_pulse(ax, test, fe):
    """A test's pulse with the calibrated ball's FE pulse `fe` on `ax` (ms, kN), or for a
    compression test its force-deflection curve with the FE curve (mm, kN). Returns `ax`."""
    from .compression import is_compression

    if is_compression(test):
        ax.plot(test.deflection_m * 1e3, test.force_n * 1e-3, "o", ms=3, color="0.3",
                label=f"test {test.name}")
        ax.plot(fe.deflection_m * 1e3, fe.force_n * 1e-3, "--", color="C3", label="calibrated")
        rate = "long-term" if test.rate_m_s is None else f"{test.rate_m_s:g} m/s"
        ax.set(xlabel="deflection (mm)", ylabel="force (kN)", title=f"compression, {rate}")
        ax.legend(fontsize=8)
        return ax
    t, f = test.pulse
    ax.plot(t * 1e3, f * 1e-3, color="0.3", label=f"test {test.name}")
    h = fe.history
    ax.plot(h["time_s"] * 1e3, h["contact_force_n"] * 1e-3, "--", color="C3",
            label=f"calibrated (COR {fe.cor:.3f})")
    ax.set(xlabel="time from contact (ms)", ylabel="force (kN)",
           title=f"{test.impact_speed_m_s:.3g} m/s, test COR {test.features.values['P17']:.3f}")
    ax.legend(fontsize=8)
    return ax


def plot_pulses(tests, runs, path: str | Path, title: str | None = None) -> Path:
    """Write `draw_pulse` of each test with its FE run (`runs`, in the same order) side by
    side."""
    figure, axes = subplots(1, len(tests), figsize=(4.6 * len(tests), 3.8),
                            layout="constrained", squeeze=False)
    for ax, test, fe in zip(axes[0], tests, runs):
        draw_pulse(ax, test, fe)
    return save_and_close(figure, path, title)
