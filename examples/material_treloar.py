"""Treloar's (1944) rubber in uniaxial, equibiaxial and planar tension, fitted with every
hyperelastic model of `ballimpact material fit`, all three modes together (absolute error).

Prints the R^2 table (model x mode, and pooled) and writes material-treloar.png: data and fits
per mode. Run: .venv/bin/python examples/material_treloar.py [PNG]
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ballimpact.material.data import read_test  # noqa: E402
from ballimpact.material.hyperelastic import energy_constants, fit_hyperelastic  # noqa: E402
from ballimpact.material.modes import deformation_stress  # noqa: E402

DATA = Path(__file__).resolve().parents[1] / "src" / "ballimpact" / "data"
MODELS = (("neo_hookean", None), ("mooney_rivlin", None), ("yeoh", None), ("ogden", 3),
          ("ogden_hyperfoam", 2))


def main(png: str = "material-treloar.png") -> None:
    tests = [read_test(DATA / f"treloar1944_{name}.csv", mode)
             for name, mode in (("uniaxial", "uniaxial"), ("biaxial", "biaxial"),
                                ("planar", "planar"))]
    figure, axes = plt.subplots(1, 3, figsize=(13, 4), constrained_layout=True)
    print(f"{'model':<22}" + "".join(f"{t.deformation:>13}" for t in tests) + f"{'pooled':>10}")
    for k, (model, order) in enumerate(MODELS):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            fit = fit_hyperelastic(tests, model, order=order)
        label = model + (f" N={order}" if order else "")
        print(f"{label:<22}" + "".join(f"{fit.r2[str(t.path)]:>13.4f}" for t in tests)
              + f"{fit.r2['overall']:>10.4f}" + ("" if fit.usable else "  (not a ball material)")
              + "".join(f"\n    warning: {w.message}" for w in caught if fit.usable))
        constants = energy_constants(fit.material)
        for ax, t in zip(axes, tests):
            lam = np.linspace(1.0, t.columns["stretch"].max(), 200)
            ax.plot(lam, deformation_stress(model, constants, t.deformation, lam) / 1e6,
                    color=f"C{k}", lw=1.3, label=label)
    for ax, t in zip(axes, tests):
        ax.plot(t.columns["stretch"], t.columns["nominal_stress_pa"] / 1e6, "ko", ms=4,
                label="Treloar 1944")
        ax.set_title(t.deformation)
        ax.set_xlabel("stretch")
        ax.set_ylabel("nominal stress (MPa)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    figure.savefig(png, dpi=110)
    print(f"wrote {png}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
