"""A ball from a specification's COR and compression (`standards.specification`, `standard ball`):
the presets calibrated to both give them back through the methods themselves, the compression
is linear in the moduli (the calibration's premise), an unreachable COR is refused with the
layered path named, and bad input gets one line."""

import json
from importlib import resources

import pytest

from ballimpact.errors import InputError
from ballimpact.fe import compress, load_ball
from ballimpact.balls.ball import universal_spec
from ballimpact.records.loaders import LBF_N
from ballimpact.standards import INCH_M, on_model
from ballimpact.standards.model import method_options
from ballimpact.standards.specification import (Specification, ball_for_specification,
                                                check_tau1)

RULES = json.loads(resources.files("ballimpact").joinpath("data/sports_balls.json")
                   .read_text())["balls"]
SOFTBALL = dict(diameter_m=0.097, mass_kg=0.188, cor=0.44, compression_force_n=375 * LBF_N)


@pytest.mark.parametrize("change, words", [
    ({"diameter_m": 97.0}, r"diameter_m \(--diameter-m\) = 97 m .*millimetres"),
    ({"mass_kg": 188.0}, r"mass_kg \(--mass-kg\) = 188.0 kg.*grams"),
    ({"cor": 1.2}, r"cor \(--cor\) = 1\.2: allowed range \(0, 1\)"),
    ({"cor": 0.0}, r"cor \(--cor\) = 0"),
    ({"compression_force_n": 0.5}, r"compression_force_n \(--compression-n\) = 0\.5.*N"),
    ({"compression_deflection_m": 6.35}, r"compression_deflection_m.*looks like millimetres"),
    ({"impact_speed_m_s": 60.0}, r"looks like mph"),
    ({"compression_force_n": 1.668}, r"compression_force_n \(--compression-n\) = 1\.668 N at "
                                     r"6\.35 mm implies a shear modulus .*looks like kN: use 1668 N"),
])
def test_bad_specifications_are_named(change, words):
    with pytest.raises(InputError, match=words):
        Specification(**{**SOFTBALL, **change}).checked()


@pytest.mark.parametrize("argv, fragments", [
    (["--diameter-m", "0.097", "--cor", "0.44", "--compression-n", "1668", "--out", "b.json"],
     ("--mass-kg: missing",)),
    (["--diameter-m", "0.097", "--mass-kg", "0.188", "--cor", "0.44", "--compression-n",
      "1668"], ("--out: missing",)),
    (["--diameter-m", "97", "--mass-kg", "0.188", "--cor", "0.44", "--compression-n", "1668",
      "--out", "b.json"], ("diameter_m", "millimetres")),
    (["--diameter-m", "0.097", "--mass-kg", "0.188", "--cor", "0.44", "--compression-n",
      "1668", "--out", "b.csv"], ("--out", ".json")),
    (["--ball", "baseball", "--diameter-m", "0.097"], ("--ball", "not taken by `standard ball`")),
])
def test_standard_ball_bad_input_one_line(bad_input, tmp_path, argv, fragments):
    argv = [str(tmp_path / a) if a.endswith((".json", ".csv")) else a for a in argv]
    bad_input(["standard", "ball", *argv], *fragments)


@pytest.mark.parametrize("value, words", [(42.6, r"42\.6 s: .*looks like us: use 4\.26e-05"),
                                          (5.0, r"looks like ms: use 0\.005"),
                                          (1e-9, r"allowed range")])
def test_a_relaxation_time_in_us_or_ms_is_named(value, words):
    with pytest.raises(InputError, match=words):
        check_tau1(value)
    assert check_tau1(4.26e-5) == 4.26e-5


def test_standard_ball_tau1_and_force_slips_one_line(bad_input, tmp_path):
    base = ["standard", "ball", "--diameter-m", "0.097", "--mass-kg", "0.188", "--cor", "0.44",
            "--out", tmp_path / "b.json"]
    bad_input([*base, "--compression-n", "1.668"], "--compression-n", "looks like kN")
    bad_input([*base, "--compression-n", "1668", "--tau1-s", "42.6"], "--tau1-s", "looks like us")


def test_a_calibration_that_does_not_close_exits_3_and_writes_nothing(monkeypatch, tmp_path,
                                                                      capsys):
    """The command writes the ball only when its FE check holds; a miss (here a calibration
    stubbed to miss its COR) exits 3 with the result printed and one error line."""
    import ballimpact.standards.specification as specification
    from ballimpact.cli import main

    def missed(spec, name, **kwargs):
        check = {"cor": 0.47, "cor_error": 0.03, "compression_force_n": 1668.0,
                 "compression_relative_error": 0.0, "dynamic_stiffness_n_m": 1e6,
                 "peak_force_n": 1e4, "contact_time_s": 1e-3,
                 "missed": ["COR 0.4700 against 0.44"]}
        return {"ball": {"name": name}, "params": {"c10_pa": 3e6, "c01_pa": 0.0, "g1": 0.8,
                                                   "tau1_s": 4e-5},
                "specification": {"diameter_m": spec.diameter_m, "mass_kg": spec.mass_kg,
                                  "cor": spec.cor, "compression_force_n": 1668.0,
                                  "compression_deflection_m": 0.00635,
                                  "impact_speed_m_s": 26.8224},
                "check": check, "runs": {"impacts": 13, "compressions": 3},
                "element_size_m": 0.002, "wall_time_s": 1.0}

    monkeypatch.setattr(specification, "ball_for_specification", missed)
    out = tmp_path / "b.json"
    code = main(["standard", "ball", "--diameter-m", "0.097", "--mass-kg", "0.188", "--cor",
                 "0.44", "--compression-n", "1668", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 3 and not out.exists()
    errors = [line for line in err.splitlines() if line.startswith("error:")]
    assert len(errors) == 1 and "COR 0.4700 against 0.44" in errors[0] and "not written" in errors[0]


def test_the_other_methods_refuse_the_ball_options(bad_input):
    bad_input(["standard", "cor", "--ball", "baseball", "--cor", "0.5"],
              "--cor", "only `standard ball`")


@pytest.mark.slow
@pytest.mark.parametrize("name", ["baseball", "softball-44-375", "softball-47-375",
                                  "softball-52-300"])
def test_a_specified_preset_gives_back_its_two_numbers(name):
    """`standard cor` and `standard compression` (F1888's 0.25 in; the baseball's own 0.08 in
    through `fe.compress` on the same mesh) on the preset give back its published COR within
    0.001 and its compression within 0.1% (the calibration closes to 5e-4 and 1e-3; the
    issue asks 0.01 and 5%). Measured: docs/balls.md."""
    t = RULES[name]["specification"]
    cor = on_model("cor", name)["result"]["cor"]
    assert cor == pytest.approx(t["cor"], abs=1e-3)
    deflection = t["compression_deflection_m"]
    if deflection == pytest.approx(0.25 * INCH_M, rel=1e-12):
        force = on_model("compression", name)["result"]["force_at_6_35_mm_n"]
    else:
        ball = load_ball(name)
        force = compress(ball, deflection, options=method_options(ball.outer_radius_m)
                         ).force_at(deflection)
    assert force == pytest.approx(t["compression_force_n"], rel=1e-3)


@pytest.mark.slow
def test_the_compression_is_linear_in_the_moduli():
    """The calibration's premise: at fixed g1 (and so fixed K / mu0), the long-term force at a
    deflection is proportional to C10 (the FE problem is homogeneous of degree one in the
    moduli; the contact penalty follows them)."""
    radius, density = 0.0485, 393.0
    options = method_options(radius)

    def force(c10):
        ball = load_ball(universal_spec({"c10_pa": c10, "c01_pa": 0.0, "g1": 0.6,
                                         "tau1_s": 4e-5}, radius, density))
        return compress(ball, 0.00635, options=options).force_at(0.00635)

    assert force(5.0e6) / force(2.0e6) == pytest.approx(2.5, rel=1e-9)


@pytest.mark.slow
def test_standard_ball_writes_a_ball_that_meets_its_specification(tmp_path, capsys):
    """End to end: `standard ball` writes the ball file; `standard cor` and `standard
    compression` on that file give the specification back."""
    from ballimpact.cli import main

    out = tmp_path / "ball.json"
    code = main(["standard", "ball", "--diameter-m", "0.097", "--mass-kg", "0.188", "--cor",
                 "0.5", "--compression-n", "1400", "--out", str(out), "--json"])
    result = json.loads(capsys.readouterr().out)
    assert code == 0 and result["out"] == str(out)
    assert result["params"]["c01_pa"] == 0.0 and 0.0 < result["params"]["g1"] < 0.95
    assert abs(result["check"]["cor_error"]) <= 5e-4
    assert abs(result["check"]["compression_relative_error"]) <= 1e-3
    assert on_model("cor", str(out))["result"]["cor"] == pytest.approx(0.5, abs=1e-3)
    force = on_model("compression", str(out))["result"]["force_at_6_35_mm_n"]
    assert force == pytest.approx(1400, rel=1e-3)


@pytest.mark.slow
def test_an_unreachable_cor_names_the_layered_path():
    """COR 0.99 at 26.8 m/s is beyond any g1 of a softball this stiff (elastic: 0.977)."""
    with pytest.raises(InputError, match=r"cor = 0\.99: a homogeneous ball .* reaches COR "
                                         r"0\.[0-9]+ to 0\.9[0-9]+ .*layered ball"):
        ball_for_specification(Specification(**{**SOFTBALL, "cor": 0.99}))
