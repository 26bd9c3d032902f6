"""A verb prints the library's text of its result (each package's `*_lines` functions), so that
a Python user gets the command's text; and the command stays thin: small modules whose only
printing is the library's lines (issue 40)."""

from pathlib import Path

import pytest

import ballimpact.cli as cli
from ballimpact.bats.study import ball_on_bat
from ballimpact.bats.text import ball_on_bat_lines
from ballimpact.cli import main
from ballimpact.lumped import describe_models
from ballimpact.lumped.text import models_lines
from ballimpact.records import datasets
from ballimpact.records.options import RecordOptions
from ballimpact.records.summaries import features_of_files
from ballimpact.records.text import datasets_lines, features_lines
from ballimpact.standards import describe_methods
from ballimpact.standards.text import methods_lines

CLI = Path(cli.__file__).parent
SPEED_SET = ["builtin:speed-set/synthetic_10.0_m_s.csv", "builtin:speed-set/synthetic_20.8_m_s.csv"]


def printed(capsys, *argv) -> str:
    assert main([str(a) for a in argv]) == 0
    return capsys.readouterr().out


def text(lines: list[str]) -> str:
    return "".join(line + "\n" for line in lines)


@pytest.mark.parametrize("files, argv", [
    (["builtin:sample"], []),
    (SPEED_SET, []),
    (["builtin:sample"], ["--filter", "loess", "--pulse-method", "samples"]),
])
def test_features_prints_the_librarys_text(capsys, files, argv):
    out = printed(capsys, "features", *files, *argv)
    options = (RecordOptions(filter="loess", method="samples", uncertainty=False) if argv
               else RecordOptions())
    assert out == text(features_lines(*features_of_files(files, options=options)))


@pytest.mark.parametrize("argv, lines", [
    (["models"], lambda: models_lines(describe_models())),
    (["standard", "--list"], lambda: methods_lines(describe_methods())),
    (["data", "list"], lambda: datasets_lines([d.to_dict() for d in
                                               datasets.DATASETS.values()])),
    (["bat", "--bat", "baseball-wood-34in", "--ball", "hc:0.145:2e7:0.1", "--speed-m-s", "30",
      "--impact-m", "0.75"],
     lambda: ball_on_bat_lines(ball_on_bat("baseball-wood-34in", _hc_ball(), 30.0, [0.75]))),
])
def test_listings_and_results_print_the_librarys_text(capsys, argv, lines):
    assert printed(capsys, *argv) == text(lines())


def _hc_ball():
    from ballimpact.bats.ball_law import HuntCrossleyBall

    return HuntCrossleyBall(0.145, 2e7, 0.1, name="hc:0.145:2e7:0.1")


def test_cli_modules_stay_small():
    sizes = {path.name: len(path.read_text().splitlines()) for path in CLI.glob("*.py")}
    assert max(sizes.values()) <= 300, sizes
    assert sum(sizes.values()) <= 2500, sizes


def test_verbs_print_no_text_of_their_own():
    """Outside the conventions (`__init__`: errors, warnings, the JSON), a verb's output is the
    library's lines (`common.print_lines`), or progress on stderr."""
    for path in CLI.glob("*.py"):
        if path.name != "__init__.py":
            assert 'print(f"' not in path.read_text(), path.name
