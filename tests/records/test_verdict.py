"""Issue 39: a verdict that means it. Force NRMSE, COR, contact time and peak force judged
together, each within its tolerance plus the test's 90% uncertainty; `identify` exits 3 on a
miss naming each criterion, 0 when all pass."""

import json
import math
import runpy
from pathlib import Path

import pytest

from ballimpact.cli import main
from ballimpact.errors import InputError
from ballimpact.verdict import Tolerances, judge

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def comparison(nrmse=0.02, cor_error=0.01, contact=0.01, peak=-0.01):
    return {"force_nrmse": nrmse, "cor_error": cor_error, "cor_measured": 0.5,
            "contact_time_relative_error": contact, "contact_time_measured_s": 1e-3,
            "peak_force_relative_error": peak, "peak_force_measured_n": 1e4}


def test_passed_only_when_every_criterion_passes():
    assert judge(comparison())["passed"] is True
    for name, miss in (("force_nrmse", dict(nrmse=0.06)), ("cor", dict(cor_error=-0.04)),
                       ("contact_time", dict(contact=0.05)), ("peak_force", dict(peak=-0.05))):
        verdict = judge(comparison(**miss))
        assert verdict["passed"] is False and len(verdict["missed"]) == 1, name
        assert [k for k, c in verdict["criteria"].items() if not c["passed"]] == [name]


def test_a_nan_misses_and_the_words_say_by_how_much():
    verdict = judge(comparison(cor_error=math.nan, contact=0.123))
    assert verdict["passed"] is False
    assert "cor is nan" in verdict["missed"][0]
    assert verdict["missed"][1] == ("contact time off by +12.3%, beyond +-4.0% "
                                    "(--max-contact-time-error)")


def test_the_tests_uncertainty_widens_what_is_allowed():
    """A contact time known to +-2% (standard) cannot be held to 4%: 4% + 1.645 x 2%."""
    u = {"P1": 2e-5, "P6": 0.0, "P17": 0.01}
    verdict = judge(comparison(contact=0.06), uncertainty=u)
    assert verdict["criteria"]["contact_time"]["allowed"] == pytest.approx(0.04 + 1.645 * 0.02,
                                                                           rel=1e-4)
    assert verdict["criteria"]["cor"]["allowed"] == pytest.approx(0.03 + 1.645 * 0.01, rel=1e-4)
    assert verdict["passed"] is True


def test_tolerances_refuse_percentages_and_out_of_range():
    with pytest.raises(InputError, match=r"max_cor \(--max-cor-error\) = 3: .* use 0.03"):
        Tolerances(cor=3)
    with pytest.raises(InputError, match=r"--max-nrmse.*\(0, 1\]"):
        Tolerances(force_nrmse=0)


@pytest.fixture(scope="module")
def tests_folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("verdicts")
    runpy.run_path(str(EXAMPLES / "verdict_tests.py"), run_name="verdict_tests")["main"](folder)
    return folder


def identify(capsys, path, *flags):
    capsys.readouterr()
    code = main(["identify", str(path), "--json", *map(str, flags)])
    out, err = capsys.readouterr()
    return code, json.loads(out), err


def test_identify_passes_a_ball_of_its_own_family(tests_folder, capsys):
    code, found, err = identify(capsys, tests_folder / "universal_25.csv")
    assert code == 0, err
    check = found["verification"]
    assert check["passed"] is True and check["missed"] == []
    assert all(c["passed"] for c in check["criteria"].values())


@pytest.mark.parametrize("name", ["half_sine", "stiff"])
def test_identify_exits_3_naming_every_miss(tests_folder, capsys, name):
    """A half-sine whose measured COR (0.35) no ball of that pulse gives, and a ball ten times
    stiffer than the model's range: exit 3, the result printed, one error line naming each
    criterion missed with its flag."""
    code, found, err = identify(capsys, tests_folder / f"{name}.csv")
    assert code == 3
    check = found["verification"]
    assert check["passed"] is False
    errors = [line for line in err.splitlines() if line.startswith("error:")]
    assert len(errors) == 1
    for words in check["missed"]:
        assert words in errors[0]
    assert "(--max-cor-error)" in errors[0] and "(--max-contact-time-error)" in errors[0]
