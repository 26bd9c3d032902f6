"""`export.read_abaqus_file` (what `ballimpact import-material` prints): an ABAQUS deck read back
into materials or a whole ball, checked as a ball file would be, errors naming the file."""

import pytest

from ballimpact.errors import InputError
from ballimpact.export import ImpactSetup, export_ball, read_abaqus_file
from ballimpact.fe import load_ball


@pytest.fixture(scope="module")
def deck(tmp_path_factory):
    ball = load_ball("cricket-3layer")
    path = tmp_path_factory.mktemp("deck") / "three.inp"
    export_ball(ball, path, "abaqus", setup=ImpactSetup(20.0))
    return ball, path


def test_materials_of_a_deck(deck):
    ball, path = deck
    out = read_abaqus_file(path)
    assert list(out) == ["materials"]
    read = {m["name"]: m for m in out["materials"]}
    assert set(read) == {layer.name for layer in ball.layers}
    for layer in ball.layers:
        assert read[layer.name]["density_kg_m3"] == pytest.approx(layer.density_kg_m3,
                                                                  rel=1e-9)
        assert read[layer.name]["material"]["model"] == layer.material.model


def test_the_ball_of_a_deck(deck):
    ball, path = deck
    out = read_abaqus_file(str(path), "mm-tonne-s", ball=True)
    spec = out["ball"]
    assert list(out) == ["ball"] and spec["name"] == ball.name
    assert [layer["name"] for layer in spec["layers"]] == [layer.name for layer in ball.layers]
    for read, layer in zip(spec["layers"], ball.layers):
        assert read["outer_radius_m"] == pytest.approx(layer.outer_radius_m, rel=1e-6)
    assert load_ball(spec).mass_kg == pytest.approx(ball.mass_kg, rel=1e-6)


def test_errors_name_the_file(deck, tmp_path):
    _, path = deck
    with pytest.raises(InputError, match="a folder, not an ABAQUS input file"):
        read_abaqus_file(tmp_path)
    missing = tmp_path / "none.inp"
    with pytest.raises(InputError, match=f"^{missing}: cannot read"):
        read_abaqus_file(missing)
    empty = tmp_path / "empty.inp"
    empty.write_text("*HEADING\n")
    with pytest.raises(InputError, match=f"^{empty}: units: the file does not say its units"):
        read_abaqus_file(empty)
    with pytest.raises(InputError, match=f"^{empty}: no \\*MATERIAL block found"):
        read_abaqus_file(empty, "si")
    with pytest.raises(InputError, match="units"):
        read_abaqus_file(path, "furlongs")
    with pytest.raises(InputError, match="no-such-check"):
        read_abaqus_file(path, allow=["no-such-check"])
