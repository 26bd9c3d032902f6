"""Issue 39 C: `export --ball-only` says the impact's flags are ignored; `video` refuses a
surface row outside the picture by name, before any progress line."""

import numpy as np

from ballimpact.cli import main
from ballimpact.video import PROGRESS_AFTER_S, SyntheticImpact, render
from ballimpact.video.frames import write_frames_npz

SMALL = dict(width_px=300, height_px=240, surface_row=225.0, scale_m_per_px=0.00225,
             travel_diameters=3.0)


def test_export_ball_only_warns_that_impact_flags_are_ignored(tmp_path, capsys):
    out = tmp_path / "ball.inp"
    capsys.readouterr()
    assert main(["export", "--ball", "cricket-3layer", "--format", "calculix", "--ball-only",
                 "--angle-deg", "30", "--friction", "0.3", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    warnings = [line for line in err.splitlines() if line.startswith("warning:")]
    assert warnings == ["warning: --angle-deg, --friction: ignored with --ball-only (the file "
                        "holds the ball alone, no impact); they set a complete deck's impact"]
    assert "*NODE" in out.read_text().upper()
    # without them, no warning; and a complete deck takes them without one
    assert main(["export", "--ball", "cricket-3layer", "--format", "calculix", "--ball-only",
                 "--out", str(out)]) == 0
    assert "warning:" not in capsys.readouterr().err
    deck = tmp_path / "deck.inp"
    assert main(["export", "--ball", "cricket-3layer", "--format", "abaqus", "--speed-m-s", "20",
                 "--friction", "0.3", "--out", str(deck), "--json"]) == 0
    captured = capsys.readouterr()
    assert "warning:" not in captured.err and '"friction": 0.3' in captured.out


def test_video_surface_row_outside_the_picture_is_refused_by_name(tmp_path, bad_input):
    impact = SyntheticImpact(speed_m_s=20.0, fps=5000.0, **SMALL)
    npz = tmp_path / "shot.npz"
    write_frames_npz(npz, render(impact), 5000)
    base = ["video", npz, "--fps", 5000, "--scale-m-per-px", impact.scale_m_per_px]
    bad_input([*base, "--surface-row", -5], "--surface-row) = -5: allowed range [0, inf) px")
    # known once the frames are read: the picture is 240 rows high
    bad_input([*base, "--surface-row", 400], "--surface-row) = 400: allowed range [0, 239] px")


def test_video_quick_failure_is_one_line_without_progress(tmp_path, bad_input):
    rng = np.random.default_rng(1)
    empty = tmp_path / "empty.npz"
    frames = (100 + 3 * rng.standard_normal((20, 60, 80))).astype(np.uint8)
    write_frames_npz(empty, frames, 5000)
    assert frames.size / 2.2e6 < PROGRESS_AFTER_S
    bad_input(["video", empty, "--fps", 5000, "--scale-m-per-px", 0.001],
              "found whole in 0 of 20")
