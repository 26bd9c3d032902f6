"""`ballimpact fit` and `ballimpact models`: JSON contract, speed tables, plots, bad input."""

import json

import numpy as np
import pytest

from ballimpact.cli import main
from lumped_cases import SINGLE, clean, noisy

FIT_KEYS = {"model", "params", "units", "rmse_n", "nrmse", "wall_time_s", "standard_errors",
            "history", "seed", "method", "cor", "contact_time_s", "measured"}


def write_test(folder, name, speed, noise=0.01):
    record = noisy(clean("single_element", SINGLE, speed), noise, seed=int(speed))
    path = folder / f"{name}.csv"
    np.savetxt(path, np.c_[record.time_s, record.force_n], delimiter=",", header="time_s,force_n",
               comments="")
    (folder / f"{name}.json").write_text(json.dumps(
        {"mass_kg": record.mass_kg, "impact_speed_m_s": speed,
         "rebound_speed_m_s": record.rebound_speed_m_s}))
    return path


def run(capsys, *argv):
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_fit_json_has_the_contract_keys(capsys, tmp_path):
    path = write_test(tmp_path, "a", 20.0)
    plot = tmp_path / "fit.png"
    code, out, err = run(capsys, "fit", path, "--model", "single_element", "--json", "--plot", plot,
                         "--seed", 4)
    assert code == 0, err
    result = json.loads(out)
    assert FIT_KEYS <= set(result)
    assert result["model"] == "single_element" and result["seed"] == 4
    assert result["units"] == {"k": "N/m^alpha", "alpha": "1", "c": "N s/m"}
    assert result["params"]["alpha"] == pytest.approx(SINGLE["alpha"], rel=0.03)
    assert 0.005 < result["nrmse"] < 0.015
    assert len(result["history"]["best_fitness"]) == 40
    assert plot.stat().st_size > 10_000


def test_fit_several_speeds_writes_a_table(capsys, tmp_path):
    paths = [write_test(tmp_path, name, speed) for name, speed in (("fast", 20.0), ("slow", 10.0))]
    table = tmp_path / "table.csv"
    code, out, err = run(capsys, "fit", *paths, "--model", "hunt_crossley", "--method", "de",
                         "--generations", 15, "--fix", "n=1.5", "--table", table, "--json")
    assert code == 0, err
    result = json.loads(out)
    assert result["table"]["speeds_m_s"] == [10.0, 20.0]
    assert [f["file"] for f in result["fits"]] == [str(paths[1]), str(paths[0])]
    lines = table.read_text().splitlines()
    assert lines[0].startswith("impact_speed_m_s,k [N/m^n]") and len(lines) == 3
    assert "fit 2/2" in err


def test_fit_table_text_output(capsys, tmp_path):
    path = write_test(tmp_path, "a", 20.0)
    code, out, err = run(capsys, "fit", path, "--model", "kelvin_voigt", "--generations", 10)
    assert code == 0, err
    assert "kelvin_voigt by GA" in out and "NRMSE" in out and "COR" in out


def test_models_lists_the_registry(capsys):
    code, out, err = run(capsys, "models", "--json")
    assert code == 0, err
    names = [m["name"] for m in json.loads(out)["models"]]
    assert {"single_element", "three_element", "hunt_crossley", "kelvin_voigt", "hertz",
            "lieberman_johnson", "simon", "single_element_thesis"} <= set(names)


@pytest.mark.parametrize("extra, message", [
    (["--model", "nope"], "model: unknown 'nope'"),
    (["--model", "hertz", "--bound", "k=1:2"], "bounds: unknown parameter"),
    (["--model", "hertz", "--bound", "youngs_modulus_pa=1"], "--bound: expected NAME=LOW:HIGH"),
    (["--model", "hertz", "--fix", "radius_m=abc"], "--fix: expected NAME=VALUE"),
    (["--model", "single_element", "--method", "sa"], "method: must be one of"),
    (["--model", "single_element", "--plot", "out.pdf"], "--plot"),
    (["--model", "single_element", "--table", "/no/such/folder/t.csv"], "--table: folder"),
    (["--model", "single_element", "--table", "t.csv"], "--table: needs several files"),
    (["--model", "single_element", "--seed", "-1"], "seed"),
])
def test_fit_bad_input_exits_2(capsys, tmp_path, extra, message):
    path = write_test(tmp_path, "a", 20.0)
    code, out, err = run(capsys, "fit", path, *extra)
    assert code == 2
    assert err.startswith("error:") and message in err and err.count("\n") == 1
