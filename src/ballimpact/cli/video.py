"""`ballimpact video`: impact and rebound speeds from a high-speed recording."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..progress import progress_line
from .common import add_json, print_lines


def add_parser(verbs) -> None:
    video = verbs.add_parser(
        "video", help="impact and rebound speeds, angles and COR from a high-speed video",
        description="Track the ball (background subtraction, circle fit to its edge), fit its "
                    "free flight before and after contact (a line across, a parabola under "
                    "gravity down the image), and report the speeds and angles where each "
                    "trajectory meets the surface, the normal COR, and their standard errors. "
                    "Frames in contact, at the border or with a poor fit are left out. The "
                    "surface is a horizontal row; rows grow downward.")
    video.add_argument("file", type=Path,
                       help="video (MP4, AVI, ... through OpenCV), a folder of images, or .npz")
    video.add_argument("--fps", type=float, help="recording frame rate (frames/s)")
    scale = video.add_mutually_exclusive_group(required=True)
    scale.add_argument("--ball-diameter-m", type=float, help="ball diameter (m), for the scale")
    scale.add_argument("--scale-m-per-px", type=float, help="calibrated scale (m per pixel)")
    video.add_argument("--surface-row", type=float,
                       help="image row of the surface (px; default: the lowest row the ball "
                            "reaches)")
    video.add_argument("--gravity-m-s2", type=float, default=9.81,
                       help="gravity along the image's downward rows (default 9.81; 0: lines)")
    video.add_argument("--side-file", type=Path,
                       help="write the JSON side file of a force record (features, fit, "
                            "identify): impact_speed_m_s and rebound_speed_m_s as the components "
                            "normal to the surface, each phase's normal, tangential and total "
                            "speed and angle, and --mass-kg (docs/video.md)")
    video.add_argument("--mass-kg", type=float, help="ball mass (kg), for the side file")
    video.add_argument("--plot", type=Path, help="write the tracked and fitted trajectory (PNG)")
    add_json(video)


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..video import measure_video
    from ..video.text import measurement_lines

    out = measure_video(args.file, fps=args.fps, scale_m_per_px=args.scale_m_per_px,
                        ball_diameter_m=args.ball_diameter_m, surface_row=args.surface_row,
                        gravity_m_s2=args.gravity_m_s2, side_file_path=args.side_file,
                        mass_kg=args.mass_kg, source=f"ballimpact video {args.file.name}",
                        plot_path=args.plot, log=progress_line)
    if not args.json:
        print_lines(measurement_lines(out))
    return out
