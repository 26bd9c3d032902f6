"""Pictures of a hyperelastic fit: measured and fitted nominal stress against stretch, one panel
per deformation mode (volumetric: pressure against volume ratio). Axes in MPa.

`draw_fit` draws one mode on a matplotlib Axes the caller gives; `plot_fit` writes the panels of
every mode to a file. Nothing here chooses a backend."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..plotting import save_and_close, subplots
from .hyperelastic import HyperelasticFit, energy_constants
from .modes import deformation_stress


def deformations(tests) -> list[str]:
    """The deformation modes of `tests` in order of first appearance (a panel each)."""
    return list(dict.fromkeys(t.deformation for t in tests))


def draw_fit(ax, tests, fit: HyperelasticFit, kind: str):
    """The tests of deformation `kind` (markers) and the fitted model (line, on a fine grid of
    stretches; general biaxial at the data's stretches) on `ax`, a colour per test, with the
    R^2 of each in the legend. Returns `ax`."""
    constants = energy_constants(fit.material)
    volumetric_constants = dict(constants)
    if fit.model != "ogden_hyperfoam":  # rubber laws: K from d1_per_pa (0: not fitted)
        d1 = fit.material.get("d1_per_pa", 0.0)
        volumetric_constants["k_pa"] = 2.0 / d1 if d1 else 0.0
    for i, t in enumerate(x for x in tests if x.deformation == kind):
        c = t.columns
        colour = f"C{i}"
        if kind == "volumetric":
            x, y = c["volume_ratio"], c["pressure_pa"]
            grid = np.linspace(x.min(), x.max(), 200)
            model = deformation_stress(fit.model, volumetric_constants, kind, grid)
        elif kind == "biaxial":
            x, y = c["stretch_1"], c["nominal_stress_1_pa"]
            grid = x
            model = deformation_stress(fit.model, constants, kind, x, c["stretch_2"])[:, 0]
        else:
            x, y = c["stretch"], c["nominal_stress_pa"]
            grid = np.linspace(x.min(), x.max(), 200)
            model = deformation_stress(fit.model, constants, kind, grid)
        ax.plot(x, y / 1e6, "o", ms=4, color=colour, label=f"{t.name}")
        ax.plot(grid, model / 1e6, "-", color=colour, lw=1.4,
                label=f"{fit.model} (R^2 {fit.r2.get(str(t.path), float('nan')):.4f})")
    ax.set_title(kind)
    ax.set_xlabel("volume ratio J" if kind == "volumetric" else "stretch")
    ax.set_ylabel("pressure (MPa)" if kind == "volumetric" else "nominal stress (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    return ax


def plot_fit(tests, fit: HyperelasticFit, path: str | Path) -> Path:
    """Write a PNG with `draw_fit` of each deformation of `tests`, side by side."""
    kinds = deformations(tests)
    figure, axes = subplots(1, len(kinds), figsize=(4.2 * len(kinds), 3.8),
                            layout="constrained", squeeze=False)
    for ax, kind in zip(axes[0], kinds):
        draw_fit(ax, tests, fit, kind)
    return save_and_close(figure, path)


__all__ = ["deformations", "draw_fit", "plot_fit"]
