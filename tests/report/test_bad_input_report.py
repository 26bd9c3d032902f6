"""`ballimpact report` refuses a user's mistakes before any fit or FE run (issue 24): exit 2, one
line on stderr naming the flag or file and the fix, nothing on stdout, no output folder."""

import json
import warnings

import numpy as np
import pytest

from ballimpact.report.inputs import builtin_files

SAMPLE = str(builtin_files("sample")[0])


@pytest.fixture
def tests_folder(tmp_path):
    """Two small test records: `a.csv` with its side file (speed and mass), `bare.csv` without."""
    time = np.arange(-50, 250) / 100e3
    force = np.where((time > 0) & (time < 1e-3), 8e3 * np.sin(np.pi * time / 1e-3), 0.0)
    for name in ("a", "bare"):
        np.savetxt(tmp_path / f"{name}.csv", np.c_[time, force], delimiter=",",
                   header="time_s,force_n", comments="")
    (tmp_path / "a.json").write_text(json.dumps({"mass_kg": 0.16, "impact_speed_m_s": 20.0}))
    return tmp_path


def report(tmp_path, *argv):
    return ["report", *argv, "--quiet"] + ([] if "--out" in argv else ["--out", tmp_path / "r"])


@pytest.mark.parametrize("models, fragments", [
    ("", ["--models", "no model named", "single_element,three_element"]),
    (",", ["--models", "no model named"]),
    (" , ", ["--models", "no model named"]),
    ("hertz,,simon", ["--models", "empty name"]),
    ("single_elemnt", ["unknown model 'single_elemnt'", "did you mean single_element?"]),
    ("unversal", ["unknown model 'unversal'", "did you mean universal?"]),
    ("cricket-3layr", ["did you mean cricket-3layer?"]),
    ("hunt_crossley,hunt_crossley", ["--models", "'hunt_crossley' is named twice"]),
    ("tennis", ["unknown model 'tennis'", "allowed: lumped models"]),
])
def test_bad_model_lists(tmp_path, bad_input, models, fragments):
    bad_input(report(tmp_path, "--builtin", "sample", "--models", models), *fragments)
    assert not (tmp_path / "r").exists()


def test_a_ball_file_that_does_not_exist(tmp_path, bad_input):
    bad_input(report(tmp_path, "--builtin", "sample", "--models",
                     f"hertz,{tmp_path / 'myball.json'}"),
              "--models", "myball.json", "does not exist")


def test_a_ball_file_that_is_not_a_ball_is_refused_before_any_run(tmp_path, bad_input):
    ball = tmp_path / "flat.json"
    ball.write_text(json.dumps({"name": "flat", "layers": []}))
    bad_input(report(tmp_path, "--builtin", "sample", "--models", f"hertz,{ball}"),
              "--models", "flat.json", "layers")


#: a foam ball whose shear modulus 2 c10 = 5e3 Pa lies below the 1e4 Pa of `ball-units`
FOAM = {"name": "foam", "layers": [{"name": "foam", "outer_radius_m": 0.0366, "density_kg_m3": 30.0,
                                    "material": {"model": "neo_hookean", "c10_pa": 2.5e3}}]}


def test_a_ball_outside_the_sports_ball_ranges_is_refused_unless_allowed(tmp_path, bad_input):
    from ballimpact.errors import InputWarning
    from ballimpact.report.models import check_balls, parse_models

    ball = tmp_path / "myball.json"
    ball.write_text(json.dumps(FOAM))
    bad_input(report(tmp_path, "--builtin", "sample", "--models", f"hertz,{ball}"),
              "--models", "myball.json", "shear modulus", "--allow ball-units")
    with pytest.warns(InputWarning, match="^ball-units: .*shear modulus"):  # what --allow does
        check_balls(parse_models(str(ball)), 20.0, allow=["ball-units"])


def test_allow_reaches_the_runs_of_a_ball_and_of_the_universal_model(tmp_path, monkeypatch):
    import importlib

    import ballimpact.fe as fe
    from ballimpact.records.loaders import load_record
    from ballimpact.records.pipeline import process
    from ballimpact.report.inputs import label_tests
    from ballimpact.report.models import parse_models, run_model

    ball = tmp_path / "myball.json"
    ball.write_text(json.dumps(FOAM))
    given = []

    def stop(*args, allow=(), **kwargs):  # before any FE run
        given.append(allow)
        raise RuntimeError("stop")

    monkeypatch.setattr(fe, "simulate", stop)
    # the module, not the package's function of the same name
    monkeypatch.setattr(importlib.import_module("ballimpact.universal.identify"), "identify",
                        stop)
    test = label_tests([SAMPLE], [process(load_record(SAMPLE))])[0]
    for spec in parse_models(f"{ball},universal"):
        with pytest.warns(UserWarning) if spec.kind == "ball" else warnings.catch_warnings(), \
                pytest.raises(RuntimeError, match="stop"):
            run_model(spec, test, universal_model=object(), options=object(),
                      allow=["ball-units"])
    assert given == [["ball-units"], ["ball-units"]]


def test_out_that_is_a_file(tmp_path, bad_input):
    target = tmp_path / "report.html"
    target.write_text("")
    bad_input(report(tmp_path, "--builtin", "sample", "--out", target),
              "--out", "report.html", "is a file")


def test_out_in_a_folder_that_does_not_exist(tmp_path, bad_input):
    bad_input(report(tmp_path, "--builtin", "sample", "--out", tmp_path / "no" / "r"),
              "--out: folder", "does not exist")


def test_no_tests(tmp_path, bad_input):
    bad_input(report(tmp_path), "give test files or --builtin")


def test_tests_and_builtin_together(tmp_path, bad_input):
    bad_input(report(tmp_path, SAMPLE, "--builtin", "sample"), "one of the two")


def test_an_unknown_builtin_set(tmp_path, bad_input):
    bad_input(report(tmp_path, "--builtin", "tennis"), "--builtin", "tennis")


def test_a_test_file_that_does_not_exist(tmp_path, bad_input):
    bad_input(report(tmp_path, tmp_path / "t25.csv"), "t25.csv")


def test_a_test_without_speed_or_mass_names_its_side_file(tests_folder, bad_input):
    bad_input(report(tests_folder, tests_folder / "a.csv", tests_folder / "bare.csv"),
              "bare.csv", "no impact_speed_m_s and no mass_kg", "side file bare.json")


def test_a_single_test_without_speed_may_take_the_flag(tests_folder, bad_input):
    bad_input(report(tests_folder, tests_folder / "bare.csv", "--mass-kg", "0.16"),
              "bare.csv", "no impact_speed_m_s", "--impact-speed-m-s")


def test_one_speed_flag_for_several_tests(tests_folder, bad_input):
    bad_input(report(tests_folder, tests_folder / "a.csv", tests_folder / "bare.csv",
                     "--impact-speed-m-s", "20"),
              "--impact-speed-m-s", "one speed for 2 test files", "side file")


def test_one_rebound_speed_for_several_tests(tests_folder, bad_input):
    bad_input(report(tests_folder, tests_folder / "a.csv", tests_folder / "bare.csv",
                     "--rebound-speed-m-s", "11"),
              "--rebound-speed-m-s", "one speed for 2 test files")


def test_the_same_test_twice(tests_folder, bad_input):
    bad_input(report(tests_folder, tests_folder / "a.csv", tests_folder / "a.csv"),
              "a.csv is given twice")


def test_the_same_test_twice_under_two_spellings(tests_folder, bad_input):
    bad_input(report(tests_folder, tests_folder / "a.csv",
                     tests_folder / "." / ".." / tests_folder.name / "a.csv"),
              "is given twice", "give each file once")


def test_a_negative_seed(tmp_path, bad_input):
    bad_input(report(tmp_path, "--builtin", "sample", "--models", "hertz", "--seed", "-1"),
              "--seed = -1: allowed range [0, inf)")


def test_a_universal_model_that_does_not_exist(tmp_path, bad_input):
    bad_input(report(tmp_path, "--builtin", "sample", "--models", "universal",
                     "--universal-model", tmp_path / "nomodel"), "nomodel")
