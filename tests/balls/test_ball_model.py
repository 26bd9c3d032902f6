"""Ball specifications: presets, loading (dict, JSON, TOML), validation, table 7-3 interpolation."""

import copy
import json
import math
import warnings

import pytest

from ballimpact.errors import InputError, InputWarning
from ballimpact.balls.ball import (
    PRESETS,
    TABLE_7_3,
    BallModel,
    Layer,
    describe_presets,
    load_ball,
    universal_parameters,
)
from ballimpact.constitutive import MooneyRivlin, NeoHookean, OgdenHyperfoam

# the example ball specification of docs/balls.md, which is the cricket-3layer preset.
DESIGN_EXAMPLE = {
    "name": "cricket-3layer",
    "layers": [
        {"name": "core", "outer_radius_m": 0.020, "density_kg_m3": 865.0,
         "material": {"model": "mooney_rivlin", "c10_pa": 4.72e6, "c01_pa": -0.45e6,
                      "d1_per_pa": 0.0, "moduli": "long_term",
                      "prony": [{"g": 0.41, "k": 0.0, "tau_s": 7e-5}]}},
        {"name": "midsole", "outer_radius_m": 0.031, "density_kg_m3": 668.0,
         "material": {"model": "ogden_hyperfoam", "terms": [{"mu_pa": 70.3e6, "alpha": 4.0, "nu": 0.0}],
                      "prony": [{"g": 0.0, "k": 0.0, "tau_s": 4.1e-4}]}},
        {"name": "cover", "outer_radius_m": 0.036, "density_kg_m3": 1132.0,
         "material": {"model": "mooney_rivlin", "c10_pa": 4.5e6, "c01_pa": -0.5e6,
                      "d1_per_pa": 0.0}}]}

TOML_BALL = """
name = "two-layer"

[[layers]]
name = "inner"
outer_radius_m = 0.02
density_kg_m3 = 900.0
[layers.material]
model = "neo_hookean"
c10_pa = 1.0e6
moduli = "instantaneous"
[[layers.material.prony]]
g = 0.3
k = 0.0
tau_s = 1.0e-4

[[layers]]
name = "outer"
outer_radius_m = 0.036
density_kg_m3 = 1100.0
[layers.material]
model = "linear_elastic"
youngs_modulus_pa = 5.0e6
poissons_ratio = 0.45
"""


def sphere_mass(radii, densities):
    inner = [0.0, *radii[:-1]]
    return sum(rho * 4 / 3 * math.pi * (r1 ** 3 - r0 ** 3) for r0, r1, rho in zip(inner, radii, densities))


# ---- presets -------------------------------------------------------------------------------------

def test_three_layer_preset_is_the_design_example_and_table_5_1():
    ball = load_ball("cricket-3layer")
    assert ball == BallModel.from_dict(DESIGN_EXAMPLE)
    assert ball.layer_radii_m == (0.020, 0.031, 0.036) and ball.outer_radius_m == 0.036
    assert [layer.name for layer in ball.layers] == ["core", "midsole", "cover"]
    assert isinstance(ball.layers[0].material, MooneyRivlin)
    assert isinstance(ball.layers[1].material, OgdenHyperfoam)
    assert ball.moduli == ("long_term",) * 3
    # table 5-1: 29 + 61 + 80 g = 170 g
    assert ball.mass_kg == pytest.approx(0.170, rel=5e-3)
    for m, m_table in zip(ball.layer_masses_kg, (0.029, 0.061, 0.080)):
        assert m == pytest.approx(m_table, rel=1e-2)
    assert ball.mass_kg == pytest.approx(sphere_mass([0.02, 0.031, 0.036], [865, 668, 1132]), rel=1e-14)
    assert not ball.homogeneous()


@pytest.mark.parametrize("speed", [5.5, 7.0, 15.4, 20.8, 25.0])
def test_universal_preset_mass_and_name(speed):
    ball = load_ball("cricket-universal", impact_speed_m_s=speed)
    assert abs(ball.mass_kg - 0.160) < 1e-12
    assert ball.outer_radius_m == 0.036 and len(ball.layers) == 1 and ball.homogeneous()
    assert ball.name == f"cricket-universal@{float(speed)!r}m/s"
    m = ball.layers[0].material
    p = universal_parameters(speed)
    assert isinstance(m, MooneyRivlin) and m.moduli == "long_term" and m.d1_per_pa == 0.0
    assert (m.c10_pa, m.c01_pa) == (p["c10_pa"], p["c01_pa"])
    assert len(m.prony) == 1 and m.prony[0].k == 0.0
    assert (m.prony[0].g, m.prony[0].tau_s) == (p["g1"], p["tau1_s"])
    assert load_ball(ball.name) == ball  # the recorded name loads again


def test_universal_name_reads_25():
    assert load_ball("cricket-universal", 25).name == "cricket-universal@25.0m/s"


def test_universal_needs_the_speed():
    with pytest.raises(InputError, match="cricket-universal needs the impact speed"):
        load_ball("cricket-universal")
    with pytest.raises(InputError, match="impact_speed_m_s"):
        load_ball("cricket-universal", impact_speed_m_s=-3.0)
    with pytest.raises(InputError, match="disagrees"):
        load_ball("cricket-universal@20.8m/s", impact_speed_m_s=10.0)


def test_table_7_3_exact_at_the_rows_and_linear_between():
    for row in TABLE_7_3:
        p = universal_parameters(row["speed_m_s"])
        for key in ("c10_pa", "c01_pa", "g1", "tau1_s"):
            assert p[key] == row[key]
    assert universal_parameters(25.0) == {"impact_speed_m_s": 25.0, "c10_pa": 4.02e6,
                                          "c01_pa": -0.41e6, "g1": 0.79, "tau1_s": 8e-5}
    mid = universal_parameters(15.4)  # midway between the 10 and 20.8 m/s rows
    for key in ("c10_pa", "c01_pa", "g1", "tau1_s"):
        assert mid[key] == pytest.approx(0.5 * (TABLE_7_3[1][key] + TABLE_7_3[2][key]), rel=1e-12)
    assert mid["c10_pa"] == pytest.approx(5.435e6, rel=1e-12)
    q = universal_parameters(5.5 + 0.25 * 4.5)  # a quarter of the way from 5.5 to 10
    assert q["c10_pa"] == pytest.approx(5.24e6 + 0.25 * (6.12e6 - 5.24e6), rel=1e-12)


def test_inside_the_table_no_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        universal_parameters(5.5)
        universal_parameters(25.0)
        load_ball("cricket-universal", 12.0)


@pytest.mark.parametrize("speed, row", [(3.0, 0), (40.0, -1)])
def test_outside_the_table_holds_the_end_row_with_a_warning(speed, row):
    with pytest.warns(InputWarning, match="outside the table's 5.5-25 m/s"):
        p = universal_parameters(speed)
    assert p["c10_pa"] == TABLE_7_3[row]["c10_pa"] and p["tau1_s"] == TABLE_7_3[row]["tau1_s"]
    with pytest.warns(InputWarning, match="outside"):
        ball = load_ball("cricket-universal", speed)
    assert ball.layers[0].material.c10_pa == TABLE_7_3[row]["c10_pa"]


def test_describe_presets_is_json_and_complete():
    info = describe_presets()
    json.dumps(info)
    assert tuple(p["name"] for p in info) == PRESETS
    three, universal = info[:2]
    assert three["mass_kg"] == pytest.approx(0.170, rel=5e-3) and "table 5-1" in three["source"]
    assert "0.170 kg" in three["description"] and "29 + 61 + 80 g" in three["description"]
    assert [layer["outer_radius_m"] for layer in three["layers"]] == [0.020, 0.031, 0.036]
    assert [layer["model"] for layer in three["layers"]] == ["mooney_rivlin", "ogden_hyperfoam",
                                                              "mooney_rivlin"]
    assert universal["mass_kg"] == 0.160 and universal["needs_impact_speed"]
    assert "table 7-3" in universal["source"]
    rows = universal["speed_table"]["rows"]  # thesis table 7-3, as a speed-table ball file
    assert [r["speed_m_s"] for r in rows] == [5.5, 10.0, 20.8, 25.0]
    assert set(rows[0]) == {"speed_m_s", "c10_pa", "c01_pa", "g1", "tau1_s"}
    assert universal["speed_range_m_s"] == [5.5, 25.0]


# ---- round trips and files -----------------------------------------------------------------------

@pytest.mark.parametrize("name, speed", [("cricket-3layer", None), ("cricket-universal", 20.8)])
def test_to_dict_round_trip(name, speed):
    ball = load_ball(name, speed)
    d = ball.to_dict()
    assert BallModel.from_dict(d) == ball
    assert load_ball(json.loads(json.dumps(d))) == ball
    assert BallModel.from_dict(d).to_dict() == d


def test_json_file(tmp_path):
    path = tmp_path / "my_ball.json"
    path.write_text(json.dumps(DESIGN_EXAMPLE))
    assert load_ball(path) == load_ball("cricket-3layer")
    assert load_ball(str(path)) == load_ball("cricket-3layer")
    spec = copy.deepcopy(DESIGN_EXAMPLE)
    del spec["name"]
    path.write_text(json.dumps(spec))
    assert load_ball(path).name == "my_ball"  # name defaults to the file's stem


def test_toml_file(tmp_path):
    path = tmp_path / "ball.toml"
    path.write_text(TOML_BALL)
    ball = load_ball(path)
    assert ball.name == "two-layer" and ball.layer_radii_m == (0.02, 0.036)
    inner = ball.layers[0].material
    assert isinstance(inner, NeoHookean) and inner.moduli == "instantaneous"
    assert inner.prony[0].g == 0.3
    assert ball.mass_kg == pytest.approx(sphere_mass([0.02, 0.036], [900, 1100]), rel=1e-14)
    assert BallModel.from_dict(ball.to_dict()) == ball


def test_file_errors(tmp_path):
    with pytest.raises(InputError, match="neither a preset"):
        load_ball(tmp_path / "missing.json")
    with pytest.raises(InputError, match="neither a preset"):
        load_ball("cricket-4layer")
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(InputError, match="not valid JSON"):
        load_ball(bad)
    bad_toml = tmp_path / "bad.toml"
    bad_toml.write_text("name = ")
    with pytest.raises(InputError, match="not valid TOML"):
        load_ball(bad_toml)
    spec = copy.deepcopy(DESIGN_EXAMPLE)
    spec["layers"][2]["density_kg_m3"] = 0.0
    bad.write_text(json.dumps(spec))
    with pytest.raises(InputError, match=r"bad\.json: ball\.layers\[2\]\.density_kg_m3"):
        load_ball(bad)


# ---- validation: every error names the key -------------------------------------------------------

def _set(path, value):
    def edit(d):
        *head, last = path
        for key in head:
            d = d[key]
        if value is _DELETE:
            del d[last]
        else:
            d[last] = value
    return edit


_DELETE = object()

BAD_SPECS = [
    (_set(["colour"], "red"), "ball: unknown key 'colour'"),
    (_set(["layers"], _DELETE), "ball: missing key 'layers'"),
    (_set(["layers"], []), r"ball\.layers: expected a non-empty list"),
    (_set(["layers", 0, "thickness_m"], 1.0), r"ball\.layers\[0\]: unknown key 'thickness_m'"),
    (_set(["layers", 1, "outer_radius_m"], _DELETE), r"ball\.layers\[1\]: missing key 'outer_radius_m'"),
    (_set(["layers", 1, "outer_radius_m"], 0.020),
     r"ball\.layers\[1\]\.outer_radius_m = 0\.02: must be greater than the previous layer's 0\.02"),
    (_set(["layers", 2, "outer_radius_m"], 0.025),
     r"ball\.layers\[2\]\.outer_radius_m = 0\.025: must be greater than the previous layer's 0\.031"),
    (_set(["layers", 0, "outer_radius_m"], -0.01), r"ball\.layers\[0\]\.outer_radius_m = -0\.01: allowed range"),
    (_set(["layers", 0, "outer_radius_m"], 0.0), r"ball\.layers\[0\]\.outer_radius_m = 0"),
    (_set(["layers", 0, "outer_radius_m"], float("nan")), r"ball\.layers\[0\]\.outer_radius_m = nan: expected a finite number in \(0, inf\)"),
    (_set(["layers", 0, "outer_radius_m"], "20 mm"), r"ball\.layers\[0\]\.outer_radius_m = '20 mm': expected a finite"),
    (_set(["layers", 1, "density_kg_m3"], 0.0), r"ball\.layers\[1\]\.density_kg_m3 = 0: allowed range"),
    (_set(["layers", 1, "density_kg_m3"], float("inf")), r"ball\.layers\[1\]\.density_kg_m3 = inf: expected a finite"),
    (_set(["layers", 2, "material"], _DELETE), r"ball\.layers\[2\]: missing key 'material'"),
    (_set(["layers", 0, "material", "c10_pa"], _DELETE), r"ball\.layers\[0\]\.material: missing key 'c10_pa'"),
    (_set(["layers", 0, "material", "model"], "rubber"), r"ball\.layers\[0\]\.material\.model = 'rubber'"),
    (_set(["layers", 0, "material", "moduli"], "peak"), r"ball\.layers\[0\]\.material\.moduli = 'peak'"),
    (_set(["layers", 0, "material", "prony", 0, "g"], 1.5), r"ball\.layers\[0\]\.material\.prony\[0\]\.g = 1\.5"),
    (_set(["layers", 1, "material", "terms", 0, "alpha"], _DELETE),
     r"ball\.layers\[1\]\.material\.terms\[0\]: missing key 'alpha'"),
    (_set(["layers", 2, "material", "c01_pa"], float("nan")), r"ball\.layers\[2\]\.material\.c01_pa = nan: expected a finite number"),
    (_set(["layers", 2, "name"], "core"), r"ball\.layers\[2\]\.name = 'core': layer names must be unique"),
    (_set(["layers", 2, "name"], 7), r"ball\.layers\[2\]\.name = 7"),
    (_set(["name"], ""), r"ball\.name = ''"),
]


@pytest.mark.parametrize("edit, message", BAD_SPECS, ids=[m[:40] for _, m in BAD_SPECS])
def test_validation_names_the_key(edit, message):
    spec = copy.deepcopy(DESIGN_EXAMPLE)
    edit(spec)
    with pytest.raises(InputError, match=message):
        load_ball(spec)


def test_not_an_object():
    with pytest.raises(InputError, match="ball: expected an object"):
        BallModel.from_dict([1, 2])
    with pytest.raises(InputError, match=r"ball\.layers\[0\]: expected an object"):
        BallModel.from_dict({"layers": [3.0]})


def test_layer_name_defaults():
    spec = copy.deepcopy(DESIGN_EXAMPLE)
    for layer in spec["layers"]:
        del layer["name"]
    assert [layer.name for layer in load_ball(spec).layers] == ["layer0", "layer1", "layer2"]


def test_direct_construction_is_checked():
    m = NeoHookean(c10_pa=1e6)
    with pytest.raises(InputError, match="must be greater than the previous"):
        BallModel("b", (Layer("a", 0.02, 1000.0, m), Layer("b", 0.01, 1000.0, m)))
    with pytest.raises(InputError, match="density_kg_m3"):
        BallModel("b", (Layer("a", 0.02, -1.0, m),))
    with pytest.raises(InputError, match="at least one layer"):
        BallModel("b", ())


# ---- variants ------------------------------------------------------------------------------------

def test_with_moduli():
    ball = load_ball("cricket-3layer")
    inst = ball.with_moduli("instantaneous")
    assert inst.moduli == ("instantaneous",) * 3 and ball.moduli == ("long_term",) * 3
    assert inst.name == ball.name and inst.layer_radii_m == ball.layer_radii_m
    assert inst.mass_kg == ball.mass_kg
    core, core_inst = ball.layers[0].material, inst.layers[0].material
    assert (core_inst.c10_pa, core_inst.c01_pa, core_inst.prony) == (core.c10_pa, core.c01_pa, core.prony)
    # long-term constants are scaled up by 1 / (1 - g) to instantaneous ones; instantaneous are not
    assert core.shear_modulus_pa() == pytest.approx(core_inst.shear_modulus_pa() / (1 - 0.41), rel=1e-12)
    assert core_inst.shear_modulus_pa() == pytest.approx(2 * (4.72e6 - 0.45e6), rel=1e-12)
    assert inst.with_moduli("long_term") == ball
    assert BallModel.from_dict(inst.to_dict()) == inst
    with pytest.raises(InputError, match="moduli = 'peak'"):
        ball.with_moduli("peak")


def test_homogeneous_two_identical_layers():
    m = NeoHookean(c10_pa=1e6)
    assert BallModel("b", (Layer("a", 0.02, 1000.0, m), Layer("b", 0.03, 1000.0, m))).homogeneous()
    assert not BallModel("b", (Layer("a", 0.02, 1000.0, m), Layer("b", 0.03, 1001.0, m))).homogeneous()
