"""The accuracy table of docs/video.md: synthetic recordings (a shaded ball on a textured
background, motion blur, noise) over impact speeds and frame rates, measured with the scale
given and from the ball's diameter; the error against the truth next to the stated standard
error (the error budget). Prints JSON.

    python examples/video_accuracy.py [--speeds-m-s 5 10 20 40] [--fps 2000 5000 20000]
"""

from __future__ import annotations

import argparse
import json
import sys
import time

from ballimpact.video import SyntheticImpact, measure, render, track


def case(speed: float, fps: float, angle: float, noise: float) -> dict:
    impact = SyntheticImpact(speed_m_s=speed, fps=fps, angle_deg=angle, noise=noise)
    start = time.perf_counter()
    frames = render(impact)
    detections = track(frames)
    tracking = time.perf_counter() - start
    truth = impact.truth()
    row = {"speed_m_s": speed, "fps": fps, "angle_deg": angle, "noise_grey_levels": noise,
           "frames": len(frames), "render_and_track_s": tracking}
    for label, scale in (("scale_given", {"scale_m_per_px": impact.scale_m_per_px}),
                         ("from_diameter", {"ball_diameter_m": impact.ball_diameter_m})):
        s = measure(detections, fps, **scale).summary
        row[label] = {
            "impact_speed_error": s["impact_speed_m_s"] / truth["impact_speed_m_s"] - 1,
            "impact_speed_se": s["impact_speed_se_m_s"] / truth["impact_speed_m_s"],
            "rebound_speed_error": s["rebound_speed_m_s"] / truth["rebound_speed_m_s"] - 1,
            "rebound_speed_se": s["rebound_speed_se_m_s"] / truth["rebound_speed_m_s"],
            "impact_angle_error_deg": s["impact_angle_deg"] - truth["impact_angle_deg"],
            "rebound_angle_error_deg": s["rebound_angle_deg"] - truth["rebound_angle_deg"],
            "cor_error": s["cor"] - truth["cor"], "cor_se": s["cor_se"],
            "centre_residual_px": s["centre_residual_px"],
            "frames_before": s["frames_before"], "frames_after": s["frames_after"]}
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds-m-s", type=float, nargs="+", default=[5.0, 10.0, 20.0, 40.0])
    parser.add_argument("--fps", type=float, nargs="+", default=[2000.0, 5000.0, 20000.0])
    parser.add_argument("--angle-deg", type=float, default=20.0)
    parser.add_argument("--noise", type=float, default=4.0)
    args = parser.parse_args()
    rows = []
    for speed in args.speeds_m_s:
        for fps in args.fps:
            print(f"{speed:g} m/s at {fps:g} fps ...", file=sys.stderr)
            rows.append(case(speed, fps, args.angle_deg, args.noise))
    print(json.dumps({"cases": rows}, indent=2))


if __name__ == "__main__":
    main()
