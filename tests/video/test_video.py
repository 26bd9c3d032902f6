"""Speeds from high-speed video (issue: video): synthetic recordings with known speeds, angles
and COR; the side file; bad input."""

import json

import numpy as np
import pytest

from ballimpact.cli import main
from ballimpact.errors import InputError
from ballimpact.records.loaders import load_record
from ballimpact.records.pulses import half_sine
from ballimpact.video import SyntheticImpact, analyse, measure, render, track
from ballimpact.video.trajectory import check_speeds
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
    assert record.impact_speed_m_s == pytest.approx(result["impact_speed_normal_m_s"])
    assert record.rebound_speed_m_s == pytest.approx(result["rebound_speed_normal_m_s"])
    assert record.mass_kg == 0.16
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
    cases.append(((late, "--scale-m-per-px", 0.001, "--fps", -5), "--fps = -5: allowed range (0, inf)"))
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


def test_oblique_shot_side_file_gives_the_normal_cor_in_features(tmp_path, capsys):
    """A 20-degree shot, normal COR 0.5 and tangential 0.8: the total speeds' ratio is 0.544,
    the normal components' 0.500. The side file's impact_speed_m_s and rebound_speed_m_s are
    the normal components, so `features` gives COR 0.500 and the impulse of a force record
    made for the normal speeds passes its check."""
    impact = SyntheticImpact(speed_m_s=20.0, fps=2000.0, angle_deg=20.0, cor_normal=0.5,
                             cor_tangential=0.8, **SMALL)
    npz = tmp_path / "shot.npz"
    write_frames_npz(npz, render(impact), impact.fps)
    side = tmp_path / "shot.json"
    code, out, err = run(capsys, "video", npz, "--fps", 2000, "--ball-diameter-m", 0.072,
                         "--side-file", side, "--mass-kg", 0.16, "--json")
    assert code == 0, err
    written = json.loads(side.read_text())
    v_in, v_out = impact.velocities_px_s()
    truth = {"impact": (v_in[1], v_in[0]), "rebound": (-v_out[1], v_out[0])}
    for phase, (normal, tangential) in truth.items():
        scale = impact.scale_m_per_px
        assert written[f"{phase}_speed_m_s"] == written[f"{phase}_speed_normal_m_s"]
        assert written[f"{phase}_speed_normal_m_s"] == pytest.approx(normal * scale, rel=0.01)
        assert written[f"{phase}_speed_tangential_m_s"] == pytest.approx(tangential * scale,
                                                                          rel=0.01)
        assert written[f"{phase}_speed_total_m_s"] == pytest.approx(
            np.hypot(normal, tangential) * scale, rel=0.01)
    assert written["impact_angle_deg"] == pytest.approx(20.0, abs=0.5)
    assert written["mass_kg"] == 0.16
    assert written["rebound_speed_total_m_s"] / written["impact_speed_total_m_s"] == \
        pytest.approx(0.544, abs=0.005)  # what features read before: the totals' ratio
    # a force record for the true normal speeds: impulse m (v_n,in + v_n,out), a 1 ms half-sine
    impulse = 0.16 * (normal_in := v_in[1] * impact.scale_m_per_px) * 1.5
    record = half_sine(np.pi * impulse / 2e-3, 1e-3, 200e3)
    csv = side.with_suffix(".csv")
    csv.write_text("time_s,force_n\n" + "".join(f"{t:.9e},{f:.9g}\n"
                                                for t, f in zip(record.time_s, record.force_n)))
    code, out, err = run(capsys, "features", csv, "--json")
    assert code == 0, err
    result = json.loads(out)
    assert result["cor"] == pytest.approx(0.500, abs=0.002)
    assert result["impact_speed_m_s"] == pytest.approx(normal_in, rel=0.005)
    assert result["impulse_check_passed"] is True


def test_video_options_are_checked_before_any_frame_is_read(tmp_path):
    """The Python API refuses what the command line refuses, before reading the (absent)
    recording: the error is about the option, not the missing file."""
    missing = tmp_path / "absent.npz"
    cases = [({"fps": 5000, "ball_diameter_m": 72.0}, "looks like millimetres; use 0.072"),
             ({"fps": 5000, "scale_m_per_px": 0.001, "gravity_m_s2": float("nan")},
              "gravity_m_s2"),
             ({"fps": 5000, "scale_m_per_px": 0.001, "gravity_m_s2": 9810.0}, "mm/s^2"),
             ({"fps": float("inf"), "scale_m_per_px": 0.001}, "fps"),
             ({"fps": 5000, "scale_m_per_px": float("nan")}, "scale_m_per_px"),
             ({"fps": 5000, "scale_m_per_px": 0.001, "surface_row": float("nan")},
              "surface_row")]
    for options, message in cases:
        with pytest.raises(InputError, match=message.replace("^", r"\^")):
            analyse(missing, **options)


def test_speeds_no_ball_reaches_are_errors_naming_the_slip():
    """Above 100 m/s or not finite: the scale or the frame rate is wrong. A given scale that
    makes the ball 72 m across is in mm per pixel."""
    summary = {"impact_speed_m_s": 20.0, "rebound_speed_m_s": 10.0, "fps": 5000.0,
               "scale_m_per_px": 0.00225, "ball_radius_px": 16.0, "scale_from": "given"}
    check_speeds(summary)
    with pytest.raises(InputError, match="19965 m/s is above 100 m/s.*--fps 5000"):
        check_speeds({**summary, "impact_speed_m_s": 19965.0})
    with pytest.raises(InputError, match="rebound speed is not finite"):
        check_speeds({**summary, "rebound_speed_m_s": float("nan")})
    with pytest.raises(InputError, match="72 m across.*millimetres per pixel"):
        check_speeds({**summary, "scale_m_per_px": 2.25})
