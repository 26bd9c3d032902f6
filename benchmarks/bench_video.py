"""Cost of the video tracker on this machine, printed as JSON.

A synthetic recording (20 m/s at 5,000 fps, 400 x 320 px, the default of
`ballimpact.video.synthetic`) is tracked and measured. The reference measured in the same run
is one per-pixel median of the frames (the background pass the tracker makes twice).

    python benchmarks/bench_video.py
"""

from __future__ import annotations

import json
import os
import platform
import time

from ballimpact.video import SyntheticImpact, measure, render, track
from ballimpact.video.track import background


def main() -> None:
    impact = SyntheticImpact(speed_m_s=20.0, fps=5000.0)
    frames = render(impact)
    start = time.perf_counter()
    background(frames)
    median = time.perf_counter() - start
    start = time.perf_counter()
    detections = track(frames)
    tracking = time.perf_counter() - start
    start = time.perf_counter()
    measure(detections, impact.fps, ball_diameter_m=impact.ball_diameter_m)
    fitting = time.perf_counter() - start
    print(json.dumps({
        "machine": {"platform": platform.platform(), "cpus": os.cpu_count()},
        "frames": len(frames), "frame_px": list(frames.shape[1:]),
        "track_s": tracking, "frames_per_s": len(frames) / tracking,
        "median_background_s": median, "track_over_median": tracking / median,
        "measure_s": fitting}, indent=2))


if __name__ == "__main__":
    main()
