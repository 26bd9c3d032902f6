"""Loaders: CSV units, WAV conversion with sensitivity and gain, JSON side files."""

import json

import numpy as np
import pytest
from scipy.io import wavfile

from ballimpact import InputError, load_record
from ballimpact.pulses import half_sine

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
        ("time_s,force_lbf\n0,0\n", "unknown column 'force_lbf'"),
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
