"""What a backed impact did to what is behind the target (a headform, a hand, a leg): the
backing's speed, peak acceleration, HIC15 and Gadd severity index, and the force transmitted
to it, from an FE run's histories (either geometry: the columns `backing_velocity_z_m_s`,
`backing_acceleration_z_m_s2` and, on a meshed target, `transmitted_force_n`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from .injury import gadd_severity_index, hic15, peak_acceleration_g


def backing_figures(result, histories: bool = True) -> dict[str, Any] | None:
    """The backing's figures of an `fe.ImpactResult` (None without a backing): its speed at
    the end of the run (m/s, away from the ball), peak acceleration (g), HIC15 with its window
    (s) and Gadd severity index over the run, and (with `histories`) its acceleration and
    the transmitted force (N, positive pushing the backing away) against time (s)."""
    h = result.history
    if "backing_acceleration_z_m_s2" not in h:
        return None
    t, a = h["time_s"], h["backing_acceleration_z_m_s2"]
    window = hic15(t, a)
    out = {"backing_speed_m_s": float(-h["backing_velocity_z_m_s"][-1]),
           "backing_peak_acceleration_g": peak_acceleration_g(t, a),
           "hic15": window.value, "hic15_window_s": [window.t1_s, window.t2_s],
           "gadd_severity_index": gadd_severity_index(t, a)}
    force = h.get("transmitted_force_n", h["contact_force_n"])
    out["peak_transmitted_force_n"] = float(np.max(force))
    if histories:
        out["history"] = {"time_s": t.tolist(), "acceleration_m_s2": (-a).tolist(),
                          "transmitted_force_n": force.tolist()}
    return out
