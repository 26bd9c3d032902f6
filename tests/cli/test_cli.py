"""The command line contract: JSON keys, exit codes, one-line errors, plots."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.io import wavfile

from ballimpact.cli import main
from ballimpact.records.features import FEATURE_NAMES
from ballimpact.records.pulses import KelvinVoigt

BALL = KelvinVoigt(mass_kg=0.16, stiffness_n_m=1.5e6, damping_n_s_m=60.0, impact_speed_m_s=10.0)
CONTRACT_KEYS = {"peak_force_n", "contact_time_s", "cor", "impact_speed_m_s", "rebound_speed_m_s",
                 "wall_time_s", "features", "feature_names", "impulse_n_s", "warnings"}


@pytest.fixture
def test_csv(tmp_path):
    record = BALL.record(200e3)
    path = tmp_path / "kv.csv"
    rows = "".join(f"{t:.9e},{f:.9g}\n" for t, f in zip(record.time_s * 1e3, record.force_n))
    path.write_text("time_ms,force_n\n" + rows)
    return path


def run(capsys, *argv):
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_features_json_has_the_contract_keys(capsys, test_csv, tmp_path):
    plot = tmp_path / "kv.png"
    code, out, err = run(capsys, "features", test_csv, "--mass-kg", 0.16, "--impact-speed-m-s", 10,
                         "--rebound-speed-m-s", BALL.cor * 10, "--json", "--plot", plot)
    assert code == 0, err
    result = json.loads(out)
    assert CONTRACT_KEYS <= set(result)
    assert set(result["features"]) == set(FEATURE_NAMES)
    assert result["contact_time_s"] == pytest.approx(BALL.contact_time_s, rel=0.01)
    assert result["impulse_cor"] == pytest.approx(BALL.cor, rel=2e-3)
    assert result["impulse_check_passed"] is True
    assert plot.stat().st_size > 10_000


def test_features_table_and_filter(capsys, test_csv):
    code, out, err = run(capsys, "features", test_csv, "--mass-kg", 0.16, "--impact-speed-m-s", 10,
                         "--filter", "loess")
    assert code == 0, err
    assert "P19" in out and "peak_deceleration_m_s2" in out and "filter: loess" in out


def test_impulse_warning_goes_to_stderr_and_json(capsys, test_csv):
    code, out, err = run(capsys, "features", test_csv, "--mass-kg", 0.16, "--impact-speed-m-s", 10,
                         "--rebound-speed-m-s", 5.0, "--json")
    assert code == 0
    assert err.startswith(f"warning: {test_csv}: impulse check")
    assert json.loads(out)["impulse_check_passed"] is False
    assert any("impulse check" in note for note in json.loads(out)["warnings"])


def bad_inputs(tmp_path, test_csv):
    def csv(name, text):
        path = tmp_path / name
        path.write_text(text)
        return path

    noise = np.random.default_rng(0).standard_normal(500)
    noise_rows = "".join(f"{i * 1e-5:.6e},{x:.6g}\n" for i, x in enumerate(noise))
    wav = tmp_path / "pulse.wav"
    wavfile.write(wav, 48000, np.zeros(100, dtype=np.int16))
    speeds = ["--mass-kg", "0.16", "--impact-speed-m-s", "10"]
    return {
        "empty file": ([csv("empty.csv", ""), *speeds], "the file is empty"),
        "missing unit": ([csv("nounit.csv", "time,force\n0,0\n"), *speeds], "has no unit"),
        "unknown unit": ([csv("kip.csv", "time_s,force_kip\n0,0\n"), *speeds], "unknown column"),
        "non-monotonic time": ([csv("back.csv", "time_s,force_n\n0,0\n2,1\n1,0\n"), *speeds],
                               "strictly increasing"),
        "repeated time": ([csv("rep.csv", "time_s,force_n\n0,0\n1,1\n1,0\n"), *speeds], "repeated"),
        "nan": ([csv("nan.csv", "time_s,force_n\n0,0\n1,NaN\n2,0\n"), *speeds], "not a finite"),
        "no pulse": ([csv("noise.csv", "time_s,force_n\n" + noise_rows), *speeds],
                     "no pulse above the noise"),
        "zero mass": ([test_csv, "--mass-kg", "0", "--impact-speed-m-s", "10"], "mass_kg = 0: allowed range (0, inf)"),
        "negative mass": ([test_csv, "--mass-kg=-0.16", "--impact-speed-m-s", "10"],
                          "mass_kg = -0.16: allowed range (0, inf)"),
        "missing mass": ([test_csv, "--impact-speed-m-s", "10"], "mass_kg: the ball mass is required"),
        "wav without sensitivity": ([wav, *speeds], "sensitivity_v_per_n"),
        "missing file": ([tmp_path / "nope.csv", *speeds], "no such file"),
        "unknown filter": ([test_csv, *speeds, "--filter", "median"], "filter: unknown name"),
        "bad number": ([test_csv, "--mass-kg", "heavy"], "is not a number"),
        "plot not png": ([test_csv, *speeds, "--plot", tmp_path], "must be a .png file"),
        "plot folder missing": ([test_csv, *speeds, "--plot", tmp_path / "no" / "p.png"],
                                "does not exist"),
    }


@pytest.mark.parametrize("case", [
    "empty file", "missing unit", "unknown unit", "non-monotonic time", "repeated time", "nan",
    "no pulse", "zero mass", "negative mass", "missing mass", "wav without sensitivity",
    "missing file", "unknown filter", "bad number", "plot not png", "plot folder missing"])
def test_bad_input_exits_2_with_one_line(capsys, tmp_path, test_csv, case):
    argv, message = bad_inputs(tmp_path, test_csv)[case]
    code, out, err = run(capsys, "features", *argv)
    assert code == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and message in lines[0], err
    assert "Traceback" not in err


def test_sample_record_features_and_fit(capsys, tmp_path):
    """The packaged sample test (the former demo input): its features and the Hunt-Crossley
    generator recovered by `fit`."""
    from importlib import resources

    with resources.as_file(resources.files("ballimpact") / "data" / "sample_impact.csv") as path:
        code, out, err = run(capsys, "features", path, "--filter", "loess", "--json")
        assert code == 0, err
        result = json.loads(out)
        # the sample record's exact values (its header): contact 1.097 ms, peak 11.22 kN, COR 0.55
        assert result["contact_time_s"] == pytest.approx(1.09704e-3, rel=0.03)
        assert result["peak_force_n"] == pytest.approx(11219.9, rel=0.03)
        assert result["cor"] == pytest.approx(0.55, abs=0.001)
        assert result["impulse_check_passed"] is True
        code, out, err = run(capsys, "fit", path, "--model", "hunt_crossley", "--filter", "loess",
                             "--json")
    assert code == 0, err
    fitted = json.loads(out)
    # the Hunt-Crossley generator of the sample (its header): k 2.06e7 N/m^1.5, lambda 0.057001 s/m
    assert fitted["params"]["n"] == pytest.approx(1.5, rel=0.02)
    assert fitted["params"]["lambda"] == pytest.approx(0.057001, rel=0.02)
    assert abs(fitted["params"]["k"] - 2.06e7) < 2 * fitted["standard_errors"]["k"]
    assert fitted["nrmse"] < 0.01


def test_console_script_runs(tmp_path):
    """The installed `ballimpact` entry point (falls back to `python -m` if not on PATH)."""
    beside = Path(sys.executable).parent / "ballimpact"
    exe = str(beside) if beside.exists() else shutil.which("ballimpact")
    command = [exe] if exe else [sys.executable, "-m", "ballimpact.cli"]
    done = subprocess.run([*command, "features", str(tmp_path / "absent.csv")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and done.stderr.startswith("error: ") and "no such file" in done.stderr


def test_simulate_csv_and_json_feed_features(capsys, tmp_path):
    """`simulate --csv x.csv --json > x.json`, then `features x.csv`: the FE history loads (its
    force column contact_force_n, the samples before first contact put back), the JSON beside
    it is read as its side file (mass, impact and rebound speed), and the features agree with
    those simulate computed itself."""
    csv, side = tmp_path / "x.csv", tmp_path / "x.json"
    code, out, err = run(capsys, "simulate", "--ball", "cricket-universal", "--speed-m-s", 25,
                         "--element-size-m", 3e-3, "--csv", csv, "--json")
    assert code == 0, err
    side.write_text(out)
    simulated = json.loads(out)
    code, out, err = run(capsys, "features", csv, "--json")
    assert code == 0, err
    result = json.loads(out)
    assert result["mass_kg"] == simulated["mass_kg"]
    assert result["impact_speed_m_s"] == 25.0
    assert result["cor"] == pytest.approx(simulated["cor"], rel=1e-12)
    assert result["impulse_check_passed"] is True
    # simulate's features come from its history resampled at the final step, these from the
    # steps themselves: the contact time agrees to a fraction of a step (1.3 us of 1.06 ms);
    # the refined peak to 1% (this coarse mesh's force jitters from step to step)
    assert result["features"]["P1"] == pytest.approx(simulated["features"]["P1"], rel=1e-3)
    assert result["features"]["P6"] == pytest.approx(simulated["features"]["P6"], rel=0.01)
