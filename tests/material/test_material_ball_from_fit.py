"""`material.ball_file.write_ball` (the library side of `ballimpact material ball`) and the
material files it reads (`material.files`), called from Python."""

import json
import math

import pytest

from ballimpact.errors import InputError
from ballimpact.fe import load_ball
from ballimpact.material.ball_file import write_ball
from ballimpact.material.files import read_json, read_material, read_prony_terms, write_material

CORE = {"model": "mooney_rivlin", "c10_pa": 4.72e6, "c01_pa": -0.45e6, "d1_per_pa": 0.0,
        "moduli": "long_term"}
COVER = {"model": "neo_hookean", "c10_pa": 4.0e6, "d1_per_pa": 0.0, "moduli": "long_term"}


def test_material_files_round_trip_and_name_the_file(tmp_path):
    path = tmp_path / "core.json"
    write_material(path, CORE)
    assert read_material(path) == CORE and path.read_text().endswith("}\n")
    printed = tmp_path / "fit.json"  # the JSON `material fit --json` prints
    printed.write_text(json.dumps({"material": COVER, "r2": {"overall": 0.99}}))
    assert read_material(printed) == COVER
    prony = tmp_path / "prony.json"
    prony.write_text(json.dumps({"model": "prony", "prony": [{"g": 0.4, "k": 0.0, "tau_s": 1e-4}]}))
    assert read_prony_terms(prony) == [{"g": 0.4, "k": 0.0, "tau_s": 1e-4}]
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    with pytest.raises(InputError, match=r"^--x .*bad.json: not JSON \(.*line 1\)$"):
        read_json(bad, "--x ")
    with pytest.raises(InputError, match="no 'prony' list"):
        read_prony_terms(path)
    listed = tmp_path / "list.json"
    listed.write_text("[1]")
    with pytest.raises(InputError, match="expected a material object"):
        read_material(listed)


def test_one_layer_ball_with_prony_terms(tmp_path):
    core, relax = tmp_path / "core.json", tmp_path / "relax.json"
    write_material(core, CORE)
    relax.write_text(json.dumps({"prony": [{"g": 0.41, "k": 0.0, "tau_s": 7e-5}]}))
    out = tmp_path / "ball.json"
    result = write_ball(out, [core], 0.072, mass_kg=0.16, prony=[(None, str(relax))])
    volume = 4.0 / 3.0 * math.pi * 0.036 ** 3
    assert result["name"] == "ball" and result["out"] == str(out)
    assert result["diameter_m"] == pytest.approx(0.072, rel=1e-12)
    assert result["mass_kg"] == pytest.approx(0.16, rel=1e-12)
    (layer,) = result["layers"]
    assert layer["name"] == "core" and layer["model"] == "mooney_rivlin"
    assert layer["density_kg_m3"] == pytest.approx(0.16 / volume, rel=1e-12)
    assert layer["prony_terms"] == 1
    ball = load_ball(out)
    assert [(t.g, t.k, t.tau_s) for t in ball.layers[0].material.prony] == [(0.41, 0.0, 7e-5)]


def test_two_layers_auto_density_and_named_prony_layer(tmp_path):
    core, cover, relax = tmp_path / "core.json", tmp_path / "cover.json", tmp_path / "r.json"
    write_material(core, CORE)
    write_material(cover, COVER)
    relax.write_text(json.dumps({"prony": [{"g": 0.3, "tau_s": 1e-3}]}))
    out = tmp_path / "two.json"
    result = write_ball(out, [core, cover], 0.072, mass_kg=0.16, layer_radii_m=[0.03],
                        densities_kg_m3=[None, 1200.0], layer_names=["in", "out"],
                        prony=[("out", relax)], name="pair")
    inner = 4.0 / 3.0 * math.pi * 0.03 ** 3
    shell = 4.0 / 3.0 * math.pi * (0.036 ** 3 - 0.03 ** 3)
    assert result["name"] == "pair"
    assert [e["name"] for e in result["layers"]] == ["in", "out"]
    assert result["layers"][0]["density_kg_m3"] == pytest.approx((0.16 - 1200 * shell) / inner,
                                                                 rel=1e-12)
    assert [e["prony_terms"] for e in result["layers"]] == [0, 1]
    with pytest.raises(InputError, match=r"^--prony .*r.json: 2 layers; name the layer"):
        write_ball(out, [core, cover], 0.072, mass_kg=0.16, layer_radii_m=[0.03],
                   densities_kg_m3=[None, 1200.0], prony=[(None, relax)])
    with pytest.raises(InputError, match=r"--prony side=.*no layer 'side'"):
        write_ball(out, [core, cover], 0.072, mass_kg=0.16, layer_radii_m=[0.03],
                   densities_kg_m3=[None, 1200.0], prony=[("side", relax)])
    with pytest.raises(InputError, match=r"a ball file ends in .json"):
        write_ball(tmp_path / "ball.toml", [core], 0.072, mass_kg=0.16)
