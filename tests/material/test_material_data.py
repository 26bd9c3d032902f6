"""Material test files (material/data.py): units to SI, normalisation, and one-line errors that
name file, line and column."""

from pathlib import Path

import numpy as np
import pytest

from ballimpact.errors import InputError
from ballimpact.material.data import MODES, parse_spec, read_test

DATA = Path(__file__).resolve().parents[2] / "src" / "ballimpact" / "data"


def write(tmp_path, text, name="t.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_treloar_package_files_in_si():
    """MPa -> Pa, exactly as tabulated (second data row of each file, read independently)."""
    for mode, name in (("uniaxial", "uniaxial"), ("biaxial", "biaxial"), ("planar", "planar")):
        path = DATA / f"treloar1944_{name}.csv"
        rows = [line for line in path.read_text().splitlines() if not line.startswith("#")]
        stretch, stress = map(float, rows[2].split(","))
        test = read_test(path, mode)
        assert test.columns["stretch"][1] == stretch
        assert test.columns["nominal_stress_pa"][1] == pytest.approx(stress * 1e6, rel=1e-15)
        assert test.deformation == ("equibiaxial" if mode == "biaxial" else mode)
        assert test.size == len(rows) - 1


def test_unit_variants(tmp_path):
    """strain_pct and kPa give the same SI arrays as stretch and Pa."""
    a = read_test(write(tmp_path, "# c\nstrain_pct,nominal_stress_kpa\n-20,-50\n0,0\n50,120\n"),
                  "uniaxial")
    assert np.allclose(a.columns["stretch"], [0.8, 1.0, 1.5], rtol=1e-15)
    assert np.allclose(a.columns["nominal_stress_pa"], [-5e4, 0.0, 1.2e5], rtol=1e-15)
    b = read_test(write(tmp_path, "strain,nominal_stress_mpa\n0.0,0\n0.5,1.5\n", "b.csv"), "planar")
    assert np.allclose(b.columns["stretch"], [1.0, 1.5]) and b.columns["nominal_stress_pa"][1] == 1.5e6
    v = read_test(write(tmp_path, "volume_ratio,pressure_mpa\n0.9,2\n1.0,0\n1.1,-1\n", "v.csv"),
                  "volumetric")
    assert np.allclose(v.columns["pressure_pa"], [2e6, 0, -1e6])


def test_moduli_normalised_by_first_value(tmp_path):
    r = read_test(write(tmp_path, "time_ms,relaxation_modulus_mpa\n0,4\n1,3\n10,2\n"), "relaxation")
    assert np.allclose(r.columns["relaxation_modulus_ratio"], [1.0, 0.75, 0.5], rtol=1e-15)
    assert np.allclose(r.columns["time_s"], [0.0, 1e-3, 1e-2], rtol=1e-15)
    c = read_test(write(tmp_path, "time_s,creep_compliance_per_mpa\n0,2\n1,3\n", "c.csv"), "creep")
    assert np.allclose(c.columns["creep_compliance_ratio"], [1.0, 1.5], rtol=1e-15)
    d = read_test(write(tmp_path, "frequency_hz,storage_modulus_mpa,loss_modulus_kpa,"
                                  "temperature_c\n1,2,300,20\n10,3,400,20\n", "d.csv"), "dma")
    assert d.columns["loss_modulus_pa"][1] == 4e5 and d.columns["temperature_c"][0] == 20


def test_general_biaxial_columns(tmp_path):
    t = read_test(write(tmp_path, "stretch_1,stretch_2,nominal_stress_1_pa,nominal_stress_2_pa\n"
                                  "1,1,0,0\n1.2,1.0,5,2\n1.4,1.0,9,3\n"), "biaxial")
    assert t.deformation == "biaxial" and t.stretch_range() == (1.0, 1.4)


BAD = [
    ("stretch,nominal_stress_pa\n1,0\n1.2,abc\n", "uniaxial", ["line 3", "nominal_stress_pa", "not a number"]),
    ("stretch,nominal_stress_pa\n1,0\n1.2,nan\n", "uniaxial", ["line 3", "not a finite number"]),
    ("stretch,nominal_stress_pa\n1,0\n1.2,inf\n", "uniaxial", ["line 3", "not a finite"]),
    ("stretch\n1\n1.2\n", "uniaxial", ["no nominal_stress_pa column", "nominal_stress_mpa"]),
    ("stress_pa,stretch\n1,0\n", "uniaxial", ["unknown column 'stress_pa'", "allowed"]),
    ("# c\nstretch,nominal_stress_pa\n1,0\n1.2,3\n1.1,4\n", "uniaxial", ["line 5", "stretch", "monotone"]),
    ("stretch,nominal_stress_pa\n1,0\n1,3\n", "planar", ["line 3", "monotone"]),
    ("strain,nominal_stress_pa\n-1.5,-3\n0,0\n", "uniaxial",
     ["line 2", "column strain: stretch = -0.5: allowed range (0, inf)"]),
    ("stretch,nominal_stress_pa\n1,0\n1.2,-3\n", "uniaxial", ["line 3", "> 0 (tension)"]),
    ("stretch,nominal_stress_pa\n0.8,2\n1,0\n", "uniaxial", ["line 2", "< 0 (compression)"]),
    ("stretch,nominal_stress_pa\n1,0\n1.2,0\n", "biaxial", ["line 3", "tension"]),
    ("volume_ratio,pressure_pa\n0,1\n1,0\n", "volumetric",
     ["line 2", "volume_ratio = 0: allowed range (0, inf)"]),
    ("volume_ratio,pressure_pa\n0.9,-1\n1,0\n", "volumetric", ["line 2", "pressure", "compressed"]),
    ("time_s,relaxation_modulus_ratio\n0,1\n0,0.9\n", "relaxation", ["line 3", "increase"]),
    ("time_s,relaxation_modulus_ratio\n0,1\n1,1.2\n", "relaxation", ["line 3", "(0, 1.05]"]),
    ("time_s,relaxation_modulus_pa\n0,-1\n1,-2\n", "relaxation",
     ["line 2", "relaxation_modulus_pa = -1: allowed range (0, inf)"]),
    ("time_s,creep_compliance_ratio\n0,1\n1,0.8\n", "creep", ["line 3", "below 0.95"]),
    ("frequency_hz,storage_modulus_pa,loss_modulus_pa\n1,5,-1\n2,6,1\n", "dma", ["line 2", "loss_modulus_pa", "negative"]),
    ("frequency_hz,storage_modulus_pa,loss_modulus_pa\n1,-5,1\n2,6,1\n", "dma", ["line 2", "storage"]),
    ("stretch,nominal_stress_pa\n1,0\n", "uniaxial", ["at least 2"]),
    ("1,0\n1.2,3\n", "uniaxial", ["not a header"]),
    ("stretch,strain,nominal_stress_pa\n1,0,0\n", "uniaxial", ["both give stretch"]),
    ("stretch,nominal_stress_pa\n1,0,4\n", "uniaxial", ["line 2 has 3 values"]),
    ("", "uniaxial", ["empty"]),
]


@pytest.mark.parametrize("text, mode, fragments", BAD)
def test_bad_files_name_file_line_and_column(tmp_path, text, mode, fragments):
    path = write(tmp_path, text)
    with pytest.raises(InputError) as error:
        read_test(path, mode)
    message = str(error.value)
    assert "\n" not in message and message.startswith(str(path))
    for fragment in fragments:
        assert fragment.lower() in message.lower(), (fragment, message)


def test_parse_spec():
    assert parse_spec("a/b.csv:uniaxial") == (Path("a/b.csv"), "uniaxial")
    for text in ("a.csv", "a.csv:shear"):
        with pytest.raises(InputError, match="FILE:MODE"):
            parse_spec(text)
    assert set(MODES) >= {"uniaxial", "biaxial", "planar", "volumetric", "relaxation", "creep", "dma"}
