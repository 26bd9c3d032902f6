"""Pictures of a hyperelastic fit: measured and fitted nominal stress against stretch, one panel
per deformation mode (volumetric: pressure against volume ratio). Axes in MPa."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .hyperelastic import HyperelasticFit, energy_constants  # noqa: E402
from .modes import deformation_stress  # noqa: E402


def plot_fit(tests, fit: HyperelasticFit, path: str | Path) -> Path:
    """Write a PNG with one panel per deformation of `tests`: data (markers) and the fitted
    model (line, on a fine grid of stretches; general biaxial at the data's stretches)."""
    path = Path(path)
    kinds = list(dict.fromkeys(t.deformation for t in tests))
    figure, axes = plt.subplots(1, len(kinds), figsize=(4.2 * len(kinds), 3.8),
                                constrained_layout=True, squeeze=False)
    constants = energy_constants(fit.material)
    volumetric_constants = dict(constants)
    if fit.model != "ogden_hyperfoam":  # rubber laws: K from d1_per_pa (0: not fitted)
        d1 = fit.material.get("d1_per_pa", 0.0)
        volumetric_constants["k_pa"] = 2.0 / d1 if d1 else 0.0
    for ax, kind in zip(axes[0], kinds):
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
    figure.savefig(path, dpi=120)
    plt.close(figure)
    return path


__all__ = ["plot_fit"]
