"""Speeds from high-speed video (issue: video): synthetic recordings with known speeds, angles
and COR; the side file; bad input."""

import json

import numpy as np
import pytest

from ballimpact.cli import main
from ballimpact.errors import InputError
from ballimpact.loaders import load_record
from ballimpact.video import SyntheticImpact, analyse, measure, render, track
from ballimpact.video.frames import write_frames_npz

#: a smaller picture than the default (faster); the ball 32 px across
SMALL = dict(width_px=300, height_px=240, surface_row=225.0, scale_m_per_px=0.00225,
             travel_diameters=3.0)


def run(capsys, *argv):
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


def check(result, impact, speed_rel=0.01, angle_deg=0.5):
    truth = impact.truth()
    for key in ("impact_speed_m_s", "rebound_speed_m_s"):
        assert result[key] == pytest.approx(truth[key], rel=speed_rel), key
    for key in ("impact_angle_deg", "rebound_angle_deg"):
        assert result[key] == pytest.approx(truth[key], abs=angle_deg), key
    assert result["cor"] == pytest.approx(truth["cor"], rel=speed_rel)


@pytest.mark.parametrize("speed, fps, angle", [(40.0, 2000.0, 30.0), (20.0, 5000.0, 10.0),
                                               (12.0, 5000.0, 45.0), (8.0, 2000.0, 0.0)])
def test_synthetic_speeds_within_1_percent_and_angles_within_half_a_degree(speed, fps, angle):
    impact = SyntheticImpact(speed_m_s=speed, fps=fps, angle_deg=angle, noise=4.0, **SMALL)
    detections = track(render(impact))
    for scale in ({"scale_m_per_px": impact.scale_m_per_px},
                  {"ball_diameter_m": impact.ball_diameter_m}):
        m = measure(detections, fps, **scale)
        check(m.summary, impact)
        assert m.summary["frames_before"] >= 5 and m.summary["frames_after"] >= 5


def test_standard_errors_cover_the_error_with_a_calibrated_scale():
    """With the scale given, what is left is the centres' scatter: the stated standard errors
    must cover the measured errors (within 4 SE, over noise levels)."""
    for noise in (2.0, 8.0):
        impact = SyntheticImpact(speed_m_s=20.0, fps=5000.0, angle_deg=20.0, noise=noise, **SMALL)
        s = measure(track(render(impact)), impact.fps, scale_m_per_px=impact.scale_m_per_px).summary
        truth = impact.truth()
        for key in ("impact_speed", "rebound_speed"):
            error = abs(s[f"{key}_m_s"] - truth[f"{key}_m_s"])
            assert error <= 4 * s[f"{key}_se_m_s"] + 2e-4 * truth[f"{key}_m_s"], (noise, key)
        # and the scatter grows with the noise
        assert s["centre_residual_px"][0] < 0.5


def test_gravity_matters_at_low_speed_and_is_modelled():
    impact = SyntheticImpact(speed_m_s=5.0, fps=2000.0, angle_deg=0.0,
                             **{**SMALL, "travel_diameters": 4.0, "height_px": 360,
                                "surface_row": 340.0})
    detections = track(render(impact))
    with_g = measure(detections, impact.fps, scale_m_per_px=impact.scale_m_per_px).summary
    without = measure(detections, impact.fps, scale_m_per_px=impact.scale_m_per_px,
                      gravity_m_s2=0.0).summary
    truth = impact.truth()
    assert with_g["impact_speed_m_s"] == pytest.approx(truth["impact_speed_m_s"], rel=0.002)
    # straight lines average the speed over the frames used: off by about g t / 2
    assert abs(without["impact_speed_m_s"] / truth["impact_speed_m_s"] - 1) > 0.005


def test_cli_reads_images_and_video_files_and_writes_a_side_file(tmp_path, capsys):
    cv2 = pytest.importorskip("cv2", reason="OpenCV (the video extra) is not installed")
    impact = SyntheticImpact(speed_m_s=20.8, fps=5000.0, angle_deg=0.0, cor_normal=0.55, **SMALL)
    frames = render(impact)
    npz = tmp_path / "shot.npz"
    write_frames_npz(npz, frames, impact.fps)
    avi = tmp_path / "shot.avi"
    writer = cv2.VideoWriter(str(avi), cv2.VideoWriter_fourcc(*"MJPG"), 30.0,
                             (frames.shape[2], frames.shape[1]), isColor=False)
    for frame in frames:
        writer.write(frame)
    writer.release()
    side, plot = tmp_path / "record.json", tmp_path / "track.png"
    code, out, err = run(capsys, "video", avi, "--fps", 5000, "--ball-diameter-m", 0.072,
                         "--side-file", side, "--mass-kg", 0.16, "--plot", plot, "--json")
    assert code == 0, err
    result = json.loads(out)
    check(result, impact)
    assert plot.stat().st_size > 10_000
    # the side file feeds the force record's processing (features, fit, identify)
    from importlib.resources import files
    record_csv = tmp_path / "record.csv"
    record_csv.write_text(files("ballimpact.data").joinpath("sample_impact.csv").read_text())
    record = load_record(record_csv)
    assert record.impact_speed_m_s == pytest.approx(result["impact_speed_m_s"])
    assert record.rebound_speed_m_s == pytest.approx(result["rebound_speed_m_s"])
    # the .npz (frame rate inside, with a warning to give --fps) and a folder of images
    code, out, err = run(capsys, "video", npz, "--scale-m-per-px", impact.scale_m_per_px)
    assert code == 0 and "give --fps" in err and "COR 0.55" in out
    folder = tmp_path / "frames"
    folder.mkdir()
    import matplotlib.image as mpimg
    for i, frame in enumerate(frames):
        mpimg.imsave(folder / f"f{i:04d}.png", frame, cmap="gray", vmin=0, vmax=255)
    code, out, err = run(capsys, "video", folder, "--fps", 5000, "--ball-diameter-m", 0.072,
                         "--json")
    assert code == 0, err
    check(json.loads(out), impact)


def test_bad_video_input_exits_2(tmp_path, capsys):
    pytest.importorskip("cv2", reason="OpenCV (the video extra) is not installed")
    text = tmp_path / "notes.mp4"
    text.write_text("not a video")
    cases = [((text, "--fps", 5000, "--scale-m-per-px", 0.001), "unreadable video")]
    empty = tmp_path / "empty.npz"
    rng = np.random.default_rng(1)
    write_frames_npz(empty, (100 + 3 * rng.standard_normal((20, 60, 80))).astype(np.uint8), 5000)
    cases.append(((empty, "--fps", 5000, "--scale-m-per-px", 0.001), "found whole in 0 of 20"))
    impact = SyntheticImpact(speed_m_s=20.0, fps=5000.0, **SMALL)
    frames = render(impact)
    late = tmp_path / "late.npz"   # the recording starts 3 frames before contact
    first_contact = int(np.argmin(np.abs(impact.frame_times_s())))
    write_frames_npz(late, frames[first_contact - 3:], 5000)
    cases.append(((late, "--fps", 5000, "--scale-m-per-px", impact.scale_m_per_px),
                  "usable frames before the impact"))
    cases.append(((tmp_path / "missing.avi", "--fps", 5000, "--scale-m-per-px", 0.001),
                  "no such file or folder"))
    folder = tmp_path / "pngs"
    folder.mkdir()
    cases.append(((folder, "--fps", 5000, "--scale-m-per-px", 0.001), "no images"))
    cases.append(((late, "--scale-m-per-px", 0.001, "--fps", -5), "--fps = -5.0: must be > 0"))
    for argv, message in cases:
        code, _, err = run(capsys, "video", *argv)
        assert code == 2, (message, err)
        assert message in err, err
    with pytest.raises(InputError, match="exactly one of"):
        measure(track(frames), 5000.0)
    with pytest.raises(InputError, match="frame rate is unknown"):
        folder_png = tmp_path / "one"
        folder_png.mkdir()
        import matplotlib.image as mpimg
        mpimg.imsave(folder_png / "a.png", frames[0], cmap="gray")
        analyse(folder_png, None, scale_m_per_px=0.001)
