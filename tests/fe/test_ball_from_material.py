"""`ballimpact material ball` (issue 39 B): a ball file from `material fit --out` results, a
diameter and a mass (and layers), which `load_ball` reads and `simulate` runs."""

import json
import math

import pytest

from ballimpact.cli import main
from ballimpact.fe import estimate_run, load_ball
from ballimpact.material.ball_file import ball_from_materials

CORE = {"model": "mooney_rivlin", "c10_pa": 4.72e6, "c01_pa": -0.45e6, "d1_per_pa": 0.0,
        "moduli": "long_term"}
COVER = {"model": "neo_hookean", "c10_pa": 4.0e6, "d1_per_pa": 0.0, "moduli": "long_term"}


@pytest.fixture
def materials(tmp_path):
    core, cover = tmp_path / "core.json", tmp_path / "cover.json"
    core.write_text(json.dumps(CORE))
    # the JSON `material fit --json` prints is read too (its "material")
    cover.write_text(json.dumps({"material": COVER, "r2": {"overall": 0.99}}))
    relax = tmp_path / "relax.json"
    relax.write_text(json.dumps({"model": "prony", "terms": [{"g": 0.41, "tau_s": 7e-5}],
                                 "prony": [{"g": 0.41, "k": 0.0, "tau_s": 7e-5}]}))
    return core, cover, relax


def run_json(capsys, argv):
    capsys.readouterr()
    assert main([str(a) for a in argv] + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_one_layer_density_from_the_mass_loads_and_estimates(materials, tmp_path, capsys):
    core, _, relax = materials
    out = tmp_path / "ball.json"
    result = run_json(capsys, ["material", "ball", core, "--diameter-m", 0.072, "--mass-kg", 0.16,
                               "--prony", relax, "--out", out])
    volume = 4.0 / 3.0 * math.pi * 0.036 ** 3
    ball = load_ball(out)
    assert ball.name == "ball" and len(ball.layers) == 1
    assert ball.layers[0].density_kg_m3 == pytest.approx(0.16 / volume, rel=1e-12)
    assert ball.layers[0].density_kg_m3 == pytest.approx(818.6982669336182, rel=1e-12)
    assert ball.mass_kg == pytest.approx(0.16, rel=1e-12)
    assert ball.outer_radius_m == 0.036
    material = ball.layers[0].material
    assert material.model == "mooney_rivlin" and material.c10_pa == 4.72e6
    assert [(t.g, t.k, t.tau_s) for t in material.prony] == [(0.41, 0.0, 7e-5)]
    assert result["mass_kg"] == pytest.approx(0.16, rel=1e-12)
    assert result["layers"][0]["prony_terms"] == 1
    # the same constants as the cricket-universal preset at 20.8 m/s but c10/c01: a runnable run
    estimate = estimate_run(ball, 20.0)
    assert estimate.steps > 100 and estimate.elements > 100


def test_layers_with_an_auto_density_and_a_checked_mass(materials, tmp_path, capsys):
    core, cover, _ = materials
    out = tmp_path / "two.json"
    run_json(capsys, ["material", "ball", core, cover, "--diameter-m", 0.072, "--mass-kg", 0.16,
                      "--layer-radii-m", 0.02, "--densities-kg-m3", "auto,800", "--out", out])
    ball = load_ball(out)
    assert [layer.name for layer in ball.layers] == ["core", "cover"]
    assert ball.layer_radii_m == (0.02, 0.036)
    cover_mass = 800.0 * 4.0 / 3.0 * math.pi * (0.036 ** 3 - 0.02 ** 3)
    assert ball.layers[1].density_kg_m3 == 800.0
    assert ball.layer_masses_kg[0] == pytest.approx(0.16 - cover_mass, rel=1e-12)
    assert ball.layers[1].material.model == "neo_hookean"
    # every density given: the mass is checked (1%), the radii may end with the ball's
    densities = [ball.layers[0].density_kg_m3, 800.0]
    spec = ball_from_materials([CORE, COVER], 0.072, mass_kg=0.1605,
                               layer_radii_m=[0.02, 0.036], densities_kg_m3=densities)
    assert load_ball(spec) == load_ball({**spec, "name": "ball"})
    assert [layer["name"] for layer in spec["layers"]] == ["core", "layer1"]


@pytest.mark.slow
def test_written_ball_runs_in_simulate(materials, tmp_path, capsys):
    core, _, relax = materials
    out = tmp_path / "ball.json"
    run_json(capsys, ["material", "ball", core, "--diameter-m", 0.072, "--mass-kg", 0.16,
                      "--prony", relax, "--out", out])
    run = run_json(capsys, ["simulate", "--ball", out, "--speed-m-s", 20,
                            "--element-size-m", 6e-3])
    assert 0.3 < run["cor"] < 0.95 and abs(run["energy_balance_error"]) < 0.05
    assert run["peak_force_n"] > 1000


def test_bad_input(materials, tmp_path, bad_input):
    core, cover, relax = materials
    out = tmp_path / "x.json"
    ball = ["material", "ball", core, "--out", out]
    two = ["material", "ball", core, cover, "--out", out, "--diameter-m", 0.072]
    bad_input([*ball, "--diameter-m", 72, "--mass-kg", 0.16], "--diameter-m", "0.01..0.4 m",
              "millimetres", "0.072")
    bad_input([*ball, "--diameter-m", 0.072, "--mass-kg", 160], "--mass-kg", "grams", "0.16")
    bad_input([*ball, "--diameter-m", 0.072, "--mass-kg", 20], "--mass-kg", "density",
              "10..20000 kg/m^3")
    bad_input([*ball, "--diameter-m", 0.072], "--mass-kg")
    bad_input([*ball, "--diameter-m", "nan", "--mass-kg", 0.16], "--diameter-m", "nan")
    bad_input([*two, "--mass-kg", 0.16, "--layer-radii-m", "0.04", "--densities-kg-m3",
               "auto,800"], "--layer-radii-m", "must increase")
    bad_input([*two, "--mass-kg", 0.16, "--layer-radii-m", "20", "--densities-kg-m3",
               "auto,800"], "--layer-radii-m", "millimetres", "0.02")
    bad_input([*two, "--mass-kg", 0.16, "--densities-kg-m3", "auto,800"], "--layer-radii-m",
              "2 layers")
    bad_input([*two, "--mass-kg", 0.16, "--layer-radii-m", "0.02"], "--densities-kg-m3",
              "'auto'")
    bad_input([*two, "--mass-kg", 0.16, "--layer-radii-m", "0.02", "--densities-kg-m3",
               "800,900"], "--mass-kg", "allowed 1%")
    bad_input([*two, "--mass-kg", 0.16, "--layer-radii-m", "0.02", "--densities-kg-m3",
               "auto,0.8"], "--densities-kg-m3", "g/cm^3")
    bad_input([*two, "--mass-kg", 0.16, "--layer-radii-m", "0.02", "--densities-kg-m3",
               "auto,auto"], "--densities-kg-m3", "at most one")
    bad_input([*two, "--mass-kg", 0.16, "--layer-radii-m", "0.02", "--densities-kg-m3",
               "auto,800", "--prony", relax], "--prony", "LAYER=FILE")
    bad_input([*two, "--mass-kg", 0.16, "--layer-radii-m", "0.02", "--densities-kg-m3",
               "auto,800", "--prony", f"shell={relax}"], "--prony", "no layer 'shell'")
    bad_input([*ball, "--diameter-m", 0.072, "--mass-kg", 0.16, "--prony", core], "--prony",
              "no 'prony' list")
    bad_input(["material", "ball", core, "--out", tmp_path / "x.toml", "--diameter-m", 0.072,
               "--mass-kg", 0.16], "--out", ".json")
    soft = tmp_path / "soft.json"
    soft.write_text(json.dumps({**CORE, "c10_pa": 4.72, "c01_pa": -0.45}))  # MPa as Pa
    bad_input(["material", "ball", soft, "--out", out, "--diameter-m", 0.072, "--mass-kg", 0.16],
              "shear modulus", "MPa")
