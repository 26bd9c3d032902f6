"""The demo report on the built-in multi-speed set (5.5, 10, 20.8, 25 m/s; synthetic, from a
three-layer FE ball): the thesis' chapter 7 comparison, checked in numbers and in a browser."""

import json

import pytest

from ballimpact.cli import main
from ballimpact.report.browser import check_page, find_browser

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def speeds_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "speeds"
    assert main(["report", "--builtin", "speeds", "--out", str(out), "--quiet"]) == 0
    return out, json.loads((out / "report.json").read_text())


def _by(report, model):
    return {r["test"]: r for r in report["runs"] if r["model"] == model}


def test_the_generating_ball_reproduces_its_tests_to_the_noise_and_mesh_floor(speeds_report):
    _, report = speeds_report
    runs = _by(report, "FE synthetic-3layer")
    assert len(runs) == 4
    for run in runs.values():  # 1% noise, default mesh against the tests' twice finer one
        assert run["comparison"]["force_nrmse"] < 0.02
        assert abs(run["comparison"]["cor_error"]) < 0.01
        assert abs(run["comparison"]["peak_force_relative_error"]) < 0.015


def test_models_rank_as_in_the_thesis(speeds_report):
    """Thesis 7.2: the universal FE model matches best, the three-element model better than the
    single-element one (whose unloading is off)."""
    _, report = speeds_report
    single, three, universal = (_by(report, m) for m in ("single_element", "three_element",
                                                         "universal FE"))
    for test in single:
        assert universal[test]["comparison"]["force_nrmse"] < 0.03
        assert abs(universal[test]["comparison"]["cor_error"]) < 0.035
        assert (universal[test]["comparison"]["force_nrmse"]
                < three[test]["comparison"]["force_nrmse"]
                < single[test]["comparison"]["force_nrmse"])
    table = report["tables"]["nrmse"]
    assert table["columns"] == ["model", "5.5 m/s", "10 m/s", "20.8 m/s", "25 m/s", "mean_abs"]
    assert [row[0] for row in table["rows"]] == ["single_element", "three_element",
                                                 "universal FE", "FE synthetic-3layer"]


@pytest.mark.skipif(find_browser() is None, reason="no Chromium (apt-get install chromium)")
def test_the_demo_page_renders_every_figure_in_chromium(speeds_report, tmp_path):
    out, _ = speeds_report
    seen = check_page(out / "report.html", tmp_path / "page.png")
    assert seen["console_errors"] == []
    # overlays, COR / contact time / peak force vs speed, NRMSE bars, cost, 3 parameter figures
    assert len(seen["figures"]) == 9
    assert all(w > 200 and h > 150 for w, h in seen["figures"])


# ---- a generator outside the universal model's family (issue 24) -----------------------------
# The built-in set's ball has one Prony term (g 0.88, tau 20 us) in every layer: a relaxation
# the universal ball's single term (tau1 10-100 us) represents, so its ranking first follows
# partly by construction. This ball is the same three-layer ball (Ogden hyperfoam midsole) with
# TWO Prony terms per layer, 10 us and 200 us (the slow one outside the universal model's tau1
# range), and half the moduli: peak 8.0 kN and contact 1.17 ms at 20.8 m/s, COR falling from
# 0.56 at 5.5 m/s to 0.49 at 25 m/s, as the thesis' tests.
OUT_OF_FAMILY_PRONY = [{"g": 0.72, "k": 0.0, "tau_s": 1e-5}, {"g": 0.16, "k": 0.0, "tau_s": 2e-4}]
OUT_OF_FAMILY_MODULUS_SCALE = 0.5
SPEEDS_M_S = (5.5, 10.0, 20.8, 25.0)


def out_of_family_ball() -> dict:
    from ballimpact.report.inputs import builtin_ball

    spec = json.loads(builtin_ball("speeds").read_text())
    spec["name"] = "two-prony-3layer"
    for layer in spec["layers"]:
        material = layer["material"]
        material["prony"] = [dict(term) for term in OUT_OF_FAMILY_PRONY]
        if "c10_pa" in material:
            material["c10_pa"] *= OUT_OF_FAMILY_MODULUS_SCALE
        for term in material.get("terms", []):
            term["mu_pa"] *= OUT_OF_FAMILY_MODULUS_SCALE
    return spec


@pytest.fixture(scope="module")
def out_of_family_report(tmp_path_factory):
    """Tests of the two-Prony ball at the thesis' speeds (default mesh, 100 kHz, 1% noise, seed
    2024), then the default models and the generating ball against them (about 2 minutes)."""
    import numpy as np

    from ballimpact.calibrate.synthetic import synthetic_record
    from ballimpact.fe import SolverOptions

    folder = tmp_path_factory.mktemp("out_of_family")
    spec = out_of_family_ball()
    ball = folder / "two-prony-3layer.json"
    ball.write_text(json.dumps(spec))
    rng = np.random.default_rng(2024)
    files = []
    for speed in SPEEDS_M_S:
        record, fe = synthetic_record(spec, speed, SolverOptions(), 0.01, rng)
        path = folder / f"two_prony_{speed:04.1f}_m_s.csv"
        np.savetxt(path, np.c_[record.time_s, record.force_n], delimiter=",",
                   header="time_s,force_n", comments="")
        path.with_suffix(".json").write_text(json.dumps(
            {"mass_kg": 0.16, "impact_speed_m_s": speed,
             "rebound_speed_m_s": round(fe.cor * speed, 2)}))
        files.append(str(path))
    out = folder / "report"
    assert main(["report", *files, "--models", f"single_element,three_element,universal,{ball}",
                 "--out", str(out), "--quiet"]) == 0
    return json.loads((out / "report.json").read_text())


def test_out_of_family_generator_keeps_the_thesis_ranking(out_of_family_report):
    """What the models do against a ball outside the universal model's family (docs/report.md,
    "A generator outside the universal family"; `pytest -m slow -s -k out_of_family` prints the
    tables). Found: the ranking is the thesis' at every speed -- universal FE, then three-element,
    then single-element -- but the universal model's NRMSE grows from 1.8% (in-family demo) to
    3.2% (4.3% at 20.8 m/s), against the generator's floor of 1.3%."""
    report = out_of_family_report
    assert report["failures"] == []
    single, three, universal, generator = (_by(report, m) for m in (
        "single_element", "three_element", "universal FE", "FE two-prony-3layer"))
    for test in generator:
        nrmse = {name: runs[test]["comparison"]["force_nrmse"] for name, runs in (
            ("single", single), ("three", three), ("universal", universal),
            ("generator", generator))}
        assert nrmse["generator"] < 0.02  # the same ball and mesh: only the 1% noise is left
        assert nrmse["generator"] < nrmse["universal"] < nrmse["three"] < nrmse["single"], test
        assert abs(universal[test]["comparison"]["cor_error"]) < 0.035
    mean = {row[0]: row[-1] for row in report["tables"]["nrmse"]["rows"]}
    assert 0.02 < mean["universal FE"] < 0.045  # worse than in family (1.8%), still first
