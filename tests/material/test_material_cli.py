"""`ballimpact material fit|check`: outputs, files written, and one-line bad input."""

import json
from pathlib import Path

import numpy as np
import pytest

from ballimpact.cli import main
from ballimpact.constitutive import material_from_dict
from ballimpact.constitutive.stability import mooney_rivlin_drucker

DATA = Path(__file__).resolve().parents[2] / "src" / "ballimpact" / "data"
UNI = f"{DATA / 'treloar1944_uniaxial.csv'}:uniaxial"
BI = f"{DATA / 'treloar1944_biaxial.csv'}:biaxial"
PLANAR = f"{DATA / 'treloar1944_planar.csv'}:planar"
THESIS_CORE = {"model": "mooney_rivlin", "c10_pa": 3.09068828e6, "c01_pa": -1.49503368e6}


def run_json(capsys, argv):
    capsys.readouterr()
    assert main([str(a) for a in argv] + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_fit_json_out_and_plot(tmp_path, capsys):
    out_file, plot = tmp_path / "core.json", tmp_path / "fit.png"
    result = run_json(capsys, ["material", "fit", UNI, BI, PLANAR, "--model", "yeoh",
                               "--out", out_file, "--plot", plot])
    assert set(result) >= {"material", "r2", "standard_errors", "stable_range", "notes"}
    written = json.loads(out_file.read_text())
    assert written == result["material"]
    assert material_from_dict(written).model == "yeoh"
    assert plot.stat().st_size > 10_000
    assert result["r2"]["overall"] > 0.98 and set(result["stable_range"]) == {
        "uniaxial", "equibiaxial", "planar"}
    # the same numbers as the library (JSON round trip exact)
    from ballimpact.material.data import read_test
    from ballimpact.material.hyperelastic import fit_hyperelastic
    fit = fit_hyperelastic([read_test(DATA / f"treloar1944_{m}.csv", k) for m, k in
                            (("uniaxial", "uniaxial"), ("biaxial", "biaxial"),
                             ("planar", "planar"))], "yeoh")
    assert written["c20_pa"] == fit.material["c20_pa"]


def test_fit_table_when_not_json(capsys):
    assert main(["material", "fit", UNI, "--model", "neo_hookean"]) == 0
    out = capsys.readouterr().out
    assert "c10_pa" in out and "R^2" in out and "Drucker-stable" in out


def test_check_material_thesis_set_matches_analytic(tmp_path, capsys):
    """Thesis table 5-3: the stable range per mode from `check` equals the edges of the analytic
    Mooney-Rivlin Drucker check (the unstable intervals nearest stretch 1)."""
    path = tmp_path / "core.json"
    path.write_text(json.dumps(THESIS_CORE))
    result = run_json(capsys, ["material", "check", "--material", path])
    ranges = result["layers"][0]["stable_range"]
    unstable = mooney_rivlin_drucker(THESIS_CORE["c10_pa"], THESIS_CORE["c01_pa"], 0.05, 20.0)
    for mode, (low, high) in ranges.items():
        below = [r["stretch_to"] for r in unstable if r["mode"] == mode and r["stretch_to"] <= 1]
        above = [r["stretch_from"] for r in unstable if r["mode"] == mode and r["stretch_from"] >= 1]
        assert low == pytest.approx(max(below, default=0.05), rel=1e-6), mode
        assert high == pytest.approx(min(above, default=20.0), rel=1e-6), mode
    # closed form: equibiaxial compression fails where A1 = C10 l^2 + C01 l^-2 changes sign
    # (det = A1 (A1 + 2 A3) with A3 > 0), l = (-C01 / C10)^(1/4) = 0.834
    edge = (-THESIS_CORE["c01_pa"] / THESIS_CORE["c10_pa"]) ** 0.25
    assert ranges["equibiaxial"][0] == pytest.approx(edge, rel=1e-6)


def test_bad_input(tmp_path, bad_input):
    bad = tmp_path / "bad.csv"
    bad.write_text("stretch,nominal_stress_pa\n1,0\n1.3,5\n1.2,7\n")
    relax = tmp_path / "relax.csv"
    relax.write_text("time_s,relaxation_modulus_ratio\n0,1\n1,0.5\n")
    uni = str(DATA / "treloar1944_uniaxial.csv")
    bad_input(["material", "fit", f"{bad}:uniaxial", "--model", "yeoh"], str(bad), "line 4",
              "monotone")
    bad_input(["material", "fit", uni, "--model", "yeoh"], "FILE:MODE", "uniaxial")
    bad_input(["material", "fit", f"{uni}:shear", "--model", "yeoh"], "FILE:MODE")
    bad_input(["material", "fit", UNI, "--model", "foam"], "--model foam", "mooney_rivlin")
    bad_input(["material", "fit", UNI, "--model", "mooney_rivlin", "--order", "2"], "--order",
              "only for")
    bad_input(["material", "fit", UNI, "--model", "ogden", "--order", "4"],
              "--order = 4: allowed range [1, 3] (the number of terms)")
    bad_input(["material", "fit", UNI, "--model", "prony", "--terms", "2"], "prony",
              "stress data")
    bad_input(["material", "fit", f"{relax}:relaxation", "--model", "yeoh"], "relaxation",
              "prony")
    bad_input(["material", "fit", UNI, "--model", "yeoh", "--terms", "2"], "--terms",
              "--model prony")
    bad_input(["material", "fit", UNI, "--model", "yeoh", "--error", "log"], "--error")
    bad_input(["material", "fit", UNI, UNI, "--model", "yeoh"], "given twice")
    bad_input(["material", "fit", UNI, "--model", "mooney_rivlin", "--out",
               tmp_path / "mr.json"], "not written", "c10_pa + c01_pa")
    bad_input(["material", "check", "--material", tmp_path / "none.json"], "cannot read")
    bad_input(["material", "check", "--material", bad, "--speed-m-s", "20"], "--speed-m-s",
              "--ball")


def test_prony_branch(tmp_path, capsys):
    """`material fit --model prony --merge`: a relaxation test's Prony terms merged into a
    hyperelastic material file (the library functions: tests/material/test_material_prony.py)."""
    t = np.geomspace(1e-6, 1e-1, 40)
    ratio = 1 - 0.3 * (1 - np.exp(-t / 1e-4)) - 0.2 * (1 - np.exp(-t / 1e-2))
    path = tmp_path / "relax.csv"
    path.write_text("time_s,relaxation_modulus_ratio\n" + "".join(
        f"{a:.17g},{b:.17g}\n" for a, b in zip(t, ratio)))
    base = tmp_path / "core.json"
    base.write_text(json.dumps({"model": "neo_hookean", "c10_pa": 2e5}))
    result = run_json(capsys, ["material", "fit", f"{path}:relaxation", "--model", "prony",
                               "--terms", "2", "--merge", base])
    prony = sorted(result["material"]["prony"], key=lambda p: p["tau_s"])
    assert [p["g"] for p in prony] == pytest.approx([0.3, 0.2], rel=1e-4)
    assert [p["tau_s"] for p in prony] == pytest.approx([1e-4, 1e-2], rel=1e-4)
    assert all(p["k"] == 0.0 for p in prony)
    assert material_from_dict(result["material"]).sum_g == pytest.approx(0.5, rel=1e-4)


@pytest.mark.slow
def test_check_ball_at_speed(capsys):
    """The 3-layer cricket ball at 20 m/s: the stretches of the run lie inside every layer's
    stable range (docs/fe.md: the thesis' sets fail only outside about 0.6-1.3)."""
    result = run_json(capsys, ["material", "check", "--ball", "cricket-3layer",
                               "--speed-m-s", "20"])
    low, high = result["stretch_range"]
    assert 0.3 < low < 1.0 < high < 3.0
    for layer in result["layers"]:
        for mode, (a, b) in layer["stable_range"].items():
            assert layer["inside"][mode] == (a <= low and high <= b)


@pytest.mark.parametrize("model, extra", [("yeoh", []), ("ogden", ["--order", "3"])])
def test_fitted_material_runs_in_simulate_and_both_exports(model, extra, tmp_path, capsys):
    """A material fitted to Treloar's three modes goes into a ball file as it is written, runs
    in `simulate` (energy balanced), and its ABAQUS and LS-DYNA decks carry it: the ABAQUS one
    reads back (`import-material`) to the same constants."""
    material_file, ball_file = tmp_path / "rubber.json", tmp_path / "ball.json"
    fit = run_json(capsys, ["material", "fit", UNI, BI, PLANAR, "--model", model, *extra,
                            "--out", material_file])
    material = json.loads(material_file.read_text())
    ball_file.write_text(json.dumps({"name": "rubber-ball", "layers": [{
        "name": "rubber", "outer_radius_m": 0.036, "density_kg_m3": 1100.0,
        "material": material}]}))
    run = run_json(capsys, ["simulate", "--ball", ball_file, "--speed-m-s", 2.0,
                            "--element-size-m", 6e-3])
    assert run["materials"]["layers"][0]["material"] == fit["material"]
    assert 0.9 < run["cor"] <= 1.0 and abs(run["energy_balance_error"]) < 0.05
    deck, keyword = tmp_path / "ball.inp", tmp_path / "ball.k"
    for fmt, path in (("abaqus", deck), ("lsdyna", keyword)):
        capsys.readouterr()
        assert main(["export", "--ball", str(ball_file), "--format", fmt, "--out", str(path),
                     "--speed-m-s", "2"]) == 0
        assert path.stat().st_size > 1000
    card = {"yeoh": "*HYPERELASTIC, YEOH", "ogden": "*HYPERELASTIC, OGDEN, N=3"}[model]
    assert card in deck.read_text()
    assert {"yeoh": "*MAT_HYPERELASTIC_RUBBER", "ogden": "*MAT_OGDEN_RUBBER"}[model] \
        in keyword.read_text()
    back = run_json(capsys, ["import-material", deck])
    (imported,) = back["materials"]
    flat_fit, flat_back = _numbers(fit["material"]), _numbers(imported["material"])
    assert set(flat_fit) <= set(flat_back)
    for key, value in flat_fit.items():
        assert flat_back[key] == pytest.approx(value, rel=1e-9, abs=1e-12), key


def _numbers(tree, prefix=""):
    """Every number of a JSON tree by its path."""
    if isinstance(tree, dict):
        return {k: v for key, item in tree.items() for k, v in _numbers(item, f"{prefix}{key}.")
                .items()}
    if isinstance(tree, list):
        return {k: v for i, item in enumerate(tree) for k, v in _numbers(item, f"{prefix}{i}.")
                .items()}
    return {prefix[:-1]: tree} if isinstance(tree, (int, float)) else {}


def test_relaxation_modulus_from_after_the_ramp(tmp_path, capsys):
    """A relaxation modulus in Pa whose first point comes after the loading ramp (t0 = 0.1 s):
    normalised by that first value the ratio is G(t)/G(t0), and the fit compares it so (g 0.5,
    tau 1 s come back; taken as G(t)/G(0) they read g 0.478, tau 1.195 s)."""
    t = np.geomspace(0.1, 100.0, 40)
    modulus = 2e6 * (1.0 - 0.5 * (1.0 - np.exp(-t / 1.0)))
    path = tmp_path / "relax.csv"
    path.write_text("time_s,relaxation_modulus_pa\n"
                    + "\n".join(f"{a:.10g},{b:.10g}" for a, b in zip(t, modulus)))
    result = run_json(capsys, ["material", "fit", f"{path}:relaxation", "--model", "prony",
                               "--terms", "1"])
    (term,) = result["prony"]
    assert term["g"] == pytest.approx(0.5, rel=1e-4)
    assert term["tau_s"] == pytest.approx(1.0, rel=1e-4)


@pytest.mark.parametrize("text, fragment", [
    ("stretch,nominal_stress_pa\n1,0\n1.5,0.4\n2,0.7\n", "MPa given as Pa"),
    ("strain,nominal_stress_mpa\n0,0\n50,0.4\n100,0.7\n", "percent given as a fraction"),
])
def test_unit_slips_warn(text, fragment, tmp_path, capsys):
    path = tmp_path / "slip.csv"
    path.write_text(text)
    result = run_json(capsys, ["material", "fit", f"{path}:uniaxial", "--model", "neo_hookean"])
    assert any(fragment in w for w in result["warnings"]), result["warnings"]


def test_prony_out_needs_a_material(tmp_path, bad_input):
    path = tmp_path / "relax.csv"
    path.write_text("time_s,relaxation_modulus_ratio\n0,1\n0.1,0.8\n1,0.6\n10,0.5\n100,0.5\n")
    bad_input(["material", "fit", f"{path}:relaxation", "--model", "prony", "--terms", "1",
               "--out", tmp_path / "x.json"], "--out", "not a material", "--merge")


def test_prony_plot_is_refused_not_skipped(tmp_path, bad_input):
    """A Prony fit draws no plot: --plot with it is refused by name (it was silently ignored)."""
    path = tmp_path / "relax.csv"
    path.write_text("time_s,relaxation_modulus_ratio\n0,1\n0.1,0.8\n1,0.6\n10,0.5\n100,0.5\n")
    bad_input(["material", "fit", f"{path}:relaxation", "--model", "prony", "--terms", "1",
               "--plot", tmp_path / "p.png"], "--plot", "prony")
    assert not (tmp_path / "p.png").exists()
