"""Bad input to the verbs that read records, side files and videos (issue 24): a careless user's
mistakes each end in one line naming the file, field or flag and the fix (exit code 2), before
anything long runs. The `bad_input` fixture (conftest.py) checks the contract."""

import json

import numpy as np
import pytest
from scipy.io import wavfile

from ballimpact.records.pulses import KelvinVoigt

BALL = KelvinVoigt(mass_kg=0.16, stiffness_n_m=1.5e6, damping_n_s_m=60.0, impact_speed_m_s=10.0)
SPEEDS = ["--mass-kg", 0.16, "--impact-speed-m-s", 10]


def write(path, text):
    path.write_text(text)
    return path


def record_csv(path, force_factor=1.0, side=None):
    """The spring-dashpot ball's pulse at 200 kHz as a CSV (and its side file, if given)."""
    record = BALL.record(200e3)
    rows = "".join(f"{t:.9e},{f * force_factor:.9g}\n" for t, f in zip(record.time_s,
                                                                       record.force_n))
    path.write_text("time_s,force_n\n" + rows)
    if side is not None:
        path.with_suffix(".json").write_text(json.dumps(side))
    return path


@pytest.fixture
def test_csv(tmp_path):
    return record_csv(tmp_path / "kv.csv")


# --------------------------------------------------------------------------- the record file


@pytest.mark.parametrize(("text", "fragments"), [
    ("", ("empty.csv", "the file is empty")),
    ("time,force\n0,0\n1,1\n2,0\n", ("column 'time' has no unit", "time_s, time_ms")),
    ("time_s,force_n\n0,0\n2,1\n1,0\n", ("time_s: must be strictly increasing", "decreasing")),
    ("time_s,force_n\n0,5\n", ("time_s: need at least 3 samples, got 1",)),
    ("time_s,force_n\n0,0\n1,NaN\n2,0\n", ("line 3, column force_n", "not a finite number")),
    ("time_s;force_n\n0;0\n1;1\n2;0\n", ("separated by semicolons", "commas")),
    # a table another verb wrote (fit --table): not a record
    ("impact_speed_m_s,k [N/m],label\n10,1e6,a.csv\n", ("a table of results", "force record")),
])
def test_careless_csv_files(bad_input, tmp_path, text, fragments):
    name = "empty.csv" if not text else "bad.csv"
    bad_input(["features", write(tmp_path / name, text), *SPEEDS], *fragments)


def test_missing_file_and_folder_and_json(bad_input, tmp_path, test_csv):
    bad_input(["features", tmp_path / "nope.csv", *SPEEDS], "nope.csv: no such file")
    empty = tmp_path / "empty"
    empty.mkdir()
    bad_input(["features", empty, *SPEEDS], "holds no test records", ".csv")
    side = write(tmp_path / "kv.json", json.dumps({"mass_kg": 0.16}))
    bad_input(["features", side, *SPEEDS], "kv.json", "side file", "not a test record")


def test_inverted_polarity_names_the_fix_not_clipping(bad_input, tmp_path):
    path = record_csv(tmp_path / "inverted.csv", force_factor=-1.0)
    line = bad_input(["features", path, *SPEEDS], "inverted.csv", "polarity looks inverted",
                     "negate the force column")
    assert "clipped" not in line


def test_inverted_wav_names_a_negative_sensitivity(bad_input, tmp_path):
    record = BALL.record(200e3)
    path = tmp_path / "inverted.wav"
    wavfile.write(path, 200000, (-record.force_n * 1e-4 * 32767).astype(np.int16))
    bad_input(["features", path, *SPEEDS, "--sensitivity-v-per-n", 1e-4],
              "polarity looks inverted", "--sensitivity-v-per-n -")


# --------------------------------------------------------------------------- processing options


@pytest.mark.parametrize(("options", "fragments"), [
    (["--pulse", 0], ("kv.csv", "pulse: 0 out of range 1..1")),
    (["--pulse", 3], ("pulse: 3 out of range 1..1", "holds 1 pulse")),
    (["--filter", "median"], ("filter: unknown name 'median'", "loess")),
    (["--filter", "loess", "--filter-window-s=-1e-4"], ("--filter-window-s", "(0, inf)")),
    (["--filter", "cfc10000", "--filter-window-s", 1e-4], ("--filter-window-s", "has no window",
                                                           "savgol, lowess, loess")),
    (["--resample-hz=-2e5"], ("--resample-hz", "(0, inf)")),
    (["--impulse-tolerance", 0], ("impulse_tolerance", "(0, inf)")),
])
def test_careless_processing_options(bad_input, test_csv, options, fragments):
    bad_input(["features", test_csv, *SPEEDS, *options], *fragments)


@pytest.mark.parametrize(("scalars", "fragments"), [
    (["--mass-kg", 0, "--impact-speed-m-s", 10], ("mass_kg = 0: allowed range (0, inf)",)),
    (["--mass-kg=-0.16", "--impact-speed-m-s", 10], ("mass_kg = -0.16",)),
    (["--mass-kg", 0.16, "--impact-speed-m-s=-10"], ("impact_speed_m_s = -10", "(0, inf)")),
    (["--mass-kg", 0.16, "--impact-speed-m-s", 10, "--rebound-speed-m-s=-1"],
     ("rebound_speed_m_s = -1", "[0, inf)")),
    (["--impact-speed-m-s", 10], ("mass_kg: the ball mass is required",)),
])
def test_careless_scalars(bad_input, test_csv, scalars, fragments):
    bad_input(["features", test_csv, *scalars], *fragments)


def test_wav_without_sensitivity_or_with_zero(bad_input, tmp_path):
    path = tmp_path / "pulse.wav"
    wavfile.write(path, 200000, (BALL.record(200e3).force_n * 1e-4 * 32767).astype(np.int16))
    bad_input(["features", path, *SPEEDS], "pulse.wav", "needs the load-cell sensitivity",
              "--sensitivity-v-per-n")
    bad_input(["features", path, *SPEEDS, "--sensitivity-v-per-n", 0], "pulse.wav",
              "sensitivity_v_per_n: must be finite and not 0")
    # 94.42 mV/kN typed as V/N: the forces a million times too small, the slip named
    bad_input(["features", path, *SPEEDS, "--sensitivity-v-per-n", 94.42], "pulse.wav",
              "sensitivity in mV/kN given as V/N")
    # 0.1 V/kN typed as V/N: the forces a thousand times too SMALL, as for mV/N
    bad_input(["features", path, *SPEEDS, "--sensitivity-v-per-n", 0.1], "pulse.wav",
              "sensitivity in mV/N or V/kN given as V/N")


# --------------------------------------------------------------------------- side files


@pytest.mark.parametrize(("side", "fragments"), [
    ({"mass_kg": "0.16", "impact_speed_m_s": 10}, ("kv.json", "mass_kg", "expected a JSON number")),
    ({"mass_kg": 0.16, "speed": 10}, ("unknown key 'speed'", "impact_speed_m_s")),
    ({"mass_kg": 0.16, "impact_speed_total_m_s": 10.6},
     ("impact_speed_total_m_s is the total speed", "impact_speed_normal_m_s")),
    ({"mass_kg": 0.16, "impact_speed_normal_m_s": 10, "impact_speed_tangential_m_s": 9,
      "impact_speed_total_m_s": 10.6}, ("do not add up",)),
    ({"mass_kg": 0.16, "impact_speed_total_m_s": 10.6, "impact_angle_deg": 120},
     ("impact_angle_deg", "between -90 and 90")),
    # simulate's JSON without its mass (an edited or older file): what to add
    ({"ball": "cricket-universal", "impact_speed_m_s": 10, "cor": 0.5}, ('add "mass_kg"',)),
])
def test_careless_side_files(bad_input, tmp_path, side, fragments):
    path = record_csv(tmp_path / "kv.csv", side=side)
    bad_input(["features", path], *fragments)


# --------------------------------------------------------------------------- video


@pytest.fixture
def frames_npz(tmp_path):
    """A small .npz of frames (nothing is tracked: every case fails before)."""
    path = tmp_path / "shot.npz"
    np.savez_compressed(path, frames=np.zeros((4, 16, 16), np.uint8), fps_hz=5000.0)
    return path


@pytest.mark.parametrize(("options", "fragments"), [
    # the diameter typed in mm gave 19,965 m/s: now the slip is named before tracking
    (["--fps", 5000, "--ball-diameter-m", 72], ("--ball-diameter-m", "looks like millimetres",
                                                "0.072")),
    (["--fps", 5000, "--scale-m-per-px", 0.001, "--gravity-m-s2", "nan"], ("gravity",)),
    (["--fps", 5000, "--scale-m-per-px", 0.001, "--gravity-m-s2", 9810], ("--gravity-m-s2",
                                                                          "m/s^2")),
    (["--fps", "inf", "--scale-m-per-px", 0.001], ("fps",)),
    (["--fps", 5000, "--scale-m-per-px", 0], ("--scale-m-per-px", "(0, inf)")),
    (["--fps", 5000, "--scale-m-per-px", 0.001, "--surface-row", "nan"], ("surface",)),
    (["--fps", 5000, "--scale-m-per-px", 0.001, "--mass-kg=-0.16"], ("--mass-kg = -0.16",
                                                                   "(0, inf) kg")),
    # the mass in grams: named before tracking, not only later by the force record's impulse
    (["--fps", 5000, "--scale-m-per-px", 0.001, "--mass-kg", 160], ("--mass-kg",
                                                                     "looks like grams", "0.16")),
    (["--fps", 5000, "--scale-m-per-px", 0.001, "--side-file", "speeds.txt"],
     ("--side-file", "must end in .json")),
    (["--fps", 5000], ("--ball-diameter-m", "--scale-m-per-px")),
])
def test_careless_video_options(bad_input, frames_npz, options, fragments):
    bad_input(["video", frames_npz, *options], *fragments)


def test_video_file_mistakes(bad_input, tmp_path):
    bad_input(["video", tmp_path / "shot.avi", "--fps", 5000, "--scale-m-per-px", 0.001],
              "shot.avi", "no such file")
    empty = tmp_path / "frames"
    empty.mkdir()
    bad_input(["video", empty, "--fps", 5000, "--scale-m-per-px", 0.001], "no images")
    bad_input(["video", empty, "--fps", 5000, "--scale-m-per-px", 0.001, "--side-file",
               tmp_path / "no" / "shot.json"], "--side-file", "does not exist")
