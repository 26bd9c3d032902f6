"""Built-in data by name (issue 39, item 7): `ballimpact data list|copy`, and `builtin:NAME` in
any verb's file arguments (records, folders of records, material tests)."""

import json

import numpy as np
import pytest

from ballimpact.records import datasets
from ballimpact.cli import main
from ballimpact.calibrate.files import parse_test
from ballimpact.records.loaders import load_record
from ballimpact.material.data import parse_spec, read_test
from ballimpact.records.repeats import expand_records

DATA = datasets.DATA


def run(capsys, *argv):
    capsys.readouterr()
    code = main([str(arg) for arg in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_list_names_what_each_is_and_its_files(capsys):
    code, out, err = run(capsys, "data", "list", "--json")
    assert code == 0, err
    sets = {d["name"]: d for d in json.loads(out)["datasets"]}
    assert {"sample", "speed-set", "treloar-uniaxial", "treloar-biaxial",
            "treloar-planar"} <= set(sets)
    for d in sets.values():
        assert d["argument"] == "builtin:" + d["name"] and d["description"] and d["source"]
        for name in d["files"]:
            assert (DATA / name).is_file(), name
    assert sets["speed-set"]["kind"] == "records"
    assert len([f for f in sets["speed-set"]["files"] if f.endswith(".csv")]) == 4
    assert "Treloar" in sets["treloar-planar"]["source"]
    code, out, _ = run(capsys, "data", "list")
    assert code == 0 and "builtin:treloar-uniaxial (material test)" in out


def test_copy_a_record_and_a_folder(capsys, tmp_path):
    code, out, err = run(capsys, "data", "copy", "sample", tmp_path, "--json")
    assert code == 0, err
    for name in ("sample_impact.csv", "sample_impact.json"):
        assert (tmp_path / name).read_bytes() == (DATA / name).read_bytes()
    assert json.loads(out)["files"] == [str(tmp_path / "sample_impact.csv"),
                                        str(tmp_path / "sample_impact.json")]
    dest = tmp_path / "new"
    code, _, err = run(capsys, "data", "copy", "builtin:speed-set", dest)
    assert code == 0, err
    copied = sorted(p.name for p in (dest / "speed_set").iterdir())
    assert copied == sorted(p.name for p in (DATA / "speed_set").iterdir()
                            if p.suffix in (".csv", ".json"))
    # a copy is a record like any other: no longer built-in
    record = load_record(dest / "speed_set" / "synthetic_10.0_m_s.csv")
    assert "builtin" not in record.metadata and record.impact_speed_m_s == 10.0
    code, _, err = run(capsys, "data", "copy", "sample", tmp_path, "--force")
    assert code == 0, err


def test_builtin_record_is_the_installed_file(capsys):
    by_name = load_record("builtin:sample")
    installed = load_record(DATA / "sample_impact.csv")
    np.testing.assert_array_equal(by_name.force_n, installed.force_n)
    assert by_name.metadata["builtin"] is True and by_name.mass_kg == 0.16
    assert by_name.impact_speed_m_s == 20.8
    code, out, err = run(capsys, "features", "builtin:sample", "--json")
    assert code == 0, err
    code2, out2, _ = run(capsys, "features", DATA / "sample_impact.csv", "--json")
    first, second = json.loads(out), json.loads(out2)
    assert first["features"] == second["features"]
    assert first["warnings"] == []  # the sample is noisy on purpose: built-in, no warning


def test_builtin_folder_and_one_of_its_files(capsys):
    files = expand_records(["builtin:speed-set"])
    assert [f.name for f in files] == ["synthetic_05.5_m_s.csv", "synthetic_10.0_m_s.csv",
                                       "synthetic_20.8_m_s.csv", "synthetic_25.0_m_s.csv"]
    code, out, err = run(capsys, "features", "builtin:speed-set", "--json")
    assert code == 0, err
    result = json.loads(out)
    assert [round(r["impact_speed_m_s"], 1) for r in result["records"]] == [5.5, 10.0, 20.8, 25.0]
    record = load_record("builtin:speed-set/synthetic_20.8_m_s.csv")
    assert record.impact_speed_m_s == 20.8 and record.metadata["builtin"] is True


def test_builtin_material_tests():
    path, mode = parse_spec("builtin:treloar-uniaxial:uniaxial")
    assert (str(path), mode) == ("builtin:treloar-uniaxial", "uniaxial")
    by_name = read_test(path, mode)
    installed = read_test(DATA / "treloar1944_uniaxial.csv", "uniaxial")
    for key, values in installed.columns.items():
        np.testing.assert_array_equal(by_name.columns[key], values)
    assert by_name.columns["nominal_stress_pa"].max() == pytest.approx(5.56e6, rel=0.01)


def test_calibrate_test_argument_takes_a_builtin_name():
    path, speed, layer = parse_test("builtin:sample:20.8")
    assert (str(path), speed, layer) == ("builtin:sample", 20.8, None)
    assert datasets.resolve(path) == DATA / "sample_impact.csv"
    path, speed, layer = parse_test("builtin:speed-set/synthetic_10.0_m_s.csv:10:core")
    assert (str(path), speed, layer) == ("builtin:speed-set/synthetic_10.0_m_s.csv", 10.0, "core")


@pytest.mark.parametrize(("argv", "fragments"), [
    (["features", "builtin:sampel"], ["builtin:sampel", "not a built-in data set",
                                      "did you mean builtin:sample", "speed-set"]),
    (["features", "builtin:speed-set/nope.csv"], ["builtin:speed-set/nope.csv",
                                                  "no such file", "synthetic_10.0_m_s.csv"]),
    (["fit", "builtin:nothing", "--model", "kelvin_voigt"], ["not a built-in data set"]),
    (["data", "copy", "speeds"], ["builtin:speeds", "not a built-in data set", "speed-set"]),
    (["material", "fit", "builtin:treloar-shear:planar", "--model", "ogden"],
     ["builtin:treloar-shear", "did you mean builtin:treloar-"]),
])
def test_bad_builtin_names(bad_input, argv, fragments):
    bad_input(argv, *fragments)


def test_bad_copy_destinations(bad_input, tmp_path):
    bad_input(["data", "copy", "sample", tmp_path / "no" / "where"], "DEST", "does not exist")
    afile = tmp_path / "file.txt"
    afile.write_text("x")
    bad_input(["data", "copy", "sample", afile], "DEST", "is a file")
    (tmp_path / "sample_impact.csv").write_text("mine")
    bad_input(["data", "copy", "sample", tmp_path], "sample_impact.csv", "exist", "--force")
    assert (tmp_path / "sample_impact.csv").read_text() == "mine"
