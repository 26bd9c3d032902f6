"""The tracked ball and the fitted trajectories (matplotlib)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .track import Detection
from .trajectory import Measurement


def plot_measurement(detections: list[Detection], m: Measurement, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = m.summary
    fps = s["fps"]
    centres = np.array([d.centre_px for d in detections])
    t = np.arange(len(detections)) / fps
    first, last = m.contact_frames
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2))
    found = np.isfinite(centres[:, 0])
    used = np.zeros(len(detections), bool)
    for phase in m.phases:
        used[phase.frames] = True
    for ax, x in ((left, centres[:, 0]), (right, t * 1e3)):
        ax.plot(x[found & ~used], centres[found & ~used, 1], "x", color="0.6", ms=4,
                label="not used (contact, border, poor fit)")
        ax.plot(x[used], centres[used, 1], ".", color="tab:blue", ms=3, label="free flight")
        ax.axhline(s["surface_row_px"] - s["ball_radius_px"], color="k", lw=0.8, ls="--",
                   label="centre at contact")
    for phase, tt in zip(m.phases, (np.linspace(t[0], s["impact_time_s"], 50),
                                    np.linspace(s["rebound_time_s"], t[-1], 50))):
        col, row = phase.position(tt)
        row = row + 0.5 * m.gravity_px_s2 * tt ** 2
        left.plot(col, row, color="tab:red", lw=1)
        right.plot(tt * 1e3, row, color="tab:red", lw=1)
    left.set(xlabel="column (px)", ylabel="row (px)", title="ball centre in the image")
    left.invert_yaxis()
    left.set_aspect("equal", adjustable="datalim")
    right.set(xlabel="time (ms)", ylabel="row (px)",
              title=f"impact {s['impact_speed_m_s']:.3f} m/s, rebound "
                    f"{s['rebound_speed_m_s']:.3f} m/s, COR {s['cor']:.3f}")
    right.invert_yaxis()
    right.axvspan(t[first] * 1e3, t[last] * 1e3, color="0.9", label="contact frames")
    right.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
