"""Impact and rebound speeds from high-speed video (thesis section 3.3, measured there by hand
in Image-Pro Plus): `read_frames`, `track` (background subtraction and a circle fit per
frame), `measure` (free-flight fits before and after contact: speeds, angles and COR with
standard errors), `measure_video` (all of them, with the side file and the plot: `ballimpact
video`), and `synthetic` videos with known answers."""

from pathlib import Path

from ..checks import check_range
from ..errors import InputError
from ..fileio import check_output_folder, check_plot_path
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


def measure_video(path, *, fps: float | None = None, scale_m_per_px: float | None = None,
                  ball_diameter_m: float | None = None, surface_row: float | None = None,
                  gravity_m_s2: float = 9.81, side_file_path: Path | None = None,
                  mass_kg: float | None = None, source: str | None = None,
                  plot_path: Path | None = None, log=None) -> dict:
    """`analyse` the recording at `path` (`fps` in frames/s; the scale by `scale_m_per_px` or
    `ball_diameter_m` in m; `surface_row` in px; `gravity_m_s2` along the rows) and return
    `Measurement.summary`; with `side_file_path` (.json) the force record's side file written
    (`write_side_file`, with `mass_kg` and `source`) and its path under `side_file`; with
    `plot_path` (PNG) the tracked and fitted trajectory drawn. `InputError`, before anything is
    read, for a bad output path, mass or frame rate, and the errors of `analyse`."""
    check_plot_path(plot_path)
    if side_file_path is not None:
        check_output_folder(side_file_path, "--side-file")
        if side_file_path.suffix.lower() != ".json":
            raise InputError(f"--side-file: {side_file_path} must end in .json (the force "
                             "record's name with .json: test1.csv -> test1.json)")
    if mass_kg is not None:
        check_mass(mass_kg)
    if fps is not None:
        check_range("--fps", fps, 0.0, low_open=True, note="frames per second")
    # analyse checks the options before it reads or tracks anything
    m, detections = analyse(path, fps, scale_m_per_px=scale_m_per_px,
                            ball_diameter_m=ball_diameter_m, surface_row=surface_row,
                            gravity_m_s2=gravity_m_s2, log=log)
    out = dict(m.summary)
    if side_file_path is not None:
        out["side_file"] = write_side_file(side_file_path, m.summary, mass_kg, source=source)
    if plot_path is not None:
        from .plots import plot_measurement

        plot_measurement(detections, m, plot_path)
    return out


__all__ = ["PROGRESS_AFTER_S", "TRACK_PIXELS_PER_S", "Detection", "Measurement", "SyntheticImpact",
           "analyse", "check_mass", "check_options", "check_surface_row", "measure",
           "measure_video", "read_frames", "render", "side_file", "track", "write_side_file"]
