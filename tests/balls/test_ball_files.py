"""Ball files (docs/balls.md): the shipped examples load and run, and every preset's entry of
`ballimpact balls --json`, saved as a file, is a ball file that loads to the preset."""

import json
from pathlib import Path

import pytest

from ballimpact.cli import main
from ballimpact.errors import InputError
from ballimpact.fe import describe_presets, load_ball, simulate
from ballimpact.constitutive import MooneyRivlin, NeoHookean, OgdenHyperfoam
from ballimpact.fe import SolverOptions

EXAMPLES = Path(__file__).parents[2] / "examples" / "balls"
COARSE = SolverOptions(element_size_m=4e-3)


def run(capsys, *argv):
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_the_examples_are_there():
    assert {p.name for p in EXAMPLES.glob("*.json")} >= {
        "one-layer-rubber.json", "cricket-3layer.json", "cricket-universal.json"}


def test_one_layer_example():
    ball = load_ball(EXAMPLES / "one-layer-rubber.json")
    assert ball.name == "one-layer-rubber" and len(ball.layers) == 1
    assert isinstance(ball.layers[0].material, NeoHookean)
    assert ball.mass_kg == pytest.approx(0.1427, rel=1e-3)
    assert "Illustrative" in ball.description and ball.source


def test_three_layer_example_is_the_preset():
    ball = load_ball(EXAMPLES / "cricket-3layer.json")
    assert ball == load_ball("cricket-3layer")
    assert [type(layer.material) for layer in ball.layers] == [MooneyRivlin, OgdenHyperfoam,
                                                                MooneyRivlin]
    assert "thesis chapter 5" in ball.description


@pytest.mark.parametrize("speed", [5.5, 12.0, 25.0])
def test_universal_example_is_the_preset(speed):
    ball = load_ball(EXAMPLES / "cricket-universal.json", impact_speed_m_s=speed)
    assert ball == load_ball("cricket-universal", impact_speed_m_s=speed)
    assert ball.name == f"cricket-universal@{speed!r}m/s"
    with pytest.raises(InputError, match="needs the impact speed"):
        load_ball(EXAMPLES / "cricket-universal.json")


@pytest.mark.parametrize("name, speed", [
    pytest.param("one-layer-rubber", 10.0, marks=pytest.mark.slow),  # a structure of its own:
    ("cricket-3layer", 20.8), ("cricket-universal", 20.8)])          # ~8 s to compile
def test_each_example_runs(name, speed):
    result = simulate(load_ball(EXAMPLES / f"{name}.json", impact_speed_m_s=speed), speed, COARSE)
    assert 0.0 < result.cor < 1.0 and result.energy_balance_error < 0.01


def test_cli_runs_an_example(capsys):
    code, out, err = run(capsys, "simulate", "--ball", EXAMPLES / "cricket-3layer.json",
                         "--speed-m-s", 20.8, "--element-size-m", 0.004, "--json")
    assert code == 0, err
    result = json.loads(out)
    assert result["ball"] == "cricket-3layer"
    assert result["materials"]["description"].startswith("Three-layer Kookaburra")


@pytest.mark.parametrize("index", [0, 1])
def test_balls_json_entry_is_a_ball_file(capsys, tmp_path, index):
    code, out, err = run(capsys, "balls", "--json")
    assert code == 0, err
    entry = json.loads(out)["balls"][index]
    path = tmp_path / f"{entry['name']}.json"
    path.write_text(json.dumps(entry))
    for speed in (7.0, 20.8, 25.0):
        ball = load_ball(path, impact_speed_m_s=speed)
        assert ball == load_ball(entry["name"], impact_speed_m_s=speed)
        assert ball.name == load_ball(entry["name"], impact_speed_m_s=speed).name
        assert ball.description == entry["description"] and ball.source == entry["source"]


def test_simulate_accepts_a_balls_json_entry(capsys, tmp_path):
    code, out, err = run(capsys, "balls", "--json")
    path = tmp_path / "universal.json"
    path.write_text(json.dumps(json.loads(out)["balls"][1]))
    code, out, err = run(capsys, "simulate", "--ball", path, "--speed-m-s", 20.8,
                         "--element-size-m", 0.004, "--json")
    assert code == 0, err
    assert json.loads(out)["ball"] == "cricket-universal@20.8m/s"


def test_every_preset_entry_loads():
    for entry in describe_presets():
        assert load_ball(json.loads(json.dumps(entry)), impact_speed_m_s=20.8) == load_ball(
            entry["name"], impact_speed_m_s=20.8)


@pytest.mark.parametrize("index, change, words", [
    (0, {"mass_kg": 0.2}, "mass_kg = 0.2: disagrees with 0.169929"),
    (0, {"moduli": "instantaneous"}, "moduli = 'instantaneous': disagrees"),
    (0, {"needs_impact_speed": True}, "needs_impact_speed = True: disagrees"),
    (0, {"description": 3}, "description: expected a string"),
    (0, {"colour": "red"}, "unknown key 'colour'"),
    (1, {"outer_radius_m": 0.05}, "outer_radius_m = 0.05: disagrees with 0.036"),
    (1, {"speed_range_m_s": [5.0, 25.0]}, "speed_range_m_s = [5, 25]: disagrees with [5.5, 25]"),
])
def test_derived_keys_must_agree(capsys, tmp_path, index, change, words):
    entry = {**describe_presets()[index], **change}
    path = tmp_path / "ball.json"
    path.write_text(json.dumps(entry))
    code, out, err = run(capsys, "simulate", "--ball", path, "--speed-m-s", 20.8)
    assert code == 2 and out == "" and words in err and err.count("\n") == 1


def test_layer_derived_keys_must_agree():
    entry = describe_presets()[0]
    entry["layers"][1]["model"] = "neo_hookean"
    with pytest.raises(InputError, match=r"layers\[1\]\.model = 'neo_hookean': disagrees"):
        load_ball(entry)
    entry = describe_presets()[0]
    entry["layers"][0]["mass_kg"] = 1.0
    with pytest.raises(InputError, match=r"layers\[0\]\.mass_kg = 1: disagrees"):
        load_ball(entry)


def test_description_round_trips():
    spec = json.loads((EXAMPLES / "one-layer-rubber.json").read_text())
    ball = load_ball(spec)
    assert ball.to_dict() == spec
    assert load_ball(ball.to_dict()) == ball
