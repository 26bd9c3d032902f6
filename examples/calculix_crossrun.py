"""The cross-code check of docs/export.md: the issue's elastic Mooney-Rivlin ball exported to
CalculiX (3D half model, C3D8, implicit dynamics) against our axisymmetric solver at 10 and
20 m/s; prints JSON and writes a force-time overlay.

    python examples/calculix_crossrun.py [--divisions 8] [--plot docs/export-calculix.png]

Needs ccx (Debian/Ubuntu: apt-get install calculix-ccx). About 2 minutes a speed on 1 core.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

from ballimpact.export.calculix import CROSS_RUN_BALL, run_impact
from ballimpact.fe import load_ball, simulate


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--divisions", type=int, default=8)
    parser.add_argument("--speeds-m-s", type=float, nargs="+", default=[10.0, 20.0])
    parser.add_argument("--plot", type=Path)
    args = parser.parse_args()
    ball = load_ball(CROSS_RUN_BALL)
    rows, curves = [], []
    with tempfile.TemporaryDirectory() as folder:
        for speed in args.speeds_m_s:
            ours = simulate(ball, speed)
            print(f"{speed:g} m/s: ours done, running CalculiX...", file=sys.stderr)
            theirs = run_impact(ball, speed, Path(folder) / f"v{speed:g}",
                                divisions=args.divisions, step_time_s=1.15 * ours.contact_time_s)
            rows.append({
                "impact_speed_m_s": speed,
                "ours": {"peak_force_n": ours.peak_force_n, "contact_time_s": ours.contact_time_s,
                         "cor": ours.cor, "wall_time_s": ours.wall_time_s},
                "calculix": {"peak_force_n": theirs.peak_force_n,
                             "contact_time_s": theirs.contact_time_s, "cor": theirs.cor,
                             "wall_time_s": theirs.wall_time_s,
                             "increments": len(theirs.time_s) - 1},
                "peak_force_difference": theirs.peak_force_n / ours.peak_force_n - 1.0,
                "contact_time_difference": theirs.contact_time_s / ours.contact_time_s - 1.0,
                "cor_difference": theirs.cor - ours.cor})
            curves.append((speed, ours, theirs))
    print(json.dumps({"ball": CROSS_RUN_BALL["name"], "divisions": args.divisions, "runs": rows},
                     indent=2))
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6.5, 4.0))
        for (speed, ours, theirs), color in zip(curves, ("tab:blue", "tab:red", "tab:green")):
            history = ours.history
            ax.plot(history["time_s"] * 1e3, history["contact_force_n"] * 1e-3, color=color,
                    label=f"ballimpact, {speed:g} m/s")
            ax.plot(theirs.time_s * 1e3, theirs.force_n * 1e-3, "o", ms=3, color=color,
                    mfc="none", label=f"CalculiX, {speed:g} m/s")
        ax.set(xlabel="time (ms)", ylabel="contact force (kN)",
               title="Exported elastic Mooney-Rivlin ball: ballimpact vs CalculiX")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)


if __name__ == "__main__":
    main()
