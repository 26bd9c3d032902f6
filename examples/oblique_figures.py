"""The figures of docs/oblique.md: the sign convention, and the thesis' oblique case (universal
ball, 37 m/s, 34 degrees to the surface, friction 0.3): force, spin and energy histories and a
frame of the mid-plane section. Prints the case's results as JSON.

    python examples/oblique_figures.py [--out docs] [--divisions 16]
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle, FancyArrowPatch  # noqa: E402

from ballimpact.fe import load_ball  # noqa: E402
from ballimpact.fe import Hexahedral, simulate  # noqa: E402
from ballimpact.oblique import ImpactCondition, Options3D  # noqa: E402
from ballimpact.oblique.output import section_figure  # noqa: E402
from ballimpact.oblique.plots import plot_oblique  # noqa: E402


def convention(path: Path) -> None:
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.add_patch(Circle((0, 1), 1, fill=False, lw=2))
    ax.axhline(0, color="0.3", lw=3)
    theta = math.radians(34)
    start = (-2.2 * math.sin(theta) - 0.0, 1 + 2.2 * math.cos(theta))
    ax.add_patch(FancyArrowPatch(start, (-0.15 * math.sin(theta), 1 + 0.15 * math.cos(theta)),
                                 arrowstyle="-|>", mutation_scale=18, color="C0", lw=2))
    ax.plot([0, 0], [1, 3.2], ":", color="0.5")
    ax.text(-0.55, 2.9, "angle_deg\n(from the normal)", fontsize=8, ha="right", color="C0")
    ax.add_patch(FancyArrowPatch((0.55, 1.75), (0.75, 0.5), connectionstyle="arc3,rad=-0.5",
                                 arrowstyle="-|>", mutation_scale=15, color="C3", lw=2))
    ax.text(1.05, 1.5, "spin_rad_s > 0:\ntopspin (rolls\nforward along +x)", fontsize=8,
            color="C3")
    ax.annotate("", xy=(2.6, 0.25), xytext=(1.8, 0.25),
                arrowprops=dict(arrowstyle="-|>", color="k"))
    ax.text(2.65, 0.2, "x", fontsize=10)
    ax.annotate("", xy=(1.8, 1.05), xytext=(1.8, 0.25),
                arrowprops=dict(arrowstyle="-|>", color="k"))
    ax.text(1.75, 1.1, "z", fontsize=10)
    ax.text(1.9, 0.45, "y into the page;\nhalf model y >= 0", fontsize=7)
    ax.set_xlim(-2.5, 3.4)
    ax.set_ylim(-0.3, 3.5)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title("oblique impact: incoming velocity, spin sign and axes", fontsize=9)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs"))
    parser.add_argument("--divisions", type=int, default=16)
    args = parser.parse_args()
    convention(args.out / "oblique-convention.png")
    ball = load_ball("cricket-universal", impact_speed_m_s=25.0)
    result = simulate(ball, ImpactCondition(37.0, 56.0, 0.0, 0.3), geometry=Hexahedral(
        Options3D(divisions=args.divisions, chunk_steps=50, frames=1)))
    plot_oblique([result], args.out / "oblique-histories.png")
    peak = min(range(len(result.frames)),
               key=lambda i: abs(result.frames[i]["time_s"] - result.time_of_peak_s))
    section_figure(result, peak, args.out / "oblique-frame.png")
    print(json.dumps({k: v for k, v in result.summary().items()}, indent=1))


if __name__ == "__main__":
    main()
