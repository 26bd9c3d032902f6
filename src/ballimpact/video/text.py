"""The text of a video measurement, as `ballimpact video` prints it: the lines (without their
line ends), so that a Python user gets the command's text."""

from __future__ import annotations

from typing import Any


def measurement_lines(out: dict[str, Any]) -> list[str]:
    """`measure_video`'s result: the impact and rebound speeds and angles with their standard
    errors, the COR, the components normal to the surface and the side file written."""
    side = f" (the side file's speeds: {out['side_file']})" if out.get("side_file") else ""
    return [f"impact  {out['impact_speed_m_s']:.3f} +- {out['impact_speed_se_m_s']:.3f} m/s at "
            f"{out['impact_angle_deg']:.2f} +- {out['impact_angle_se_deg']:.2f} deg from the "
            f"normal ({out['frames_before']} frames)",
            f"rebound {out['rebound_speed_m_s']:.3f} +- {out['rebound_speed_se_m_s']:.3f} m/s "
            f"at {out['rebound_angle_deg']:.2f} +- {out['rebound_angle_se_deg']:.2f} deg "
            f"({out['frames_after']} frames); COR {out['cor']:.4f} +- {out['cor_se']:.4f}",
            f"normal to the surface: impact {out['impact_speed_normal_m_s']:.3f} m/s, rebound "
            f"{out['rebound_speed_normal_m_s']:.3f} m/s{side}"]


__all__ = ["measurement_lines"]
