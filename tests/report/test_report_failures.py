"""A report that does not abort (issue 24): one model that cannot follow one test is listed with
its reason and the rest goes on; and the causes found behind "force_n: no sample at or below zero
force where the record ends" on three noisy tests at 7, 15 and 24 m/s (50, 80, 100 kHz)."""

import csv
import json

import numpy as np
import pytest

from ballimpact import process
from ballimpact.calibrate.problem import CalibrationTest
from ballimpact.cli import main
from ballimpact.lumped import simulate
from ballimpact.report.models import measured_like

#: a cricket ball (160 g) as a Hunt-Crossley contact: peak 3.1, 7.5 and 14 kN, COR 0.79-0.51
BALL = {"k": 2.06e7, "n": 1.5, "lambda": 0.057}
MASS_KG = 0.16
#: the tests of the issue: speed (m/s) and sampling rate (Hz)
TESTS = ((7.0, 50e3), (15.0, 80e3), (24.0, 100e3))


def noisy_test(speed, rate_hz, noise, rng):
    """The ball's pulse sampled at `rate_hz` with 0.6 ms of baseline on each side and white noise
    of `noise` times the peak, as a load cell records it."""
    pulse = simulate("hunt_crossley", BALL, impact_speed_m_s=speed, mass_kg=MASS_KG,
                     rate_hz=rate_hz)
    lead = int(6e-4 * rate_hz)
    time = np.arange(-lead, int(pulse.time_s[-1] * rate_hz) + lead) / rate_hz
    force = np.interp(time, pulse.time_s, pulse.force_n, left=0.0, right=0.0)
    force += rng.normal(0.0, noise * force.max(), force.size)
    return pulse.replace(time_s=time, force_n=force, velocity_m_s=None,
                         rebound_speed_m_s=round(pulse.rebound_speed_m_s, 2))


def write_tests(folder, noise=0.02, seed=2):
    rng = np.random.default_rng(seed)
    paths = []
    for speed, rate in TESTS:
        record = noisy_test(speed, rate, noise, rng)
        path = folder / f"t{speed:g}.csv"
        np.savetxt(path, np.c_[record.time_s, record.force_n], delimiter=",",
                   header="time_s,force_n", comments="")
        path.with_suffix(".json").write_text(json.dumps(
            {"mass_kg": MASS_KG, "impact_speed_m_s": speed,
             "rebound_speed_m_s": record.rebound_speed_m_s}))
        paths.append(path)
    return paths


@pytest.mark.parametrize("steps_per_sample", [8.0, 8.01, 10.01])
def test_a_clean_model_pulse_is_measured_at_any_test_rate(steps_per_sample):
    """The cause in the report: a clean model pulse ends in exact zeros after a kink. Resampled
    at the test's rate by a cubic spline it rang on into the tail with crumbs of one sign
    whenever the test's spacing was near an even number of model steps, so no sample came back
    to zero and the measurement aborted (these spacings all did). Linear resampling keeps the
    zeros and measures the pulse as the test's: contact time within 3% of the test's."""
    model = simulate("hunt_crossley", BALL, impact_speed_m_s=7.0, mass_kg=MASS_KG)
    rate = 1.0 / (steps_per_sample * (model.time_s[1] - model.time_s[0]))
    sampled = simulate("hunt_crossley", BALL, impact_speed_m_s=7.0, mass_kg=MASS_KG,
                       rate_hz=rate)
    noise = np.random.default_rng(0).normal(0.0, 0.01 * sampled.force_n.max(),
                                            sampled.force_n.size)
    test = CalibrationTest("7 m/s", process(sampled.replace(
        force_n=sampled.force_n + noise, velocity_m_s=None)).features)
    measured = measured_like(test, model)
    assert measured.values["P1"] == pytest.approx(test.features.values["P1"], rel=0.03)
    assert measured.values["P6"] == pytest.approx(model.force_n.max(), rel=1e-3)


def test_the_three_noisy_tests_of_the_issue_give_a_whole_report(tmp_path, capsys):
    """The failing case of the issue: both lumped models fit all three tests; the three-element
    fit no longer ends with a soft unit that stays on the surface at 5-8% of the peak for 3
    contact times (COR 0.82 against 0.63 at 15 m/s, "does not leave the surface within 1.6
    measured contact times") since its fit compares the force after the window with zero and
    penalises a model still touching at the end of its grid. (A force-only fit to a 2%-noise
    pulse still leaves its COR about 0.06 off at 24 m/s.)"""
    paths = write_tests(tmp_path)
    out = tmp_path / "report"
    code = main(["report", *map(str, paths), "--models", "single_element,three_element",
                 "--out", str(out), "--quiet", "--json"])
    captured = capsys.readouterr()
    # the COR left 0.06 off at 15 and 24 m/s is beyond the 0.03 of the model check: no model
    # passes there, exit 3 (issue 39), the report written all the same
    assert code == 3, captured.err
    assert "no model passes its check on 2 of 3 tests (15 m/s, 24 m/s)" in captured.err
    report = json.loads((out / "report.json").read_text())
    assert report["unmatched_tests"] == ["15 m/s", "24 m/s"]
    assert report["failures"] == []
    assert len(report["runs"]) == 6
    for run in report["runs"]:
        assert np.isfinite(run["contact_time_s"]) and np.isfinite(run["cor"])
        assert abs(run["comparison"]["cor_error"]) < 0.1, (run["model"], run["test"])
        assert run["comparison"]["force_nrmse"] < 0.12, (run["model"], run["test"])
    assert "does not leave the surface" not in captured.err


def test_a_pair_that_fails_as_bad_input_is_a_failed_row(tmp_path, fail_model, capsys):
    """An InputError from one model at one test (a pulse that cannot be measured, a ball out of
    its speed range) is a failed row with its reason; the other models' results stay."""
    from ballimpact.errors import InputError

    fail_model(InputError("force_n: no sample at or below zero force where the "
                          "record ends"), "kelvin_voigt")
    out = tmp_path / "r"
    code = main(["report", "--builtin", "sample", "--models", "hertz,kelvin_voigt", "--out",
                 str(out), "--quiet"])
    printed, err = capsys.readouterr()
    assert code == 3, err  # hertz cannot give the sample's COR: no model passes (issue 39)
    assert "warning: kelvin_voigt at 20.8 m/s: failed run: force_n: no sample" in err
    assert "failed: kelvin_voigt at 20.8 m/s: force_n: no sample" in printed
    with open(out / "nrmse_by_speed.csv") as f:
        rows = {row["model"]: row for row in csv.DictReader(f)}
    assert rows["kelvin_voigt"]["20.8 m/s"] == "failed" and rows["kelvin_voigt"]["mean_abs"] == ""
    assert float(rows["hertz"]["20.8 m/s"]) > 0
    with open(out / "comparison.csv") as f:
        comparison = {row["model"]: row for row in csv.DictReader(f)}
    assert comparison["hertz"]["failed"] == ""
    assert comparison["kelvin_voigt"]["failed"].startswith("failed: force_n: no sample")
    assert comparison["kelvin_voigt"]["impact_speed_m_s"] == "20.8"
    page = (out / "report.html").read_text()
    assert page.index("Failed runs") < page.index("Accuracy per model and speed")


def test_every_pair_refused_as_bad_input_exits_2(tmp_path, fail_model, bad_input):
    from ballimpact.errors import InputError

    fail_model(InputError("impact speed 0.5 m/s is below the FE engine's 1 m/s"))
    bad_input(["report", "--builtin", "sample", "--models", "hertz", "--out", tmp_path / "r",
               "--quiet"], "every model run failed: hertz at 20.8 m/s: impact speed 0.5")
