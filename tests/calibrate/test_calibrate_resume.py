"""Ctrl-C during `ballimpact calibrate` and `--resume` (issue 24): the interrupted command ends
with exit code 130 and one line that is the command to resume with; an interrupt while a
checkpoint is written leaves the previous one whole; and the resumed search ends with the same
evaluations, Pareto front and chosen design as a search that was never stopped (same seed).

Kept cheap: one free constant, population 4, 3 generations, a 4 mm mesh, and a half-sine test
record, so each generation is one vmapped group of four runs."""

from __future__ import annotations

import importlib
import json
import shlex

import numpy as np
import pytest

from ballimpact.cli import build_parser, main

# the module (the package's `search` is the function of the same name)
search_module = importlib.import_module("ballimpact.calibrate.search")

MAT = "layers.ball.material."


@pytest.fixture(scope="module")
def record(tmp_path_factory, half_sine_record):
    return half_sine_record(tmp_path_factory.mktemp("calibrate-resume"), contact_s=4.5e-4)


def argv(record, out):
    return ["calibrate", "--ball", "cricket-universal", "--test", str(record),
            "--free", MAT + "c10_pa=3e6:7e6", "--population", "4", "--generations", "3",
            "--seed", "2", "--element-size-m", "4e-3", "--objectives", "nrmse,contact_time",
            "--out", str(out), "--json"]


def _evaluations(out):
    import pyarrow.parquet as pq

    return pq.read_table(out / "calibration" / "evaluations.parquet").to_pydict()


def test_interrupted_search_resumes_to_the_uninterrupted_result(record, tmp_path, monkeypatch,
                                                                capsys):
    # the reference: never stopped
    assert main(argv(record, tmp_path / "whole")) == 0
    whole = json.loads(capsys.readouterr().out)
    whole_rows = _evaluations(tmp_path / "whole")
    assert sorted(set(whole_rows["generation"])) == [0, 1, 2]

    out = tmp_path / "stopped"
    calls = {"evaluate": 0, "write": 0}
    evaluate, write_table = search_module.evaluate, search_module._write_evaluations

    # 1. Ctrl-C while generation 1's checkpoint is written: its temporary file is half written
    def write_interrupted(problem, rows, folder):
        calls["write"] += 1
        if calls["write"] == 2:
            (folder / "evaluations.tmp.parquet").write_bytes(b"PAR1 half a file")
            raise KeyboardInterrupt
        write_table(problem, rows, folder)

    with monkeypatch.context() as patch:
        patch.setattr(search_module, "_write_evaluations", write_interrupted)
        assert main(argv(record, out)) == 130
    out_text, err = capsys.readouterr()
    lines = err.strip().splitlines()
    errors = [line for line in lines if line.startswith("error:")]
    assert out_text == "" and errors == [lines[-1]]
    prefix = "error: interrupted; resume with: "
    assert lines[-1].startswith(prefix) and lines[-1].endswith(" --resume")
    resume = shlex.split(lines[-1][len(prefix):])
    assert resume[:2] == ["ballimpact", "calibrate"]
    # the same command: it parses to the same options, plus --resume
    given = vars(build_parser().parse_args(argv(record, out)))
    assert vars(build_parser().parse_args(resume[1:])) == {**given, "resume": True}
    assert _evaluations(out)["generation"] == [0] * 4  # the last whole checkpoint

    # 2. resumed, and stopped again by Ctrl-C during generation 2's FE runs
    def evaluate_interrupted(*args, **kwargs):
        calls["evaluate"] += 1
        if calls["evaluate"] == 2:
            raise KeyboardInterrupt
        return evaluate(*args, **kwargs)

    with monkeypatch.context() as patch:
        patch.setattr(search_module, "evaluate", evaluate_interrupted)
        assert main(resume[1:]) == 130
    assert capsys.readouterr().err.strip().splitlines()[-1].endswith(" --resume")
    assert calls["evaluate"] == 2  # generation 0 came from the checkpoint: 1 and 2 ran
    assert _evaluations(out)["generation"] == [0] * 4 + [1] * 4

    # 3. resumed to the end: only generation 2 runs
    def evaluate_counted(*args, **kwargs):
        calls["evaluate"] += 1
        return evaluate(*args, **kwargs)

    with monkeypatch.context() as patch:
        patch.setattr(search_module, "evaluate", evaluate_counted)
        assert main(resume[1:]) == 0
    resumed = json.loads(capsys.readouterr().out)
    assert calls["evaluate"] == 3

    rows = _evaluations(out)
    assert rows.keys() == whole_rows.keys()
    for key, column in whole_rows.items():
        if key == "failed":
            assert rows[key] == column
        else:
            np.testing.assert_allclose(rows[key], column, rtol=1e-12, err_msg=key)
    assert len(resumed["pareto"]) == len(whole["pareto"])
    for a, b in zip(resumed["pareto"], whole["pareto"]):
        assert a["parameters"] == pytest.approx(b["parameters"], rel=1e-12)
        assert a["objectives"] == pytest.approx(b["objectives"], rel=1e-12)
    assert resumed["chosen"]["parameters"] == pytest.approx(whole["chosen"]["parameters"],
                                                            rel=1e-12)
    assert resumed["chosen"]["objectives"] == pytest.approx(whole["chosen"]["objectives"],
                                                            rel=1e-9)
    assert not (out / "calibration" / "evaluations.tmp.parquet").exists()  # replaced since


def test_the_resume_hint_is_the_command_as_given(record, tmp_path, monkeypatch, capsys):
    """A test whose speed is in its side file, then one given as FILE:SPEED: loading them leaves
    the options alone, so the hint holds no --impact-speed-m-s (the last test's speed, which
    would override the first test's side file on resuming)."""
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(search_module, "evaluate", interrupted)
    given = argv(record, tmp_path / "out") + ["--test", f"{record}:25"]
    assert main(given) == 130
    hint = capsys.readouterr().err.strip().splitlines()[-1]
    prefix = "error: interrupted; resume with: "
    assert hint.startswith(prefix) and "--impact-speed-m-s" not in hint
    resume = shlex.split(hint[len(prefix):])
    assert vars(build_parser().parse_args(resume[1:])) == {
        **vars(build_parser().parse_args(given)), "resume": True}


def test_a_search_whose_first_generation_all_fails_stops_at_once(record, tmp_path, monkeypatch,
                                                                capsys):
    """Bounds that give no runnable ball (here every run is refused as unstable) stop after the
    first generation with the first reason and the count, not after every generation."""
    from ballimpact.calibrate.evaluate import Evaluation

    calls = []

    def all_unstable(problem, unit, options):
        calls.append(len(unit))
        n = len(unit)
        return Evaluation(unit, np.full((n, len(problem.objectives)), np.nan),
                          [[] for _ in range(n)],
                          ["test ball: energy balance error 0.31 above the limit 0.05 "
                           "(unstable increment)"] * n, 0.0)

    monkeypatch.setattr(search_module, "evaluate", all_unstable)
    assert main(argv(record, tmp_path / "out")) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert calls == [4]
    assert lines[-1].startswith("error: every design of the search's first generation failed "
                                "(4 of 4), so the search stops")
    assert "energy balance error 0.31" in lines[-1] and MAT + "c10_pa=" in lines[-1]
    assert "check the --free bounds" in lines[-1]
