"""`material.fitting` (the library side of `ballimpact material fit`) and
`material.stability.stability_report` (of `material check`), called from Python."""

import json
from pathlib import Path

import numpy as np
import pytest

from ballimpact.errors import InputError
from ballimpact.material.data import read_test
from ballimpact.material.fitting import fit_material, fit_prony_test, read_tests
from ballimpact.material.hyperelastic import fit_hyperelastic
from ballimpact.material.stability import stability_report

DATA = Path(__file__).resolve().parents[2] / "src" / "ballimpact" / "data"
UNIAXIAL = DATA / "treloar1944_uniaxial.csv"


def _relaxation(folder: Path) -> Path:
    t = np.geomspace(1e-6, 1e-1, 40)
    ratio = 1 - 0.3 * (1 - np.exp(-t / 1e-4)) - 0.2 * (1 - np.exp(-t / 1e-2))
    path = folder / "relax.csv"
    path.write_text("time_s,relaxation_modulus_ratio\n" + "".join(
        f"{a:.17g},{b:.17g}\n" for a, b in zip(t, ratio)))
    return path


def test_hyperelastic_fit_equals_the_library_fit():
    run = fit_material([(UNIAXIAL, "uniaxial")], "neo_hookean")
    direct = fit_hyperelastic([read_test(UNIAXIAL, "uniaxial")], "neo_hookean")
    assert run.material == direct.material and run.unusable == ""
    assert run.result["constants"]["c10_pa"] == direct.constants["c10_pa"]
    assert 1e5 < run.result["constants"]["c10_pa"] < 1e6  # Treloar's rubber: C10 ~ 0.2 MPa
    assert [t.mode for t in run.tests] == ["uniaxial"]


def test_prony_fit_and_merge(tmp_path):
    base = tmp_path / "core.json"
    base.write_text(json.dumps({"model": "neo_hookean", "c10_pa": 2e5}))
    run = fit_material([(_relaxation(tmp_path), "relaxation")], "prony", terms=2,
                       bulk_relaxation=True, merge=base)
    prony = sorted(run.result["prony"], key=lambda p: p["tau_s"])
    assert [p["g"] for p in prony] == pytest.approx([0.3, 0.2], rel=1e-4)
    assert [p["tau_s"] for p in prony] == pytest.approx([1e-4, 1e-2], rel=1e-4)
    assert [p["k"] for p in prony] == [p["g"] for p in prony]  # bulk relaxation: k = g
    assert run.material["c10_pa"] == 2e5 and len(run.material["prony"]) == 2
    assert run.result["bulk_relaxation"] is True and run.fit.r2 > 0.9999
    fit, out = fit_prony_test(run.tests[0], 2)
    assert "material" not in out and all(p["k"] == 0.0 for p in out["prony"])
    with pytest.raises(InputError, match="only for a dma test"):
        fit_prony_test(run.tests[0], 2, shift="wlf")


def test_tests_must_suit_the_model(tmp_path):
    relax = _relaxation(tmp_path)
    with pytest.raises(InputError, match="is fitted with --model prony, not with yeoh"):
        read_tests([(relax, "relaxation")], "yeoh")
    with pytest.raises(InputError, match="--model prony fits relaxation, creep or dma tests"):
        read_tests([(UNIAXIAL, "uniaxial")], "prony")
    with pytest.raises(InputError, match="given twice"):
        read_tests([(UNIAXIAL, "uniaxial"), (UNIAXIAL, "uniaxial")], "yeoh")
    other = tmp_path / "other.csv"
    other.write_text(relax.read_text())
    with pytest.raises(InputError, match="give one relaxation, creep or dma test, got 2"):
        fit_material([(relax, "relaxation"), (other, "relaxation")], "prony", terms=1)


def test_stability_report_of_a_material_file(tmp_path):
    """Mooney-Rivlin with C01 < 0: equibiaxial compression loses stability where
    C10 l^2 + C01 l^-2 = 0, l = (-C01 / C10)^(1/4) (tests/material/test_material_cli.py)."""
    core = {"model": "mooney_rivlin", "c10_pa": 3.09068828e6, "c01_pa": -1.49503368e6}
    path = tmp_path / "core.json"
    path.write_text(json.dumps(core))
    report = stability_report(material_file=path)
    assert report["name"] == str(path) and "stretch_range" not in report
    (layer,) = report["layers"]
    assert layer["name"] == "material" and layer["checked"] is True
    edge = (-core["c01_pa"] / core["c10_pa"]) ** 0.25
    assert layer["stable_range"]["equibiaxial"][0] == pytest.approx(edge, rel=1e-6)
    with pytest.raises(InputError, match="only with --ball"):
        stability_report(material_file=path, speed_m_s=20.0)
    with pytest.raises(InputError, match=r"--speed-m-s = -1: allowed range \(0, inf\) m/s"):
        stability_report(ball="cricket-3layer", speed_m_s=-1.0)


def test_dict_and_typed_constants_share_one_compiled_stress():
    """A fit's dict of constants and the model's typed `Constants` give the same stresses from
    one compiled program (the conversion is done before the jitted stress, not inside it)."""
    from ballimpact.constitutive import MATERIALS
    from ballimpact.material import modes

    x = np.linspace(0.7, 1.6, 7)
    values = {"c10_pa": 4.0e5, "c01_pa": 1.0e5, "k_pa": 0.0}
    before = modes.incompressible_stress._cache_size()
    as_dict = modes.deformation_stress("mooney_rivlin", values, "planar", x)
    typed = modes.deformation_stress("mooney_rivlin",
                                     MATERIALS["mooney_rivlin"].Constants(**values), "planar", x)
    assert np.array_equal(as_dict, typed)
    assert modes.incompressible_stress._cache_size() - before <= 1
    # closed form of planar tension: P = 2 (l - l^-3) (C10 + C01)
    assert typed == pytest.approx(2 * (x - x ** -3) * 5.0e5, rel=1e-12)
