"""Impact and rebound speeds from high-speed video (thesis section 3.3, measured there by hand
in Image-Pro Plus): `read_frames`, `track` (background subtraction and a circle fit per
frame), `measure` (free-flight fits before and after contact: speeds, angles and COR with
standard errors), and `synthetic` videos with known answers."""

from pathlib import Path

from .frames import frame_rate, read_frames
from .synthetic import SyntheticImpact, render
from .track import Detection, track
from .trajectory import (Measurement, check_mass, check_options, check_surface_row, measure,
                         side_file, write_side_file)

#: pixels the tracking goes through per second, for the estimate that decides on a progress
#: line: the slower of the measurements on 2 CPU cores (2.2e6 with another job running; 3.1e6
#: alone, docs/video.md "Speed")
TRACK_PIXELS_PER_S = 2.2e6
#: a progress line is drawn when the tracking is expected to take longer than this (s); shorter
#: runs stay silent, so that a quick failure is one line (README "Command line")
PROGRESS_AFTER_S = 2.0


def analyse(path, fps=None, *, log=None, **options) -> tuple[Measurement, list[Detection]]:
    """Read, track and measure a recording; `options` as `measure`'s, checked before the
    frames are read (`check_options`), and the surface row against the picture's height once
    they are. `log`, if given, is called with one line when the tracking starts, if it is
    expected to take over `PROGRESS_AFTER_S` (every check of the options has passed by then)."""
    check_options(fps, **options)
    frames, fps_file = read_frames(path)
    fps = frame_rate(fps, fps_file, Path(path))
    if getattr(frames, "ndim", 0) == 3:
        check_surface_row(options.get("surface_row"), frames.shape[1])
    expected_s = getattr(frames, "size", 0) / TRACK_PIXELS_PER_S
    if log is not None and expected_s > PROGRESS_AFTER_S:
        log(f"tracking {len(frames)} frames of {Path(path).name} (~{expected_s:.0f} s) ...")
    detections = track(frames)
    return measure(detections, fps, **options), detections


__all__ = ["PROGRESS_AFTER_S", "TRACK_PIXELS_PER_S", "Detection", "Measurement", "SyntheticImpact",
           "analyse", "check_mass", "check_options", "check_surface_row", "measure",
           "read_frames", "render", "side_file", "track", "write_side_file"]
