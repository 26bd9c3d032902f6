"""The report's figures (matplotlib), returned as SVG text to inline in the page: force-time
overlays per test (thesis figures 7-1..7-4), COR, contact time and peak force against speed
(figure 7-7), the force NRMSE per model and speed, the computing cost (figure 7-5) and each
model's parameters against speed (tables 7-1..7-3)."""

from __future__ import annotations

import io
import math

import numpy as np

from ..plotting import subplots
from .inputs import ReportTest
from .models import ModelRun
from .tables import Table

#: parameter -> (factor, unit shown) for readable axes
_SHOWN = {"Pa": (1e-6, "MPa"), "s": (1e6, "us"), "N/m": (1e-6, "MN/m"), "kg": (1e3, "g")}


def svg(figure) -> str:
    """The figure as SVG text (no XML prolog, so it can sit inside HTML)."""
    out = io.StringIO()
    figure.savefig(out, format="svg", bbox_inches="tight")
    text = out.getvalue()
    return text[text.index("<svg"):]


def _colors(runs: list[ModelRun]) -> dict[str, str]:
    return {m: f"C{i % 10}" for i, m in enumerate(dict.fromkeys(r.model for r in runs))}


def force_overlays(tests: list[ReportTest], runs: list[ModelRun]):
    colors = _colors(runs)
    n = len(tests)
    columns = min(n, 2)
    rows = math.ceil(n / columns)
    figure, axes = subplots(rows, columns, figsize=(6.2 * columns, 3.9 * rows),
                            layout="constrained", squeeze=False)
    for ax, test in zip(axes.flat, tests):
        f = test.processed.features
        ax.plot(f.time_s * 1e3, f.force_n / 1e3, color="k", lw=2.2, alpha=0.45, label="test")
        for r in (r for r in runs if r.test == test.label):
            ax.plot(r.time_s * 1e3, r.force_n / 1e3, color=colors[r.model], lw=1.3,
                    label=f"{r.model} (NRMSE {r.comparison['force_nrmse']:.1%})")
        ax.set(title=f"{test.label}", xlabel="time from contact start (ms)",
               ylabel="normal force (kN)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    return figure


def versus_speed(tests: list[ReportTest], runs: list[ModelRun], key: str, label: str,
                 scale: float = 1.0):
    """`key` a feature (P17 COR, P1 contact time, P6 peak force) of the tests (markers) and of
    each model (lines) against the impact speed."""
    colors = _colors(runs)
    figure, ax = subplots(figsize=(6.4, 4.0), layout="constrained")
    ax.plot([t.speed_m_s for t in tests], [t.processed.features.values[key] * scale for t in tests],
            "ko", ms=7, label="tests")
    for model, color in colors.items():
        mine = sorted((r for r in runs if r.model == model), key=lambda r: r.impact_speed_m_s)
        ax.plot([r.impact_speed_m_s for r in mine], [r.features[key] * scale for r in mine],
                "s-", color=color, ms=4, lw=1.2, label=model)
    ax.set(xlabel="impact speed (m/s)", ylabel=label)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return figure


def nrmse_bars(tests: list[ReportTest], runs: list[ModelRun]):
    colors = _colors(runs)
    figure, ax = subplots(figsize=(6.4, 4.0), layout="constrained")
    width = 0.8 / len(colors)
    for j, (model, color) in enumerate(colors.items()):
        values = {r.test: r.comparison["force_nrmse"] * 100 for r in runs if r.model == model}
        x = np.arange(len(tests)) + (j - (len(colors) - 1) / 2) * width
        ax.bar(x, [values.get(t.label, np.nan) for t in tests], width, color=color, label=model)
    ax.set_xticks(np.arange(len(tests)), [t.label for t in tests], fontsize=8)
    ax.set(ylabel="force NRMSE (% of the test's peak)")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)
    return figure


def cost_bars(cost: Table):
    """Identification per test and one run per model, on a log scale (s)."""
    models = [row[0] for row in cost.rows]
    identification = [row[2] for row in cost.rows]
    run = [row[3] for row in cost.rows]
    figure, ax = subplots(figsize=(6.4, 0.6 * len(models) + 1.6), layout="constrained")
    y = np.arange(len(models))
    ax.barh(y - 0.2, [v if v > 0 else np.nan for v in identification], 0.4, color="C1",
            label="identification per test (fit, network)")
    ax.barh(y + 0.2, run, 0.4, color="C0", label="one run (compiled)")
    ax.set_yticks(y, models, fontsize=8)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.set(xlabel="wall time on this machine (s)")
    ax.grid(alpha=0.3, axis="x")
    ax.legend(fontsize=8)
    return figure


def parameters_vs_speed(model: str, runs: list[ModelRun]):
    """One panel per parameter of `model` against impact speed, with standard errors or 90%
    intervals as error bars."""
    mine = sorted((r for r in runs if r.model == model), key=lambda r: r.impact_speed_m_s)
    names = list(mine[0].parameters)
    columns = min(len(names), 4)
    rows = math.ceil(len(names) / columns)
    figure, axes = subplots(rows, columns, figsize=(3.3 * columns, 2.7 * rows),
                            layout="constrained", squeeze=False)
    speeds = [r.impact_speed_m_s for r in mine]
    for ax, name in zip(axes.flat, names):
        si_unit = mine[0].units.get(name, "")
        factor, unit = _SHOWN.get(si_unit, (1.0, si_unit))
        values = np.array([r.parameters[name] for r in mine])
        low, high = _spread(mine, name, values)
        ax.errorbar(speeds, values * factor, fmt="o-", ms=4, capsize=3,
                    yerr=[(values - low) * factor, (high - values) * factor])
        unknown = [i for i, r in enumerate(mine) if name in r.not_identified]
        if unknown:  # open markers: a value the test does not determine
            ax.plot([speeds[i] for i in unknown], values[unknown] * factor, "o", ms=8,
                    mfc="white", mec="C3", label="not identified")
            ax.legend(fontsize=6)
        if np.all(values > 0) and values.max() > 30 * values.min():
            ax.set_yscale("log", nonpositive="clip")  # power-law stiffnesses span decades
        ax.set_title(f"{name} ({unit})" if unit and unit != "1" else name, fontsize=9)
        ax.set_xlabel("impact speed (m/s)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(names):]:
        ax.set_visible(False)
    return figure


def _spread(runs: list[ModelRun], name: str, values: np.ndarray):
    """Lower and upper ends of each value's error bar (standard error or 90% interval)."""
    low, high = values.copy(), values.copy()
    for i, r in enumerate(runs):
        if "standard_error" in r.uncertainty:
            e = r.uncertainty["standard_error"].get(name, 0.0)
            # a bar larger than the value says nothing and would swamp the axis
            if math.isfinite(e) and name not in r.not_identified:
                low[i], high[i] = values[i] - e, values[i] + e
        elif name in r.uncertainty.get("interval_90", {}):
            low[i], high[i] = r.uncertainty["interval_90"][name]
    return low, high
