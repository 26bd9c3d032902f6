"""Impact and rebound speeds from high-speed video (thesis section 3.3, measured there by hand
in Image-Pro Plus): `read_frames`, `track` (background subtraction and a circle fit per
frame), `measure` (free-flight fits before and after contact: speeds, angles and COR with
standard errors), and `synthetic` videos with known answers."""

from pathlib import Path

from .frames import frame_rate, read_frames
from .synthetic import SyntheticImpact, render
from .track import Detection, track
from .trajectory import Measurement, check_options, measure, side_file


def analyse(path, fps=None, *, log=None, **options) -> tuple[Measurement, list[Detection]]:
    """Read, track and measure a recording; `options` as `measure`'s, checked before the
    frames are read (`check_options`). `log`, if given, is called with one line once the frames
    are read and the tracking starts."""
    check_options(fps, **options)
    frames, fps_file = read_frames(path)
    fps = frame_rate(fps, fps_file, Path(path))
    if log is not None:
        log(f"tracking {len(frames)} frames of {Path(path).name} ...")
    detections = track(frames)
    return measure(detections, fps, **options), detections


__all__ = ["Detection", "Measurement", "SyntheticImpact", "analyse", "check_options", "measure",
           "read_frames", "render", "side_file", "track"]
