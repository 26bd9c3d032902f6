"""The universal cricket ball (thesis table 7-3, its constants at 20 m/s) squeezed 5 mm between
two platens: the long-term (relaxed) curve and at platen speeds of 1, 20 and 80 m/s (5 mm take
5 ms at 1 m/s, 62 us at 80 m/s, against its relaxation time), in one figure
(docs/materials.md). Run: python examples/compress_rates.py [PNG]
"""

from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ballimpact.fe import compress, load_ball  # noqa: E402

RATES_M_S = (None, 1.0, 20.0, 80.0)


def main(png: str = "compress-rates.png") -> None:
    ball = load_ball("cricket-universal", impact_speed_m_s=20.0)
    (layer,) = ball.layers
    print(f"prony: {[(t.g, t.tau_s) for t in layer.material.prony]}")
    figure, axis = plt.subplots(figsize=(5.5, 4.2), layout="constrained")
    for rate in RATES_M_S:
        curve = compress(ball, 0.005, rate_m_s=rate)
        label = "long-term" if rate is None else f"{rate:g} m/s"
        print(f"{label:>10}: peak {curve.peak_force_n:7.1f} N, secant "
              f"{curve.secant_stiffness_n_m / 1e3:6.1f} N/mm, {curve.wall_time_s:.1f} s")
        axis.plot(curve.deflection_m * 1e3, curve.force_n, "o-", ms=3, label=label)
    axis.set_xlabel("deflection (platen approach), mm")
    axis.set_ylabel("force, N")
    axis.set_title("cricket-universal (20 m/s constants) between two platens", fontsize=10)
    axis.legend(title="platen speed")
    axis.grid(alpha=0.3)
    figure.savefig(png, dpi=120)
    print(f"wrote {png}")


if __name__ == "__main__":
    main(*sys.argv[1:])
