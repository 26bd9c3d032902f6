"""Impact and rebound speeds from high-speed video (thesis section 3.3, measured there by hand
in Image-Pro Plus): `read_frames`, `track` (background subtraction and a circle fit per
frame), `measure` (free-flight fits before and after contact: speeds, angles and COR with
standard errors), and `synthetic` videos with known answers."""

from pathlib import Path

from .frames import frame_rate, read_frames
from .synthetic import SyntheticImpact, render
from .track import Detection, track
from .trajectory import Measurement, measure


def analyse(path, fps=None, **options) -> tuple[Measurement, list[Detection]]:
    """Read, track and measure a recording; `options` as `measure`'s."""
    frames, fps_file = read_frames(path)
    fps = frame_rate(fps, fps_file, Path(path))
    detections = track(frames)
    return measure(detections, fps, **options), detections


__all__ = ["Detection", "Measurement", "SyntheticImpact", "analyse", "measure", "read_frames", "render", "track"]
