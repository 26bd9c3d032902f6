"""Plausibility checks on measured records and scalars (docs/features.md "Plausibility checks"):
several pulses, multi-channel WAV, clipping, unit slips, impossible scalars, side-file types.
Each class is exercised through the command line (exit code and message) and its override."""

import json
import warnings

import numpy as np
import pytest
from scipy.io import wavfile

from ballimpact.cli import main
from ballimpact.errors import InputError
from ballimpact.records.loaders import load_record
from ballimpact.records.pipeline import process
from ballimpact.records.features import extract_features
from ballimpact.records.plausibility import check_polarity, clipped_spans, find_pulses, likely_slips
from ballimpact.records.pulses import KelvinVoigt, half_sine
from ballimpact.records.record import ImpactRecord

BALL = KelvinVoigt(mass_kg=0.16, stiffness_n_m=1.5e6, damping_n_s_m=60.0, impact_speed_m_s=10.0)
SCALARS = {"mass_kg": 0.16, "impact_speed_m_s": 10.0, "rebound_speed_m_s": BALL.cor * 10.0}
SENSITIVITY_V_PER_N = 9.442e-5


def run(capsys, *argv):
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


def write_csv(path, time, force, header="time_s,force_n", side=SCALARS):
    path.write_text(header + "\n" + "".join(f"{t:.9e},{f:.9g}\n" for t, f in zip(time, force)))
    if side is not None:
        path.with_suffix(".json").write_text(json.dumps(side))
    return path


def one_error_line(code, out, err, *fragments):
    assert code == 2 and out == "", err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    for fragment in fragments:
        assert fragment in lines[0], err
    assert "np.float64" not in err


def bounces(count, rate_hz=200e3, gap_s=2e-3, decay=0.6):
    """`count` Kelvin-Voigt pulses in one record, each `decay` times the one before."""
    pulse = BALL.record(rate_hz)
    times, forces = [pulse.time_s], [pulse.force_n]
    for k in range(1, count):
        times.append(times[-1][-1] + gap_s + pulse.time_s - pulse.time_s[0])
        forces.append(pulse.force_n * decay**k)
    return np.concatenate(times), np.concatenate(forces)


# --------------------------------------------------------------------------- several pulses


@pytest.mark.parametrize("count", [2, 3])
def test_several_pulses_are_listed(capsys, tmp_path, count):
    path = write_csv(tmp_path / "bounce.csv", *bounces(count))
    code, out, err = run(capsys, "features", path)
    one_error_line(code, out, err, f"found {count} pulses", "#1 peak", f"#{count} peak",
                   "--pulse N")


def test_pulse_flag_takes_the_chosen_pulse(capsys, tmp_path):
    """The first of two pulses gives the features of the single pulse; the second is its own."""
    time, force = bounces(2)
    path = write_csv(tmp_path / "bounce.csv", time, force)
    single = process(BALL.record(200e3)).features
    code, out, err = run(capsys, "features", path, "--pulse", "1", "--json")
    assert code == 0, err
    first = json.loads(out)
    assert first["contact_time_s"] == pytest.approx(single.values["P1"], rel=1e-9)
    assert first["peak_force_n"] == pytest.approx(single.values["P6"], rel=1e-9)
    second = process(ImpactRecord(time, force, mass_kg=0.16, impact_speed_m_s=6.0), pulse=2)
    assert second.features.values["P6"] == pytest.approx(0.6 * single.values["P6"], rel=1e-6)
    code, out, err = run(capsys, "features", path, "--pulse", "3")
    one_error_line(code, out, err, "pulse: 3 out of range 1..2")


def test_one_pulse_with_ringing_and_pure_noise_are_not_several_pulses():
    """The built-in sample (3% load-cell ringing, 1% noise) is one pulse; noise alone is none."""
    from importlib import resources

    from ballimpact.records.loaders import load_record

    sample = load_record(resources.files("ballimpact") / "data" / "sample_impact.csv")
    assert len(find_pulses(sample.time_s, sample.force_n)) == 1
    noise = np.random.default_rng(0).standard_normal(2000)
    assert find_pulses(np.arange(2000) * 1e-5, noise) == []


# --------------------------------------------------------------------------- multi-channel WAV


def pulse_codes(peak_fraction=0.5, rate_hz=48e3):
    pulse = half_sine(1.0, 1e-3, rate_hz)
    return (pulse.force_n * peak_fraction * 32767).astype(np.int16)


@pytest.mark.parametrize("channels", [2, 4])
def test_multichannel_wav_needs_a_channel(capsys, tmp_path, channels):
    data = np.zeros((pulse_codes().size, channels), dtype=np.int16)
    data[:, 1] = pulse_codes()
    path = tmp_path / "stereo.wav"
    wavfile.write(path, 48000, data)
    code, out, err = run(capsys, "features", path, "--sensitivity-v-per-n", SENSITIVITY_V_PER_N,
                         "--mass-kg", 0.16, "--impact-speed-m-s", 10)
    one_error_line(code, out, err, f"has {channels} channels", "0: peak 0.0% of full scale",
                   "1: peak 50.0% of full scale", "--channel N")
    code, out, err = run(capsys, "features", path, "--sensitivity-v-per-n", SENSITIVITY_V_PER_N,
                         "--mass-kg", 0.16, "--impact-speed-m-s", 10, "--channel", channels)
    one_error_line(code, out, err, f"channel: {channels} out of range 0..{channels - 1}")


def test_chosen_channel_is_read(tmp_path):
    from ballimpact.records.loaders import load_record

    data = np.column_stack([np.zeros_like(pulse_codes()), pulse_codes()])
    path = tmp_path / "stereo.wav"
    wavfile.write(path, 48000, data)
    record = load_record(path, sensitivity_v_per_n=1.0, channel=1)
    assert np.max(record.force_n) == pytest.approx(0.5, rel=1e-3)


# --------------------------------------------------------------------------- clipping


def clipped_wav(tmp_path, dtype=np.int16):
    """A half-sine driven to 1.5 x the recorder's full scale: about a third of it is clipped."""
    fraction = np.clip(half_sine(1.5, 1e-3, 48e3).force_n, -1.0, 1.0)
    if dtype == np.uint8:
        data = np.clip(np.round(128 + fraction * 128), 0, 255).astype(np.uint8)
    else:
        data = np.clip(np.round(fraction * 32768), -32768, 32767).astype(np.int16)
    path = tmp_path / f"clipped-{np.dtype(dtype).name}.wav"
    wavfile.write(path, 48000, data)
    return path


@pytest.mark.parametrize("dtype", [np.int16, np.uint8])
def test_clipped_wav_is_an_error_and_can_be_allowed(capsys, tmp_path, dtype):
    path = clipped_wav(tmp_path, dtype)
    # 4e-4 V/N: the unclipped pulse's impulse is 2.4 N s = m v_in (1 + 0.5), a plausible impact
    argv = ["features", path, "--sensitivity-v-per-n", 4e-4, "--mass-kg", 0.16,
            "--impact-speed-m-s", 10]
    code, out, err = run(capsys, *argv)
    one_error_line(code, out, err, "force_n: the signal is clipped", "samples at",
                   "--allow clipping")
    code, out, err = run(capsys, *argv, "--allow", "clipping", "--json")
    assert code == 0, err
    notes = json.loads(out)["warnings"]
    assert any(note.startswith("clipping: force_n: the signal is clipped") for note in notes)


def test_flat_top_in_a_csv_is_clipping(capsys, tmp_path):
    record = BALL.record(200e3)
    level = 0.8 * np.max(record.force_n)
    path = write_csv(tmp_path / "flat.csv", record.time_s, np.minimum(record.force_n, level))
    code, out, err = run(capsys, "features", path)
    one_error_line(code, out, err, "the signal is clipped", f"{level:.6g} N")


def test_quantised_rounded_peaks_are_not_clipping():
    """A finely sampled pulse on a coarse resolution has several equal samples at its peak,
    entered by one resolution step: not a flat top. Nor is a WAV that stays below full scale."""
    pulse = half_sine(5e3, 1e-3, 2e6)
    quantised = np.round(pulse.force_n / 10.0) * 10.0  # 10 N resolution, 500 steps to the peak
    top = np.flatnonzero(quantised == quantised.max())
    assert top.size >= 3  # the flat peak the check must not mistake for clipping
    assert clipped_spans(pulse.time_s, quantised) == []
    assert clipped_spans(pulse.time_s, quantised, full_scale_n=(-1e4, 1e4)) == []


def test_inverted_pulse_is_named_not_called_clipped(capsys, tmp_path):
    """An inverted load cell: the flat zero baseline is the record's maximum, which the flat-top
    test once took for clipping ("clipped at -0 N"). It is a polarity error naming the fix."""
    record = BALL.record(200e3)
    path = write_csv(tmp_path / "inverted.csv", record.time_s, -record.force_n)
    code, out, err = run(capsys, "features", path, "--allow", "clipping")
    one_error_line(code, out, err, "polarity looks inverted", "negate the force column")
    assert "clipped" not in err
    # the flat baseline is not clipping, whichever way the pulse points
    assert clipped_spans(record.time_s, -record.force_n) == []
    assert clipped_spans(record.time_s, record.force_n) == []
    # the Python API refuses it the same way, before any other check
    with pytest.raises(InputError, match="polarity looks inverted"):
        process(record.replace(force_n=-record.force_n))
    with pytest.raises(InputError, match="polarity looks inverted"):
        extract_features(record.replace(force_n=-record.force_n))


def test_positive_pulses_with_undershoot_or_noise_are_not_inverted():
    """Ringing below the baseline after the pulse (30% of the peak) and noise (5% of the peak)
    leave the positive pulse the largest excursion: no polarity error."""
    record = BALL.record(200e3)
    t = record.time_s
    after = t > BALL.contact_time_s
    ring = -0.3 * record.force_n.max() * np.sin(2e4 * (t - BALL.contact_time_s)) * after
    rng = np.random.default_rng(4)
    noise = 0.05 * record.force_n.max() * rng.standard_normal(t.size)
    for force in (record.force_n + ring, record.force_n + noise):
        check_polarity(record.replace(force_n=force))
    with pytest.raises(InputError, match="pulse is negative"):
        check_polarity(record.replace(force_n=-(record.force_n + noise)))


# --------------------------------------------------------------------------- unit slips


@pytest.mark.parametrize("header, scale_time, scale_force, slip", [
    ("time_s,force_n", 1e3, 1.0, "time in ms under a time_s header"),
    ("time_s,force_n", 1.0, 1e-3, "force in kN under a force_n header"),
    ("time_s,force_kn", 1.0, 1.0, "force in N under a force_kn header"),
])
def test_unit_slips_are_errors_that_name_the_slip(capsys, tmp_path, header, scale_time,
                                                  scale_force, slip):
    record = BALL.record(200e3)
    path = write_csv(tmp_path / "slip.csv", record.time_s * scale_time,
                     record.force_n * scale_force, header=header)
    code, out, err = run(capsys, "features", path)
    one_error_line(code, out, err, "impulse: the integral of F dt", "beyond the factor 3", slip)


def test_mass_in_grams_and_the_override(capsys, tmp_path):
    record = BALL.record(200e3)
    path = write_csv(tmp_path / "kv.csv", record.time_s, record.force_n, side=None)
    code, out, err = run(capsys, "features", path, "--mass-kg", 160, "--impact-speed-m-s", 10)
    one_error_line(code, out, err, "mass in g given as mass_kg")
    # allowed, a slip warns and the run goes on (here time in ms under time_s, rebound measured)
    slipped = write_csv(tmp_path / "ms.csv", record.time_s * 1e3, record.force_n)
    code, out, err = run(capsys, "features", slipped, "--allow", "unit-slip", "--json")
    assert code == 0, err
    assert any(note.startswith("unit-slip: impulse") for note in json.loads(out)["warnings"])


def test_small_misses_stay_a_tolerance_warning(capsys, tmp_path):
    record = BALL.record(200e3)
    path = write_csv(tmp_path / "kv.csv", record.time_s, record.force_n,
                     side={**SCALARS, "rebound_speed_m_s": 3.0})
    code, out, err = run(capsys, "features", path, "--json")
    assert code == 0, err
    assert err.startswith(f"warning: {path}: impulse check")  # the file named: fit takes several


def test_likely_slips_for_other_factors():
    assert "time in us under a time_s header" in likely_slips(1.1e6)
    assert "km/h" in likely_slips(1 / 3.6)
    assert "no usual unit slip" in likely_slips(50.0)
    # a WAV has no header: its slips are in the sensor settings
    assert "sensitivity in mV/kN given as V/N" in likely_slips(1e-6, wav=True)
    assert "amplifier gain not given" in likely_slips(10.0, wav=True)
    assert "header" not in likely_slips(1e-3, wav=True)


# --------------------------------------------------------------------------- impossible scalars


def test_rebound_faster_than_impact_is_an_error(capsys, tmp_path):
    """Swapped speeds: the impulse matches (it is symmetric in the speeds), COR > 1 does not."""
    record = BALL.record(200e3)
    swapped = {"mass_kg": 0.16, "impact_speed_m_s": BALL.cor * 10.0, "rebound_speed_m_s": 10.0}
    path = write_csv(tmp_path / "kv.csv", record.time_s, record.force_n, side=swapped)
    code, out, err = run(capsys, "features", path)
    one_error_line(code, out, err, "rebound speed 10 m/s is above the impact speed",
                   "COR 1.", "--allow cor-above-one")
    code, out, err = run(capsys, "features", path, "--allow", "cor-above-one", "--json")
    assert code == 0, err
    assert any(note.startswith("cor-above-one:") for note in json.loads(out)["warnings"])


def test_impulse_cor_above_one_is_an_error():
    """No measured rebound: an impulse of 2.5 m v_in means a COR of 1.5."""
    record = BALL.record(200e3)
    scaled = ImpactRecord(record.time_s, record.force_n * 2.5 / (1 + BALL.cor), mass_kg=0.16,
                          impact_speed_m_s=10.0)
    with pytest.raises(InputError, match=r"the impulse gives COR 1\.50\d* > 1"):
        process(scaled)


@pytest.mark.parametrize("value, shown", [(True, "true (bool)"), ("0.16", '"0.16" (str)'),
                                          ([0.16], "[0.16] (list)")])
def test_side_file_values_must_be_json_numbers(capsys, tmp_path, value, shown):
    record = BALL.record(200e3)
    path = write_csv(tmp_path / "kv.csv", record.time_s, record.force_n,
                     side={**SCALARS, "mass_kg": value})
    code, out, err = run(capsys, "features", path)
    one_error_line(code, out, err, f"{path.with_suffix('.json')}: mass_kg: expected a JSON number",
                   shown)


def test_side_file_errors_name_the_side_file(capsys, tmp_path):
    record = BALL.record(200e3)
    path = write_csv(tmp_path / "kv.csv", record.time_s, record.force_n,
                     side={**SCALARS, "impact_speed_m_s": -10})
    code, out, err = run(capsys, "features", path)
    one_error_line(code, out, err, f"{path.with_suffix('.json')}: impact_speed_m_s = -10: allowed range")


# --------------------------------------------------------------------------- other input slips


def test_folder_without_records(capsys, tmp_path):
    code, out, err = run(capsys, "features", tmp_path, "--mass-kg", 0.16, "--impact-speed-m-s", 10)
    one_error_line(code, out, err, "holds no test records")


def test_absurd_forces_give_the_scaling_reason(capsys, tmp_path):
    record = BALL.record(200e3)
    path = write_csv(tmp_path / "huge.csv", record.time_s, record.force_n * 1e296)
    code, out, err = run(capsys, "features", path)
    one_error_line(code, out, err, "no usual unit slip", "force scaling")


def test_noisy_record_names_the_file_and_the_filter(capsys, tmp_path):
    """The user's own noisy record described by its samples: one warning naming the file and
    the filter; filtered, none; with the default fitted pulse (issue 39) none: the noise does not
    cut its edges."""
    from importlib import resources

    sample = resources.files("ballimpact") / "data"
    path = tmp_path / "mine.csv"
    path.write_text((sample / "sample_impact.csv").read_text())
    path.with_suffix(".json").write_text((sample / "sample_impact.json").read_text())
    code, out, err = run(capsys, "features", path, "--json", "--pulse-method", "samples")
    assert code == 0, err
    notes = [note for note in json.loads(out)["warnings"] if "noisy record" in note]
    assert len(notes) == 1 and notes[0].startswith(f"{path}: noisy record")
    assert "--filter loess" in notes[0]
    code, out, err = run(capsys, "features", path, "--filter", "loess", "--json",
                         "--pulse-method", "samples")
    assert code == 0, err
    assert not any("noisy record" in note for note in json.loads(out)["warnings"])
    code, out, err = run(capsys, "features", path, "--json")
    assert code == 0 and "noisy" not in err, err
    assert json.loads(out)["pulse_method"] == "fit"


def test_built_in_sample_is_not_called_noisy(capsys):
    """The built-in sample is noisy on purpose (1% of the peak; docs/features.md): the demo
    and report use it unfiltered, so no warning about it; the note stays in the features."""
    from importlib import resources

    with resources.as_file(resources.files("ballimpact") / "data" / "sample_impact.csv") as path:
        code, out, err = run(capsys, "features", path, "--json")
        assert code == 0, err
        assert not any("noisy record" in note for note in json.loads(out)["warnings"])
        assert "noisy" not in err
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # any warning fails the test
            processed = process(load_record(path), method="samples")
    assert any("noisy record" in note for note in processed.features.warnings)


def test_noisy_warning_once_per_file_and_can_be_turned_off(tmp_path):
    """Two noisy files processed as fit and report do: one warning each, each naming its file;
    `warn_noisy=False` (records made noisy on purpose) warns about none."""
    from importlib import resources

    sample = resources.files("ballimpact") / "data"
    paths = []
    for name in ("a.csv", "b.csv"):
        paths.append(tmp_path / name)
        paths[-1].write_text((sample / "sample_impact.csv").read_text())
        paths[-1].with_suffix(".json").write_text((sample / "sample_impact.json").read_text())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for path in paths:
            process(load_record(path), method="samples")
    noisy = [str(w.message) for w in caught if "noisy record" in str(w.message)]
    assert [note.split(": noisy record")[0] for note in noisy] == [str(p) for p in paths]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        processed = process(load_record(paths[0]), warn_noisy=False, method="samples")
    assert any("noisy record" in note for note in processed.features.warnings)


def test_unknown_check_name(capsys, tmp_path):
    record = BALL.record(200e3)
    path = write_csv(tmp_path / "kv.csv", record.time_s, record.force_n)
    code, out, err = run(capsys, "features", path, "--allow", "everything")
    one_error_line(code, out, err, "allow: unknown check 'everything'", "clipping")
