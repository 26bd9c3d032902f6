"""`identify` refuses a user's mistakes in one line before anything is run (issue 24): missing
or incomplete records, speeds outside the model's training speeds, bad models, limits and
output paths, tables that cannot be tables. All fail before the FE check (fast)."""

import json
import shutil
from importlib import resources
from pathlib import Path

import pytest

DATA = Path(str(resources.files("ballimpact") / "data"))


@pytest.fixture
def sample(tmp_path):
    """The built-in sample test (20.8 m/s) and its side file, copied as a user's files."""
    for suffix in (".csv", ".json"):
        shutil.copy(DATA / f"sample_impact{suffix}", tmp_path / f"sample{suffix}")
    return tmp_path / "sample.csv"


@pytest.fixture
def twin(sample):
    """A second test at the sample's speed."""
    for suffix in (".csv", ".json"):
        shutil.copy(sample.with_suffix(suffix), sample.with_name(f"twin{suffix}"))
    return sample.with_name("twin.csv")


def test_missing_record(bad_input, tmp_path):
    bad_input(["identify", tmp_path / "nothere.csv"], "nothere.csv", "no such file")


def test_record_is_a_folder(bad_input, tmp_path):
    bad_input(["identify", tmp_path, "--no-verify"], "is a folder")


def test_no_mass_and_no_side_file(bad_input, sample):
    sample.with_suffix(".json").unlink()
    bad_input(["identify", sample, "--impact-speed-m-s", 20.8, "--no-verify"], "mass_kg",
              "--mass-kg")


def test_several_tests_without_speeds(bad_input, sample, twin):
    # the check for tests at one speed must leave missing speeds to the record's own refusal
    for path in (sample, twin):
        path.with_suffix(".json").write_text(json.dumps({"mass_kg": 0.16}))
    bad_input(["identify", sample, twin, "--no-verify"], "sample.csv", "impact speed is required")


def test_negative_mass(bad_input, sample):
    bad_input(["identify", sample, "--mass-kg", -0.16, "--no-verify"], "mass_kg")


@pytest.mark.parametrize("speed", [50, 3])
def test_speed_outside_the_models_training_speeds(bad_input, sample, speed):
    bad_input(["identify", sample, "--impact-speed-m-s", speed],
              f"impact speed {speed} m/s", "training speeds 5..45 m/s", "--allow speed-range",
              "sample.csv")


def test_speed_alias_goes_through_the_same_check(bad_input, sample):
    bad_input(["identify", sample, "--speed-m-s", 46], "impact speed 46 m/s", "5..45")


def test_missing_model(bad_input, sample, tmp_path):
    bad_input(["identify", sample, "--model", tmp_path / "none.json"], "model", "none.json",
              "not found")


def test_model_that_is_not_json(bad_input, sample, tmp_path):
    shutil.copy(DATA / "cricket-universal-model.npz", tmp_path / "broken.npz")
    (tmp_path / "broken.json").write_text("{not json")
    bad_input(["identify", sample, "--model", tmp_path / "broken.json"], "model",
              "broken.json", "JSON")


@pytest.mark.parametrize("value, words", [
    ("-1", ["--max-nrmse", "-1", "(0, 1]"]),
    ("0", ["--max-nrmse", "(0, 1]"]),
    ("5", ["--max-nrmse", "looks like a percentage", "use 0.05"]),
    ("nan", ["--max-nrmse", "nan"]),
    ("inf", ["--max-nrmse", "inf"]),
])
def test_max_nrmse_out_of_range(bad_input, sample, value, words):
    bad_input(["identify", sample, "--max-nrmse", value], *words)


@pytest.mark.parametrize("verb", ["identify", "fit"])
@pytest.mark.parametrize("flag", ["--max-cor-error", "--max-contact-time-error",
                                  "--max-peak-force-error"])
@pytest.mark.parametrize("value, words", [("-0.1", ["(0, 1]"]), ("0", ["(0, 1]"]),
                                          ("4", ["looks like a percentage", "use 0.04"]),
                                          ("nan", ["nan"])])
def test_every_tolerance_out_of_range(bad_input, sample, verb, flag, value, words):
    """Issue 39: the FE check's and the model check's tolerances, each refused by its flag."""
    model = ["--model", "hunt_crossley"] if verb == "fit" else []
    bad_input([verb, sample, *model, flag, value], flag, *words)


def test_max_nrmse_without_the_fe_check(bad_input, sample):
    bad_input(["identify", sample, "--max-nrmse", 0.05, "--no-verify"], "--max-nrmse",
              "--no-verify")


def test_ball_out_in_a_missing_folder(bad_input, sample, tmp_path):
    bad_input(["identify", sample, "--ball-out", tmp_path / "no" / "ball.json"], "--ball-out",
              "does not exist")


def test_ball_out_wrong_suffix(bad_input, sample, tmp_path):
    bad_input(["identify", sample, "--ball-out", tmp_path / "ball.txt"], "--ball-out", ".json")


def test_ball_out_over_the_tests_side_file(bad_input, sample):
    bad_input(["identify", sample, "--ball-out", sample.with_suffix(".json")], "--ball-out",
              "side file", "overwrite")
    assert json.loads(sample.with_suffix(".json").read_text())["mass_kg"] == 0.16  # untouched


def test_table_with_one_test(bad_input, sample, tmp_path):
    bad_input(["identify", sample, "--table", tmp_path / "t.csv"], "--table", "several")


def test_table_wrong_suffix(bad_input, sample, twin, tmp_path):
    bad_input(["identify", sample, twin, "--table", tmp_path / "t.json"], "--table", ".csv")


def test_table_over_a_test_record(bad_input, sample, twin):
    bad_input(["identify", sample, twin, "--table", twin], "--table", "overwrite")


def test_repeats_of_mixed_masses(bad_input, sample, twin):
    side = twin.with_suffix(".json")
    side.write_text(side.read_text().replace('"mass_kg": 0.16', '"mass_kg": 0.145'))
    bad_input(["identify", sample, twin, "--no-verify"], "mixed masses", "twin.csv", "0.145")


def test_same_file_twice(bad_input, sample):
    bad_input(["identify", sample, sample], "sample.csv", "given twice")


def test_unknown_refine(bad_input, sample):
    bad_input(["identify", sample, "--refine", "fe"], "--refine", "surrogate")


def test_unknown_allow_name(bad_input, sample):
    bad_input(["identify", sample, "--allow", "speedrange"], "allow", "speed-range")


def test_plot_wrong_suffix(bad_input, sample, tmp_path):
    bad_input(["identify", sample, "--plot", tmp_path / "p.pdf"], "--plot", ".png")


# ---- --compression (issue 42, item 4): refused before any FE run -----------------------------
def _curve(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def test_compression_missing_file(bad_input, sample, tmp_path):
    bad_input(["identify", sample, "--compression", tmp_path / "squeeze.csv"],
              "--compression", "squeeze.csv", "no such file")


def test_compression_bad_header(bad_input, sample, tmp_path):
    curve = _curve(tmp_path / "squeeze.csv", "deflection_in,force_n\n1,10\n2,25\n3,45\n")
    bad_input(["identify", sample, "--compression", curve], "squeeze.csv", "deflection_in",
              "deflection_mm")


def test_compression_deflections_not_increasing(bad_input, sample, tmp_path):
    curve = _curve(tmp_path / "squeeze.csv", "deflection_mm,force_n\n1,10\n3,25\n2,45\n")
    bad_input(["identify", sample, "--compression", curve], "squeeze.csv", "line 4",
              "does not increase")


def test_compression_without_the_fe_check(bad_input, sample, tmp_path):
    curve = _curve(tmp_path / "squeeze.csv", "deflection_mm,force_n\n1,10\n2,25\n3,45\n")
    bad_input(["identify", sample, "--compression", curve, "--no-verify"], "--compression",
              "--no-verify")


@pytest.mark.parametrize("value", [0, 1.5, -0.05])
def test_compression_tolerance_out_of_range(bad_input, sample, tmp_path, value):
    curve = _curve(tmp_path / "squeeze.csv", "deflection_mm,force_n\n1,10\n2,25\n3,45\n")
    bad_input(["identify", sample, "--compression", curve, "--max-compression-error", value],
              "max_compression_error (--max-compression-error)")


def test_compression_tolerance_without_a_compression_test(bad_input, sample):
    bad_input(["identify", sample, "--max-compression-error", 0.1], "--max-compression-error",
              "needs --compression")


def test_an_output_over_the_compression_test(bad_input, sample, twin, tmp_path):
    curve = _curve(tmp_path / "squeeze.csv", "deflection_mm,force_n\n1,10\n2,25\n3,45\n")
    bad_input(["identify", sample, twin, "--compression", curve, "--table", curve],
              "--table", "squeeze.csv", "one of the inputs")


def test_compression_test_is_a_folder(bad_input, sample, tmp_path):
    bad_input(["identify", sample, "--compression", tmp_path], "--compression", "is a folder")


def test_compression_deeper_than_the_ball(bad_input, sample, tmp_path):
    # millimetres in a deflection_m column: 6.35 m on a 72 mm ball
    curve = _curve(tmp_path / "squeeze.csv", "deflection_m,force_n\n2,100\n4,600\n6.35,1600\n")
    bad_input(["identify", sample, "--compression", curve], "squeeze.csv", "6.35 m",
              "deflection_mm")


def test_compression_force_in_kn_under_a_newton_header(bad_input, sample, tmp_path):
    # a 72 mm ball's 1.6 kN at 6.35 mm typed in kN under force_n: no sports ball is that soft
    curve = _curve(tmp_path / "squeeze.csv",
                   "deflection_mm,force_n\n2,0.25\n4,0.8\n6.35,1.6\n")
    bad_input(["identify", sample, "--compression", curve], "squeeze.csv",
              "force at the largest deflection", "looks like kN", "use 1600 N")
