"""What the command prints around its results: a closed pipe on stdout (`| head -1`) ends it
quietly, and messages show numbers plainly (not NumPy 2's `np.float64(3.0)`)."""

import subprocess
import sys

import numpy as np
import pytest

from ballimpact import InputError
from ballimpact import lumped
from ballimpact.cli import main
from ballimpact.checks import shown

COMMAND = [sys.executable, "-m", "ballimpact.cli"]


@pytest.mark.parametrize("argv", [["models", "--json"], ["models"]])
def test_closed_stdout_ends_quietly(argv):
    """The reader closes the pipe before the command writes: no traceback, exit code 1 (as
    Python's "Note on SIGPIPE" recommends)."""
    process = subprocess.Popen(COMMAND + argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    process.stdout.close()
    err = process.stderr.read().decode()
    process.stderr.close()
    assert process.wait(timeout=120) == 1
    assert "Traceback" not in err and "BrokenPipeError" not in err and "Exception" not in err
    assert err == ""


@pytest.mark.parametrize("argv", [["models", "--json"], ["models"]])
def test_pipe_into_head(argv):
    line = " ".join(COMMAND + argv) + " | head -1"
    done = subprocess.run(["bash", "-o", "pipefail", "-c", line], capture_output=True, text=True,
                          timeout=120)
    assert "Traceback" not in done.stderr and done.stderr == ""
    assert done.stdout == ("{\n" if "--json" in argv else done.stdout.splitlines()[0] + "\n")
    assert done.returncode in (0, 1)  # 1 when head had gone before the command wrote


def test_shown_prints_plain_numbers():
    assert shown(np.float64(3.0)) == "3"
    assert shown(np.float64(0.1)) == "0.1"
    assert shown(np.int64(-1)) == "-1"
    assert shown((np.float64(1.5), 2.0)) == "[1.5, 2]"
    assert shown(np.array([1.0, np.nan])) == "[1, nan]"
    assert shown("one") == "'one'"


#: each call takes `pulse`, which makes a clean single-element record when called
@pytest.mark.parametrize("call, message", [
    (lambda pulse: lumped.simulate("kelvin_voigt", {"k": np.float64("nan"), "c": 1.0},
                                   impact_speed_m_s=10.0, mass_kg=0.16),
     "params.k = nan: expected a finite number"),
    (lambda pulse: lumped.simulate("kelvin_voigt", {"k": 1e6, "c": 1.0}, impact_speed_m_s=10.0,
                                   mass_kg=np.float64(-0.16)),
     "mass_kg = -0.16: allowed range (0, inf)"),
    (lambda pulse: lumped.hunt_crossley_lambda(np.float64(1.5), 10.0),
     "cor = 1.5: allowed range (0, 0.999999]"),
    (lambda pulse: lumped.hunt_crossley_cor(np.float64(-0.1), 10.0),
     "lambda = -0.1: allowed range [0, inf) s/m"),
    (lambda pulse: lumped.fit(pulse(), "single_element", cor_weight=np.float64(-1.0)),
     "cor_weight = -1: allowed range [0, inf)"),
    (lambda pulse: lumped.fit(pulse(), "single_element", seed=np.int64(-1)),
     "seed = -1: allowed range [0, inf)"),
    (lambda pulse: lumped.fit(pulse(), "single_element", bounds={"alpha": np.array([2.0, 1.0])}),
     "bounds.alpha: need low < high, got [2, 1]"),
    (lambda pulse: lumped.fit(pulse(), "single_element", fixed={"alpha": np.float64("inf")}),
     "fixed.alpha: must be finite, got inf"),
])
def test_messages_show_plain_numbers(call, message, single_params, clean_pulse):
    """Each of these printed `np.float64(...)` (or `np.int64(...)`) under NumPy 2."""
    with pytest.raises(InputError) as raised:
        call(lambda: clean_pulse("single_element", single_params))
    assert str(raised.value) == message


def test_cli_bound_message_shows_plain_numbers(capsys, tmp_path, single_params, clean_pulse):
    path = tmp_path / "a.csv"
    record = clean_pulse("single_element", single_params)
    np.savetxt(path, np.c_[record.time_s, record.force_n], delimiter=",",
               header="time_s,force_n", comments="")
    code = main(["fit", str(path), "--model", "single_element", "--mass-kg", "0.16",
                 "--impact-speed-m-s", "20", "--bound", "k=0:1e8"])
    err = capsys.readouterr().err
    assert code == 2
    assert err == ("error: bounds.k low = 0: allowed range (0, inf) (searched on a log "
                   "scale)\n")
