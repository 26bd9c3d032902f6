"""The FE speed range (`fe.speed_range.FE_SPEED_RANGE_M_S`: the speeds the solvers were checked
at, 0.001-80 m/s axisymmetric, 0.001-45 m/s 3D): refused up front by the API and the command
line, `--allow speed-range` / `allow={"speed-range"}` turns it into a warning, internal callers
stay inside it, slow impacts (0.8 m/s, issue 24) run, and the presets run over the whole range
(slow test, docs/fe.md). The Hertz check of slow impacts: tests/fe/test_fe_low_speed.py."""

import json
import re
import warnings

import pytest

from ballimpact.cli import main
from ballimpact.universal.demo import DEMO_IMPACTS
from ballimpact.errors import InputError, InputWarning
from ballimpact.fe import load_ball, simulate, simulate_batch
from ballimpact.fe import engine
from ballimpact.fe import SolverOptions
from ballimpact.oblique import ImpactCondition, Options3D, simulate_oblique, simulate_oblique_batch
from ballimpact.checks import CHECKS
from ballimpact.fe.speed_range import FE_3D_SPEED_RANGE_M_S, FE_SPEED_RANGE_M_S

LOW, HIGH = FE_SPEED_RANGE_M_S
RANGE_TEXT = f"{LOW:g}..{HIGH:g} m/s"
RANGE_TEXT_3D = "{:g}..{:g} m/s".format(*FE_3D_SPEED_RANGE_M_S)
COARSE = ("--element-size-m", "0.004")


def run(capsys, *argv):
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def no_meshing(monkeypatch):
    """Any attempt to mesh or compile fails the test: the check must come first."""
    def refuse(*args, **kwargs):
        raise AssertionError("meshed before the speed check")
    monkeypatch.setattr(engine, "kernel_for", refuse)


@pytest.mark.parametrize("ball, speed, solver", [
    ("cricket-3layer", "1e6", "axisymmetric"),
    ("cricket-3layer", "0.0002", "axisymmetric"),
    ("cricket-universal", "100", "axisymmetric"),  # both presets stop unstable there
    ("cricket-universal", "1e6", "3d"),
    ("cricket-3layer", "0.0005", "3d"),
    ("cricket-3layer", "50", "3d"),  # inside the axisymmetric range, outside the 3D one
])
def test_cli_refuses_speeds_outside_the_range(capsys, no_meshing, ball, speed, solver):
    code, out, err = run(capsys, "simulate", "--ball", ball, "--speed-m-s", speed,
                         "--solver", solver, "--json")
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("error: ")
    assert f"impact speed {float(speed):g} m/s" in err
    assert (RANGE_TEXT_3D if solver == "3d" else RANGE_TEXT) in err, err
    assert "was checked" in err and "validated" not in err
    assert "--allow speed-range" in err and "np.float64" not in err


def test_cli_non_positive_speed_still_names_the_field(capsys):
    code, out, err = run(capsys, "simulate", "--ball", "cricket-3layer", "--speed-m-s", "-1")
    assert code == 2 and "impact_speed_m_s" in err


def test_cli_unknown_allow_name(capsys):
    code, out, err = run(capsys, "simulate", "--ball", "cricket-3layer", "--speed-m-s", "20",
                         "--allow", "speed-rnage")
    assert code == 2 and "allow: unknown check 'speed-rnage'" in err
    for name in CHECKS:
        assert name in err


def test_cli_help_lists_the_checks(capsys):
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    out = re.sub(r"-\n\s*", "-", capsys.readouterr().out)  # argparse wraps at hyphens
    assert "--allow" in out
    for name in CHECKS:
        assert name in out


@pytest.mark.parametrize("speed", [0.0002, 1e6, float(HIGH) + 0.5])
def test_api_raises_before_meshing(no_meshing, speed):
    ball = load_ball("cricket-3layer")
    with pytest.raises(InputError, match=re.escape(f"impact speed {speed:g} m/s is outside "
                                                   f"{RANGE_TEXT}")):
        simulate(ball, speed)
    with pytest.raises(InputError, match="outside"):
        simulate_batch([ball, ball], [20.0, speed])
    if speed > 1e3:  # not even an impact condition (speed_m_s allowed range (0, 1000])
        return
    with pytest.raises(InputError, match="outside"):
        simulate_oblique(ball, ImpactCondition(speed, 30.0))
    with pytest.raises(InputError, match="outside"):
        simulate_oblique_batch(ball, [ImpactCondition(20.0), ImpactCondition(speed)],
                               Options3D(divisions=8))


def test_api_unknown_allow_name(no_meshing):
    with pytest.raises(InputError, match="allow: unknown check"):
        simulate(load_ball("cricket-3layer"), 20.0, allow={"speed"})


def test_the_ends_of_the_range_are_inside(no_meshing):
    """Exactly at the ends no check fails (the run itself is refused by the fixture)."""
    for speed in FE_SPEED_RANGE_M_S:
        with pytest.raises(AssertionError, match="meshed"), warnings.catch_warnings():
            warnings.simplefilter("ignore", InputWarning)  # 0.001 m/s: contact not resolved
            simulate(load_ball("cricket-3layer"), speed)


def test_api_override_warns_and_runs():
    ball = load_ball("cricket-universal", impact_speed_m_s=5.5)
    with pytest.warns(InputWarning) as caught:
        result = simulate(ball, 0.0005, SolverOptions(element_size_m=4e-3),
                          allow={"speed-range"})
    messages = [str(w.message) for w in caught if issubclass(w.category, InputWarning)]
    assert any(m.startswith("speed-range: impact speed 0.0005 m/s") for m in messages)
    assert 0.0 < result.cor < 1.0 and result.energy_balance_error < 0.01


def test_cli_override_warns_and_runs(capsys):
    code, out, err = run(capsys, "simulate", "--ball", "cricket-universal", "--speed-m-s",
                         0.0005, *COARSE, "--allow", "speed-range", "--json")
    assert code == 0, err
    result = json.loads(out)
    assert any(w.startswith("speed-range: impact speed 0.0005 m/s") for w in result["warnings"])
    assert 0.0 < result["cor"] < 1.0


def test_slow_impact_of_the_issue_runs(capsys):
    """0.8 m/s was refused ("outside 1..60 m/s"); its contact patch spans 3.6 default elements."""
    code, out, err = run(capsys, "simulate", "--ball", "cricket-3layer", "--speed-m-s", 0.8,
                         "--json")
    assert code == 0, err
    result = json.loads(out)
    assert not result["warnings"]  # neither speed-range nor an unresolved contact
    assert 0.9 < result["cor"] < 1.0 and result["energy_balance_error"] < 1e-4
    # the 3-layer ball at 0.5 and 1 m/s: 2.434 and 1.995 ms (docs/fe.md)
    assert 1.995e-3 < result["contact_time_s"] < 2.434e-3


def test_internal_callers_stay_inside_the_range():
    """The demo's impacts and the universal study's default speeds are inside the range."""
    from ballimpact.universal import space

    for _, speed in DEMO_IMPACTS:
        assert LOW <= speed <= HIGH
    low, high, _ = space.PARAMETERS["impact_speed_m_s"]
    assert LOW <= low and high <= HIGH
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no speed-range warning for a speed inside
        engine.check_speeds([LOW, 20.8, HIGH], engine.Axisymmetric())


@pytest.mark.slow
@pytest.mark.parametrize("name", ["cricket-3layer", "cricket-universal"])
@pytest.mark.parametrize("speed", [LOW, 45.0, HIGH])
def test_presets_run_over_the_whole_range(name, speed):
    """The validation of docs/fe.md: default options, both ends of the range and 45 m/s."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)  # table 7-3 held, Drucker ranges
        result = simulate(load_ball(name, impact_speed_m_s=speed), speed)
    assert 0.0 < result.cor < 1.0
    assert result.energy_balance_error < 1e-3
    assert result.peak_force_n > 0 and result.contact_time_s > 0
