"""A compilation's silent seconds get a line (issue 43 item 1): `progress.Waiting` says nothing
for a short wait, then redraws what it is doing, the time spent and what is left of the expected
time (or that it takes longer); `fe.programs.CompileWait` names the kernel and keeps the time a
real compilation took for the next one; the command line's process announces them."""

import json
import subprocess
import sys
import time

import pytest

from ballimpact import progress
from ballimpact.fe import programs
from ballimpact.progress import Waiting, format_wait


def test_format_wait_counts_down_honestly():
    assert format_wait("compiling", 3.2, 8.0) == "compiling: 3 s, about 5 s left"
    assert format_wait("compiling", 9.4, 8.0) == "compiling: 9 s, longer than the expected 8 s"
    assert format_wait("compiling", 4.0, None) == "compiling: 4 s"


def test_a_short_wait_prints_nothing(capsys):
    with Waiting("compiling", 5.0, quiet_s=0.5) as wait:
        time.sleep(0.05)
    assert wait.lines == 0 and capsys.readouterr().err == ""


def test_a_long_wait_says_what_it_is_doing_and_finishes_its_line(capsys):
    with Waiting("compiling the axisymmetric kernel", 0.2, quiet_s=0.1, interval_s=0.1) as wait:
        time.sleep(0.45)
    err = capsys.readouterr().err
    lines = [line.strip() for line in err.replace("\r", "\n").splitlines() if line.strip()]
    assert wait.lines >= 2 and err.endswith("\n") and not progress.line_open()
    assert lines[0].startswith("compiling the axisymmetric kernel: 0 s, about ")
    assert lines[-1] == "compiling the axisymmetric kernel: 0 s, longer than the expected 0 s"


class _Geometry:
    n_elements = 2318


class _Kernel:  # a kernel as CompileWait sees it: its module says the geometry
    geom = _Geometry()


@pytest.fixture
def folder(tmp_path):
    programs.use_folder(tmp_path)
    yield tmp_path
    programs.use_folder(None)


def test_compile_wait_names_the_kernel_and_keeps_a_real_compilation_time(folder, monkeypatch):
    wait = programs.CompileWait.of_kernel(_Kernel(), batched=True, members=8)
    assert wait.waiting.text == ("compiling the axisymmetric kernel for 2,318 elements, a batch of "
                                 "8 (once per ball layout)")
    assert wait.waiting.expected_s == programs.DEFAULT_COMPILE_S["axisymmetric"]
    monkeypatch.setattr(programs, "COMPILE_MIN_S", 0.05)
    with programs.CompileWait.of_kernel(_Kernel(), batched=False, members=1):
        time.sleep(0.1)  # "compiles" for 0.1 s: kept
    kept = json.loads((folder / "compile_seconds.json").read_text())
    assert kept["axisymmetric"] == pytest.approx(0.1, abs=0.05)  # a kernel without layers
    kept_s = programs.CompileWait.of_kernel(_Kernel(), False, 1).waiting.expected_s
    assert kept_s == kept["axisymmetric"]
    with programs.CompileWait.of_kernel(_Kernel(), batched=False, members=1):
        pass  # found in JAX's cache: not a compilation, the time kept stays
    assert json.loads((folder / "compile_seconds.json").read_text()) == kept


def test_only_the_command_line_process_announces_waits():
    assert not progress.waits_announced()  # the library (and in-process calls of main) stay quiet
    code = ("import ballimpact.cli as c, ballimpact.progress as p, sys; sys.argv = ['ballimpact', "
            "'models', '--json']\ntry:\n    c.main()\nfinally:\n    print(p.waits_announced(), "
            "file=sys.stderr)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert done.stderr.strip().splitlines()[-1] == "True"
