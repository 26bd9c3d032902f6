"""The tracked ball and the fitted trajectories (matplotlib): `draw_track_image` and
`draw_track_time` draw on an Axes the caller gives; `plot_measurement` writes both to a file.
Nothing here chooses a backend."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..plotting import subplots
from .track import Detection
from .trajectory import Measurement


def _points(detections: list[Detection], m: Measurement):
    """The centres (px), frame times (s), and which frames found a ball and which the fits
    used."""
    centres = np.array([d.centre_px for d in detections])
    t = np.arange(len(detections)) / m.summary["fps"]
    found = np.isfinite(centres[:, 0])
    used = np.zeros(len(detections), bool)
    for phase in m.phases:
        used[phase.frames] = True
    return centres, t, found, used


def _draw_track(ax, x, centres, found, used, m: Measurement) -> None:
    """The centre rows against `x` (not used, used) and the row of the centre at contact."""
    s = m.summary
    ax.plot(x[found & ~used], centres[found & ~used, 1], "x", color="0.6", ms=4,
            label="not used (contact, border, poor fit)")
    ax.plot(x[used], centres[used, 1], ".", color="tab:blue", ms=3, label="free flight")
    ax.axhline(s["surface_row_px"] - s["ball_radius_px"], color="k", lw=0.8, ls="--",
               label="centre at contact")


def _fitted(m: Measurement, t: np.ndarray):
    """Per free-flight phase (before, after the impact): times (s), columns and rows (px)."""
    s = m.summary
    for phase, tt in zip(m.phases, (np.linspace(t[0], s["impact_time_s"], 50),
                                    np.linspace(s["rebound_time_s"], t[-1], 50))):
        col, row = phase.position(tt)
        yield tt, col, row + 0.5 * m.gravity_px_s2 * tt ** 2


def draw_track_image(ax, detections: list[Detection], m: Measurement):
    """The ball centre in the image on `ax` (px, rows downwards, equal scales): the detections
    and the fitted trajectories. Returns `ax`."""
    centres, t, found, used = _points(detections, m)
    _draw_track(ax, centres[:, 0], centres, found, used, m)
    for _, col, row in _fitted(m, t):
        ax.plot(col, row, color="tab:red", lw=1)
    ax.set(xlabel="column (px)", ylabel="row (px)", title="ball centre in the image")
    ax.invert_yaxis()
    ax.set_aspect("equal", adjustable="datalim")
    return ax


def draw_track_time(ax, detections: list[Detection], m: Measurement):
    """The centre's row against time on `ax` (ms, px): the detections, the fitted trajectories
    and the contact frames shaded; the speeds and COR in the title. Returns `ax`."""
    s = m.summary
    centres, t, found, used = _points(detections, m)
    _draw_track(ax, t * 1e3, centres, found, used, m)
    for tt, _, row in _fitted(m, t):
        ax.plot(tt * 1e3, row, color="tab:red", lw=1)
    ax.set(xlabel="time (ms)", ylabel="row (px)",
           title=f"impact {s['impact_speed_m_s']:.3f} m/s, rebound "
                 f"{s['rebound_speed_m_s']:.3f} m/s, COR {s['cor']:.3f}")
    ax.invert_yaxis()
    first, last = m.contact_frames
    ax.axvspan(t[first] * 1e3, t[last] * 1e3, color="0.9", label="contact frames")
    ax.legend(fontsize=7)
    return ax


def plot_measurement(detections: list[Detection], m: Measurement, path: Path) -> None:
    """Write a PNG: `draw_track_image` and `draw_track_time` side by side."""
    fig, (left, right) = subplots(1, 2, figsize=(10, 4.2))
    draw_track_image(left, detections, m)
    draw_track_time(right, detections, m)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
