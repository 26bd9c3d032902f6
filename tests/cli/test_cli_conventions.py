"""The command line's shared conventions (issue 24): non-finite numbers refused in every float
flag, one name for the impact speed everywhere, unknown flags naming the nearest known one,
Ctrl-C as exit 130 with one line, and exit 3 for a failed check the user asked for."""

import json

import pytest

from ballimpact.cli import balls as cli_balls
from ballimpact.cli import build_parser, main
from ballimpact.errors import CheckFailed

NON_FINITE = [
    (["simulate", "--ball", "cricket-universal", "--speed-m-s", "nan"], "--speed-m-s"),
    (["simulate", "--ball", "cricket-universal", "--speed-m-s", "20", "--angle-deg", "inf"],
     "--angle-deg"),
    (["features", "x.csv", "--mass-kg", "nan"], "--mass-kg"),
    (["fit", "x.csv", "--model", "hertz", "--impact-speed-m-s=-inf"], "--impact-speed-m-s"),
    (["identify", "x.csv", "--rebound-speed-m-s", "NaN"], "--rebound-speed-m-s"),
    (["export", "--ball", "cricket-universal", "--speed-m-s", "1e999", "--format", "abaqus",
      "--out", "x.inp"], "--speed-m-s"),
    (["video", "frames/", "--fps", "nan", "--ball-diameter-m", "0.072"], "--fps"),
    (["report", "a.csv", "--mass-kg", "inf"], "--mass-kg"),
]


@pytest.mark.parametrize("argv, flag", NON_FINITE, ids=[a[0] + a[-1] for a, _ in NON_FINITE])
def test_non_finite_flags_are_refused_naming_the_flag(bad_input, argv, flag):
    bad_input(argv, flag, "not a finite number")


def test_a_word_where_a_number_belongs_is_refused(bad_input):
    bad_input(["simulate", "--ball", "cricket-universal", "--speed-m-s", "fast"],
              "--speed-m-s", "'fast' is not a number")


@pytest.mark.parametrize("argv, nearest", [
    (["simulate", "--ball", "cricket-universal", "--speed-m-s", "20", "--sped", "3"],
     "--speed-m-s"),
    (["features", "x.csv", "--mass-kgg", "0.16"], "--mass-kg"),
    (["universal", "run", "study", "--runs", "3", "--sede", "1"], "--seed"),
    (["export", "--ball", "cricket-universal", "--fromat", "abaqus"], "--format"),
])
def test_an_unknown_flag_names_the_nearest_known_one(bad_input, argv, nearest):
    # a typo may first show as a missing required flag: the same hint is added
    bad_input(argv, f"did you mean {nearest}?")


def _option(parser, verb, name):
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    return sub.choices[verb]._option_string_actions.get(name)


@pytest.mark.parametrize("verb", ["simulate", "export", "features", "fit", "identify", "report",
                                  "calibrate"])
def test_both_speed_flags_name_the_same_option_in_every_verb(verb):
    parser = build_parser()
    parser.parse_known_args(["balls"])  # the aliases are added on the first parse
    one, other = (_option(parser, verb, name) for name in ("--speed-m-s", "--impact-speed-m-s"))
    assert one is not None and one is other


def test_the_alias_sets_the_verbs_own_destination():
    args = build_parser().parse_args(["simulate", "--ball", "cricket-universal",
                                      "--impact-speed-m-s", "12.5"])
    assert args.speed_m_s == 12.5
    args = build_parser().parse_args(["features", "x.csv", "--speed-m-s", "7"])
    assert args.impact_speed_m_s == 7.0


def test_ctrl_c_is_exit_130_with_one_line_and_the_verbs_resume_hint(monkeypatch, capsys):
    def interrupted(args):
        args.resume_hint = "resume with: ballimpact universal run study --resume"
        raise KeyboardInterrupt

    monkeypatch.setattr(cli_balls, "run_balls", interrupted)
    assert main(["balls"]) == 130
    out, err = capsys.readouterr()
    assert out == ""
    assert err.strip().splitlines() == [
        "error: interrupted; resume with: ballimpact universal run study --resume"]


def test_a_failed_check_is_exit_3_with_the_result_still_printed(monkeypatch, capsys):
    def checked(args):
        raise CheckFailed("FE check NRMSE 0.29 above --max-nrmse 0.05", {"nrmse": 0.29})

    monkeypatch.setattr(cli_balls, "run_balls", checked)
    assert main(["balls", "--json"]) == 3
    out, err = capsys.readouterr()
    assert json.loads(out)["nrmse"] == 0.29
    assert err.strip().splitlines()[-1] == (
        "error: check failed: FE check NRMSE 0.29 above --max-nrmse 0.05")


@pytest.mark.parametrize("argv, name", [
    (["fit", "x.csv", "--model", "hertz", "--fix", "k=1e6", "--fix", "k=2e6"], "k"),
    (["fit", "x.csv", "--model", "hertz", "--bound", "k=1:2", "--bound", "k=1:3"], "k"),
    (["universal", "run", "study", "--range", "g1=0:0.5", "--range", "g1=0.1:0.6"], "g1"),
])
def test_a_name_given_twice_is_refused(bad_input, argv, name):
    bad_input(argv, f"{name} given twice")
