"""Material tests written compression-positive (issue 39 A): `material fit --compression-positive`
negates the strain and nominal-stress columns (a stretch column is kept), so that such a file
fits to exactly the constants of the signed one; without the flag a test that reads the wrong
way round is refused in one line with the flag as the hint."""

import json

import numpy as np
import pytest

from ballimpact.cli import main
from ballimpact.material.data import read_test

C10, C01 = 4.72e6, -0.45e6


def _stress(lam):
    """Mooney-Rivlin uniaxial nominal stress (Pa), with a 0.5% ripple as measurement noise."""
    lam = np.asarray(lam)
    ripple = 1.0 + 0.005 * np.sin(1.7 * np.arange(lam.size))
    return 2.0 * (lam - lam ** -2) * (C10 + C01 / lam) * ripple


def _write(path, header, a, b):
    rows = "".join(f"{float(x)!r},{float(y)!r}\n" for x, y in zip(a, b))
    path.write_text(header + "\n" + rows)
    return path


@pytest.fixture
def files(tmp_path):
    """The same compression test (stretch 1 to 0.65) as signed strain, as compression-positive
    strain (in %), as a stretch column with compression-positive stress, and a test through both
    branches, signed and compression-positive."""
    lam = np.linspace(1.0, 0.65, 15)
    p = _stress(lam)
    both = np.linspace(0.7, 1.5, 17)
    q = _stress(both)
    return {
        "signed": _write(tmp_path / "core_signed.csv", "strain,nominal_stress_pa", lam - 1.0, p),
        "positive": _write(tmp_path / "core_compression.csv", "strain_pct,nominal_stress_pa",
                           -(lam - 1.0) * 100.0, -p),
        "stretch": _write(tmp_path / "core_stretch.csv", "stretch,nominal_stress_pa", lam, -p),
        "both_signed": _write(tmp_path / "both.csv", "strain,nominal_stress_pa", both - 1.0, q),
        "both_positive": _write(tmp_path / "both_cp.csv", "strain,nominal_stress_pa",
                                -(both - 1.0), -q),
    }


def _constants(capsys, *argv):
    capsys.readouterr()
    assert main(["material", "fit", *map(str, argv), "--model", "mooney_rivlin", "--json"]) == 0
    return json.loads(capsys.readouterr().out)["constants"]


def test_compression_positive_files_fit_to_the_signed_constants(files, capsys):
    signed = _constants(capsys, f"{files['signed']}:uniaxial")
    # the fitted set is the truth's within the ripple (a real fit, not two equal failures)
    assert signed["c10_pa"] == pytest.approx(C10, rel=0.03)
    assert signed["c01_pa"] == pytest.approx(C01, rel=0.2)
    for argv in ([f"{files['positive']}:uniaxial"], [f"{files['positive']}:compression"],
                 [f"{files['stretch']}:uniaxial"], [f"{files['stretch']}:compression"]):
        flipped = _constants(capsys, *argv, "--compression-positive")
        for key, value in signed.items():
            assert flipped[key] == pytest.approx(value, rel=1e-9, abs=0.0), (argv, key)
    both = _constants(capsys, f"{files['both_signed']}:uniaxial")
    both_cp = _constants(capsys, f"{files['both_positive']}:uniaxial", "--compression-positive")
    assert both_cp == pytest.approx(both, rel=1e-9)


def test_read_test_negates_strain_and_stress_but_keeps_a_stretch(files):
    signed = read_test(files["signed"], "uniaxial")
    for name in ("positive", "stretch"):
        flipped = read_test(files[name], "compression", compression_positive=True)
        assert flipped.mode == "uniaxial"
        np.testing.assert_allclose(flipped.columns["stretch"], signed.columns["stretch"],
                                   rtol=0, atol=1e-15)
        np.testing.assert_array_equal(flipped.columns["nominal_stress_pa"],
                                      signed.columns["nominal_stress_pa"])
    assert signed.stretch_range() == pytest.approx((0.65, 1.0))


def test_tension_declared_and_unaffected_by_names(tmp_path, capsys):
    lam = np.linspace(1.0, 2.0, 11)
    tension = _write(tmp_path / "t.csv", "stretch,nominal_stress_pa", lam, _stress(lam))
    assert _constants(capsys, f"{tension}:tension") == pytest.approx(
        _constants(capsys, f"{tension}:uniaxial"), rel=1e-12)


def test_bad_sign_conventions_exit_2_with_the_flag_as_hint(files, tmp_path, bad_input):
    fit = ["material", "fit"]
    model = ["--model", "mooney_rivlin"]
    # named as a compression test but reads as tension: compression-positive strain
    bad_input([*fit, f"{files['positive']}:uniaxial", *model], "core_compression.csv",
              "reads as tension", "--compression-positive", ":tension")
    # declared compression, reads as tension
    bad_input([*fit, f"{files['positive']}:compression", *model], "declared compression",
              "stretch 1 to 1.35", "--compression-positive")
    # the flag on a file that is already signed
    bad_input([*fit, f"{files['signed']}:compression", *model, "--compression-positive"],
              "already signed", "drop --compression-positive")
    # stretch below 1 with positive stresses: the compression branch's stresses are unsigned
    bad_input([*fit, f"{files['stretch']}:uniaxial", *model], "column nominal_stress_pa",
              "must be < 0 (compression)", "--compression-positive")
    # declared compression, through both branches
    bad_input([*fit, f"{files['both_signed']}:compression", *model], "declared compression",
              "one branch per file", "both.csv:uniaxial")
    # the flag with no test it applies to
    volumetric = _write(tmp_path / "v.csv", "volume_ratio,pressure_pa", [1.0, 0.99, 0.98],
                        [0.0, 2e7, 4e7])
    bad_input([*fit, f"{volumetric}:volumetric", *model, "--compression-positive"],
              "--compression-positive", "uniaxial, biaxial and planar")
    bad_input([*fit, f"{files['signed']}:squash", *model], "compression, tension")
