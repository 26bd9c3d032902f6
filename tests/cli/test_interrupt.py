"""Ctrl-C during the first compilation of a run (issue 39 C): exit 130 and the one line, never a
segmentation fault from the interpreter's shutdown racing XLA's compiler threads.
`benchmarks/ctrl_c_check.py` runs the full check (20 tries over 0.5-6 s, simulate and calibrate);
here one try at a fixed delay, in a cold cache, so that the compilation is under way."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest


def _command():
    script = Path(sys.executable).parent / "ballimpact"
    return [str(script)] if script.is_file() else [sys.executable, "-m", "ballimpact.cli"]


def _interrupt(argv, delay_s, tmp_path):
    env = {**os.environ, "BALLIMPACT_CACHE_DIR": str(tmp_path / "cache")}
    proc = subprocess.Popen([*_command(), *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env=env, preexec_fn=lambda: signal.signal(signal.SIGINT,
                                                                      signal.SIG_DFL))
    time.sleep(delay_s)
    assert proc.poll() is None, "the run ended before the interrupt: make it longer"
    start = time.perf_counter()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    return proc.returncode, out.decode(), err.decode(), time.perf_counter() - start


@pytest.mark.parametrize("delay_s", [2.0])
def test_ctrl_c_during_the_first_compilation_exits_130_with_one_line(delay_s, tmp_path):
    code, out, err, after = _interrupt(["simulate", "--ball", "cricket-3layer", "--speed-m-s",
                                        "20", "--json"], delay_s, tmp_path)
    assert code == 130, (code, err)
    assert err.strip().splitlines() == ["error: interrupted"], err
    assert out == ""
    assert after < 30.0  # it does not wait for the run to finish


def test_ignored_sigint_stays_ignored():
    """A background job (SIGINT ignored, as a shell starts it) is not made interruptible."""
    from ballimpact import cli

    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        cli._set_sigint(cli._interrupt_at_once)
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)
