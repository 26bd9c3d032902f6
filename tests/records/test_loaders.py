"""Loaders: CSV units, WAV conversion with sensitivity and gain, JSON side files."""

import json

import numpy as np
import pytest
from scipy.io import wavfile

from ballimpact import InputError, load_record
from ballimpact.records.pulses import half_sine

# the thesis' rig: PCB 223A, 94.42 mV/kN, charge amplifier gain 10
SENSITIVITY_V_PER_N, GAIN = 94.42e-3 / 1e3, 10.0


def test_csv_units_are_converted_to_si(tmp_path):
    path = tmp_path / "test.csv"
    path.write_text("# a comment\ntime_ms,force_kn,velocity_m_s\n0,0,5\n0.5,1.5,0\n1.0,0,-4\n")
    record = load_record(path, mass_kg=0.16)
    assert np.allclose(record.time_s, [0, 5e-4, 1e-3])
    assert np.allclose(record.force_n, [0, 1500, 0])
    assert np.allclose(record.velocity_m_s, [5, 0, -4])
    assert record.mass_kg == 0.16


def test_side_file_supplies_scalars_and_arguments_win(tmp_path):
    (tmp_path / "drop.csv").write_text("time_us,force_n\n0,0\n10,5\n20,0\n")
    (tmp_path / "drop.json").write_text(json.dumps(
        {"mass_kg": 0.156, "impact_speed_m_s": 6.5, "rebound_speed_m_s": 3.9}))
    record = load_record(tmp_path / "drop.csv", impact_speed_m_s=7.0)
    assert (record.mass_kg, record.impact_speed_m_s, record.rebound_speed_m_s) == (0.156, 7.0, 3.9)
    (tmp_path / "drop.json").write_text('{"mass_g": 156}')
    with pytest.raises(InputError, match="unknown key 'mass_g'"):
        load_record(tmp_path / "drop.csv")


@pytest.mark.parametrize("dtype", [np.int16, np.int32, np.float32])
def test_wav_volts_to_newtons(tmp_path, dtype):
    """A 5 kN half-sine through the thesis' sensor and amplifier, written as WAV and read back:
    the force is recovered to the WAV's quantisation (1e-3 of the peak for 16-bit)."""
    pulse = half_sine(5e3, 1e-3, 48e3)
    volts = pulse.force_n * SENSITIVITY_V_PER_N * GAIN  # 4.7 V at the peak
    full_scale = 10.0
    fraction = volts / full_scale
    data = (fraction * np.iinfo(dtype).max).astype(dtype) if dtype != np.float32 else fraction.astype(dtype)
    path = tmp_path / "pulse.wav"
    wavfile.write(path, 48000, data)
    record = load_record(path, sensitivity_v_per_n=SENSITIVITY_V_PER_N, amplifier_gain=GAIN,
                         full_scale_v=full_scale)
    assert record.time_s[1] == pytest.approx(1 / 48000)
    assert np.max(np.abs(record.force_n - pulse.force_n)) < 1e-3 * 5e3


def test_malformed_wav_is_an_input_error(tmp_path):
    path = tmp_path / "garbage.wav"
    path.write_bytes(b"RIFF\x24\x00\x00\x00WAVEdata\x00\x00\x00\x00")
    with pytest.raises(InputError, match="not a readable WAV file"):
        load_record(path, sensitivity_v_per_n=1e-4)


def test_wav_without_sensitivity_is_an_input_error(tmp_path):
    path = tmp_path / "pulse.wav"
    wavfile.write(path, 48000, np.zeros(100, dtype=np.int16))
    with pytest.raises(InputError, match="sensitivity_v_per_n: a WAV file needs"):
        load_record(path)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "the file is empty"),
        ("# only a comment\n", "the file is empty"),
        ("time,force\n0,0\n", "column 'time' has no unit; use one of time_s, time_ms, time_us"),
        ("time_s,force_kip\n0,0\n", "unknown column 'force_kip'"),
        ("0,0\n1,2\n", "first line is not a header"),
        ("time_s\n0\n", "no force column"),
        ("time_s,force_n\n", "no samples"),
        ("time_s,force_n\n0,0\n1,2,3\n", "line 3 has 3 values"),
        ("time_s,force_n\n0,0\n1,abc\n", "line 3, column force_n: 'abc' is not a number"),
        ("time_s,force_n\n0,0\n1,nan\n2,0\n", "line 3, column force_n: 'nan' is not a finite"),
        ("time_s,force_n\n0,0\n1,2\n1,0\n", "time_s: must be strictly increasing"),
        ("time_s,time_ms,force_n\n0,0,0\n", "names time twice"),
    ],
)
def test_bad_csv_files_name_the_problem(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        load_record(path)


# --------------------------------------------------------------------------- other verbs' files


def half_sine_csv(path, impulse_n_s, duration_s=1e-3, rate_hz=200e3):
    """A half-sine force record with the given impulse (2 F0 T / pi), 1 ms of baseline each side."""
    pulse = half_sine(np.pi * impulse_n_s / (2 * duration_s), duration_s, rate_hz)
    path.write_text("time_s,force_n\n" + "".join(f"{t:.9e},{f:.9g}\n"
                                                 for t, f in zip(pulse.time_s, pulse.force_n)))
    return path


@pytest.mark.parametrize(("side", "impact", "rebound"), [
    # an old side file (video before the components, or by hand): taken as it is
    ({"impact_speed_m_s": 20.0, "rebound_speed_m_s": 10.0}, 20.0, 10.0),
    # the normal component wins over impact_speed_m_s and the totals
    ({"impact_speed_m_s": 20.0, "impact_speed_normal_m_s": 18.0, "impact_speed_total_m_s": 20.0,
      "rebound_speed_normal_m_s": 9.0, "rebound_speed_total_m_s": 11.0}, 18.0, 9.0),
    # total and angle from the normal: the normal component is total x cos(angle)
    ({"impact_speed_total_m_s": 20.0, "impact_angle_deg": 60.0,
      "rebound_speed_total_m_s": 8.0, "rebound_angle_deg": -60.0}, 10.0, 4.0),
    # total and tangential
    ({"impact_speed_total_m_s": 5.0, "impact_speed_tangential_m_s": 3.0}, 4.0, None),
])
def test_side_file_speeds_are_the_normal_components(tmp_path, side, impact, rebound):
    path = half_sine_csv(tmp_path / "shot.csv", 1.0)
    path.with_suffix(".json").write_text(json.dumps(side))
    record = load_record(path)
    assert record.impact_speed_m_s == pytest.approx(impact)
    assert record.rebound_speed_m_s == (None if rebound is None else pytest.approx(rebound))


@pytest.mark.parametrize(("side", "message"), [
    ({"impact_speed_total_m_s": 20.0}, "add impact_speed_normal_m_s"),
    ({"impact_speed_normal_m_s": 21.0, "impact_speed_total_m_s": 20.0}, "do not add up"),
    ({"impact_speed_normal_m_s": 10.0, "impact_speed_tangential_m_s": 10.0,
      "impact_speed_total_m_s": 20.0}, "do not add up"),
    ({"impact_speed_normal_m_s": 10.0, "impact_angle_deg": 20.0,
      "impact_speed_total_m_s": 20.0}, "do not add up"),
    ({"impact_speed_total_m_s": 20.0, "impact_angle_deg": 90.0}, "between -90 and 90"),
    ({"rebound_speed_normal_m_s": -1.0}, r"rebound_speed_normal_m_s = -1: allowed range \[0, inf\)"),
])
def test_side_file_speed_parts_that_cannot_be_one_speed(tmp_path, side, message):
    path = half_sine_csv(tmp_path / "shot.csv", 1.0)
    path.with_suffix(".json").write_text(json.dumps(side))
    with pytest.raises(InputError, match=message):
        load_record(path)


def test_video_json_without_normal_speed_or_angle(tmp_path):
    path = half_sine_csv(tmp_path / "shot.csv", 1.0)
    path.with_suffix(".json").write_text(json.dumps(
        {"impact_speed_m_s": 20.0, "rebound_speed_m_s": 10.0, "rebound_angle_deg": 60.0,
         "fps": 5000.0, "scale_m_per_px": 0.002}))
    with pytest.raises(InputError, match=r"shot\.json: no impact_speed_normal_m_s and no "
                                         r"impact_angle_deg.*add impact_speed_normal_m_s"):
        load_record(path, mass_kg=0.16)


def test_video_and_simulate_json_are_read_as_side_files(tmp_path):
    """`video --json > x.json` (totals and angles; the normal components where given) and
    `simulate --json > x.json` (axisymmetric; 3d: total speed at angle_deg, cor the normal COR)."""
    path = half_sine_csv(tmp_path / "shot.csv", 1.0)
    side = path.with_suffix(".json")
    video = {"impact_speed_m_s": 20.0, "rebound_speed_m_s": 10.0, "impact_angle_deg": 60.0,
             "rebound_angle_deg": 60.0, "cor": 0.5, "fps": 5000.0, "scale_m_per_px": 0.002}
    side.write_text(json.dumps(video))
    record = load_record(path, mass_kg=0.16)
    assert (record.impact_speed_m_s, record.rebound_speed_m_s) == (pytest.approx(10.0),
                                                                   pytest.approx(5.0))
    side.write_text(json.dumps({**video, "impact_speed_normal_m_s": 9.0,
                                "rebound_speed_normal_m_s": 4.0}))
    assert load_record(path).impact_speed_m_s == 9.0
    simulate = {"ball": "cricket-universal@25.0m/s", "impact_speed_m_s": 25.0, "cor": 0.4,
                "rebound_speed_m_s": 10.0, "mass_kg": 0.16, "elements": 1482, "warnings": []}
    side.write_text(json.dumps(simulate))
    record = load_record(path)
    assert (record.mass_kg, record.impact_speed_m_s, record.rebound_speed_m_s) == (
        0.16, 25.0, pytest.approx(10.0))
    side.write_text(json.dumps({**simulate, "solver": "3d", "angle_deg": 60.0, "cor": 0.5,
                                "normal_cor": 0.5, "rebound_speed_m_s": 20.0}))
    record = load_record(path)
    assert (record.impact_speed_m_s, record.rebound_speed_m_s) == (pytest.approx(12.5),
                                                                   pytest.approx(6.25))
    side.write_text(json.dumps({k: v for k, v in simulate.items() if k != "mass_kg"}))
    with pytest.raises(InputError, match='add "mass_kg"'):
        load_record(path)


def test_fe_history_csv_loads_with_its_contact_start(tmp_path):
    """`simulate --csv`: force column contact_force_n (either geometry; 3D files written before
    issue 40: normal_force_n), other columns left out, and the zero-force samples before first
    contact put back."""
    t = np.arange(1, 201) * 1e-6
    force = np.clip(np.sin(np.pi * t / 150e-6), 0.0, None) * 1e3
    for column in ("contact_force_n", "normal_force_n"):
        path = tmp_path / f"{column}.csv"
        rows = "".join(f"{a:.9g},{b:.9g},{b * 2:.9g},0.5\n" for a, b in zip(t, force))
        path.write_text(f"time_s,{column},kinetic_energy_j,centre_z_m\n" + rows)
        record = load_record(path)
        lead = record.metadata["fe_lead_samples"]
        assert lead == 11  # 5% of 200 samples, plus the contact instant
        assert np.all(record.force_n[:lead] == 0) and record.time_s[lead - 1] == 0.0
        assert np.allclose(record.force_n[lead:], force)
        assert np.allclose(np.diff(record.time_s), 1e-6)


def test_negative_sensitivity_reads_an_inverted_wav(tmp_path):
    """A load cell whose output falls in compression: a negative sensitivity turns it back."""
    pulse = half_sine(5e3, 1e-3, 48e3)
    path = tmp_path / "inverted.wav"
    wavfile.write(path, 48000, (-pulse.force_n * 1e-4 * 32767).astype(np.int16))
    record = load_record(path, sensitivity_v_per_n=-1e-4)
    assert np.max(np.abs(record.force_n - pulse.force_n)) < 1e-3 * 5e3
    assert record.metadata["full_scale_n"][0] > record.metadata["full_scale_n"][1]  # swapped rails
