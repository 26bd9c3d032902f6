"""The FE verbs of the command line: simulate, balls, demo (DESIGN.md "Verbs")."""

import json

import numpy as np
import pytest

from ballimpact.cli import SolverDefaults, main
from ballimpact.fe import SolverOptions

COARSE = ("--element-size-m", "0.004")
SIMULATE_KEYS = {"features", "cor", "peak_force_n", "contact_time_s", "energy_balance_error",
                 "elements", "steps", "stable_time_increment_s", "wall_time_s", "moduli",
                 "materials", "impact_speed_m_s", "rebound_speed_m_s", "energies_j", "warnings"}


def run(capsys, *argv):
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_simulate_json_csv_plot(capsys, tmp_path):
    csv, plot = tmp_path / "h.csv", tmp_path / "h.png"
    code, out, err = run(capsys, "simulate", "--ball", "cricket-universal", "--speed-m-s", 10,
                         *COARSE, "--json", "--csv", csv, "--plot", plot)
    assert code == 0, err
    result = json.loads(out)
    assert SIMULATE_KEYS <= set(result)
    assert result["moduli"] == "long_term"
    assert result["materials"]["layers"][0]["material"]["model"] == "mooney_rivlin"
    assert 0.0 < result["cor"] < 1.0 and result["energy_balance_error"] < 0.01
    # the features of the simulated pulse agree with the solver's own figures
    assert result["features"]["P6"] == pytest.approx(result["peak_force_n"], rel=0.01)
    assert result["features"]["P1"] == pytest.approx(result["contact_time_s"], rel=0.02)
    assert result["features"]["P17"] == pytest.approx(result["cor"], rel=0.01)
    table = np.genfromtxt(csv, delimiter=",", names=True)
    assert {"time_s", "contact_force_n", "kinetic_energy_j", "viscous_dissipation_j"} <= set(
        table.dtype.names)
    assert len(table) == result["steps"]
    assert plot.stat().st_size > 10_000


def test_simulate_text_and_moduli_override(capsys):
    code, out, err = run(capsys, "simulate", "--ball", "cricket-universal", "--speed-m-s", 10,
                         *COARSE, "--moduli", "instantaneous")
    assert code == 0, err
    assert "instantaneous moduli" in out and "COR" in out


def test_simulate_ball_file(capsys, tmp_path):
    spec = {"name": "rubber", "layers": [{"name": "all", "outer_radius_m": 0.03,
                                          "density_kg_m3": 1100.0,
                                          "material": {"model": "neo_hookean", "c10_pa": 1e6}}]}
    path = tmp_path / "rubber.json"
    path.write_text(json.dumps(spec))
    code, out, err = run(capsys, "simulate", "--ball", path, "--speed-m-s", 5, *COARSE, "--json")
    assert code == 0, err
    assert json.loads(out)["ball"] == "rubber"


@pytest.mark.parametrize("extra, message", [
    (("--ball", "cricket-universal", "--speed-m-s", "10", "--angle-deg", "30"), "--angle-deg"),
    (("--ball", "cricket-universal", "--speed-m-s", "-1"), "impact_speed_m_s"),
    (("--ball", "no-such-ball", "--speed-m-s", "10"), "no-such-ball"),
    (("--ball", "cricket-universal", "--speed-m-s", "10", "--solver", "4d"), "--solver"),
    (("--ball", "cricket-universal", "--speed-m-s", "10", "--solver", "3d", "--angle-deg", "95"),
     "angle_deg"),
    (("--ball", "cricket-universal", "--speed-m-s", "10", "--solver", "3d", "--divisions", "7"),
     "divisions"),
    (("--ball", "cricket-universal", "--speed-m-s", "10", "--solver", "3d", "--animate",
      "out.txt"), "--animate"),
    (("--ball", "cricket-universal", "--speed-m-s", "10", "--solver", "3d", "--target",
      "no-such-target.json"), "--target"),
    (("--ball", "cricket-universal", "--speed-m-s", "10", "--element-size-m", "0"),
     "element_size_m"),
    (("--ball", "cricket-universal", "--speed-m-s", "10", "--moduli", "short"), "moduli"),
])
def test_simulate_bad_input_exits_2(capsys, extra, message):
    code, out, err = run(capsys, "simulate", *extra)
    assert code == 2 and out == ""
    assert message in err and "Traceback" not in err


def test_balls_lists_presets(capsys):
    code, out, err = run(capsys, "balls", "--json")
    assert code == 0, err
    names = {b["name"] for b in json.loads(out)["balls"]}
    assert {"cricket-3layer", "cricket-universal"} <= names


def test_cli_defaults_match_the_solver():
    assert SolverDefaults.element_size_m == SolverOptions().element_size_m
    assert SolverDefaults.penalty_scale == SolverOptions().penalty_scale
    assert SolverDefaults.integration == SolverOptions().integration
    assert SolverDefaults.precision == SolverOptions().precision


def test_demo_json_and_plot(capsys, tmp_path):
    plot = tmp_path / "demo.png"
    code, out, err = run(capsys, "demo", "--json", "--plot", plot)
    assert code == 0, err
    impacts = json.loads(out)["impacts"]
    assert [i["impact_speed_m_s"] for i in impacts] == [25.0, 20.8]
    for impact in impacts:
        assert impact["energy_balance_error"] < 0.01
        assert 0.0 < impact["cor"] < 1.0
        assert 5e3 < impact["peak_force_n"] < 3e4 and 5e-4 < impact["contact_time_s"] < 2e-3
    assert plot.stat().st_size > 10_000
