"""`ballimpact standard` (docs/standards.md): published ball test methods on a lab's records and
on a ball model.

Known answers: each synthetic record is a triangular force pulse whose peak falls on a sample,
so the feature extraction's refined peak is the triangle's peak F0 to rounding (its two-line
cusp model is exact for a kinked peak: features.refine_peak), and whose side file gives the
inbound speed v and the rebound speed e v. Hence per shot COR = e and DS = F0^2 / (m v^2)
exactly; the per-ball means and SDs and the mean and SD of the ball means are computed here with
numpy, independently of the package, and compared to 1e-9 (relative). Compression curves are
straight lines F = k d, so the force read at 6.35 mm is k x 6.35 mm exactly.
"""

import json
import re
import warnings

import numpy as np
import pytest

from ballimpact import cli
from ballimpact.errors import InputError, InputWarning
from ballimpact.fe import SolverOptions
from ballimpact.records.pulses import triangle
from ballimpact.records.loaders import LBF_N
from ballimpact.standards import (
    INCH_M,
    METHODS,
    SIXTY_MPH_M_S,
    ball_id_function,
    from_records,
    get_method,
    on_model,
)

RATE_HZ = 200e3
MASS_KG = 0.145  # a baseball
#: ball -> (COR per shot, peak force per shot N, inbound speed per shot m/s): scatter about the
#: method's 26.82 m/s within +-0.3 m/s
BALLS = {
    "ballA": ([0.512, 0.498, 0.505, 0.520], [9100.0, 9350.0, 8900.0, 9200.0],
              [26.60, 26.95, 27.10, 26.52]),
    "ballB": ([0.471, 0.480, 0.466, 0.476], [10400.0, 10150.0, 10620.0, 10300.0],
              [26.85, 26.70, 26.98, 27.05]),
    "ballC": ([0.540, 0.552, 0.547, 0.535], [8300.0, 8450.0, 8200.0, 8390.0],
              [26.90, 26.55, 26.75, 27.00]),
}
REL = 1e-9


def write_record(path, cor, peak_n, speed_m_s, mass_kg=MASS_KG, side_mass=True):
    """A triangular pulse with its peak on a sample and an impulse m v (1 + e) (so that the
    impulse check passes), with its side file."""
    step = 1.0 / RATE_HZ
    rise = 60 * step  # on the sample grid: the peak is a sample
    fall = 2 * mass_kg * speed_m_s * (1 + cor) / peak_n - rise
    record = triangle(peak_n, rise, fall, RATE_HZ)
    path.write_text("time_s,force_n\n" + "".join(
        f"{float(t)!r},{float(f)!r}\n" for t, f in zip(record.time_s, record.force_n)))
    side = {"impact_speed_m_s": speed_m_s, "rebound_speed_m_s": cor * speed_m_s}
    if side_mass:
        side["mass_kg"] = mass_kg
    path.with_suffix(".json").write_text(json.dumps(side))
    return path


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    folder = tmp_path_factory.mktemp("lab")
    for ball, (cors, peaks, speeds) in BALLS.items():
        for k, (e, f, v) in enumerate(zip(cors, peaks, speeds), start=1):
            write_record(folder / f"{ball}_{k:02d}.csv", e, f, v)
    return folder


def expected(per_shot):
    """ball -> (mean, SD (n - 1), n) and the (mean, SD) of the ball means, with numpy."""
    balls = {ball: (np.mean(v), np.std(v, ddof=1), len(v)) for ball, v in per_shot.items()}
    means = np.array([m for m, _, _ in balls.values()])
    return balls, (np.mean(means), np.std(means, ddof=1))


def check_against(result, key, per_shot):
    balls, (mean, sd) = expected(per_shot)
    assert [entry["ball"] for entry in result["balls"]] == list(balls)
    for entry in result["balls"]:
        m, s, n = balls[entry["ball"]]
        assert entry["count"] == n and entry[key]["count"] == n
        assert entry[key]["mean"] == pytest.approx(m, rel=REL)
        assert entry[key]["sd"] == pytest.approx(s, rel=REL)
    assert result["overall"][key]["mean"] == pytest.approx(mean, rel=REL)
    assert result["overall"][key]["sd"] == pytest.approx(sd, rel=REL)
    assert result["overall"]["balls"] == len(balls)


# --------------------------------------------------------------------------- the CLI verb


def run_json(capsys, *argv):
    capsys.readouterr()
    code = cli.main(["standard", *map(str, argv), "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    return json.loads(out), err


# --------------------------------------------------------------------------- records: known answers


def test_cor_of_a_synthetic_lab_folder_reproduces_the_known_means_and_sds(lab, capsys):
    result, err = run_json(capsys, "cor", lab)
    assert "warning" not in err  # every speed within +-0.3 m/s of 26.82 m/s
    check_against(result, "cor", {ball: cors for ball, (cors, _, _) in BALLS.items()})
    assert len(result["shots"]) == 12 and result["designation"] == "ASTM F1887"
    check_against(result, "impact_speed_m_s", {b: s for b, (_, _, s) in BALLS.items()})


def test_dynamic_stiffness_of_the_folder_is_peak_squared_over_m_v_squared(lab, capsys):
    result, _ = run_json(capsys, "dynamic-stiffness", lab)
    ds = {ball: [f * f / (MASS_KG * v * v) for f, v in zip(peaks, speeds)]
          for ball, (_, peaks, speeds) in BALLS.items()}
    check_against(result, "dynamic_stiffness_n_m", ds)
    # lbf/in: 1 lbf/in = 4.4482216152605 N / 0.0254 m = 175.1268 N/m
    check_against(result, "dynamic_stiffness_lbf_in",
                  {b: [x / 175.12683524647637 for x in v] for b, v in ds.items()})
    check_against(result, "peak_force_n", {b: p for b, (_, p, _) in BALLS.items()})


def test_text_output_has_a_line_per_ball_and_the_overall_line(lab, capsys):
    capsys.readouterr()
    assert cli.main(["standard", "F1887", str(lab)]) == 0
    out = capsys.readouterr().out.splitlines()
    balls, (mean, sd) = expected({b: c for b, (c, _, _) in BALLS.items()})
    assert "ASTM F1887 cor: 12 records, 3 balls" in out[0]
    line = next(x for x in out if x.strip().startswith("ballB"))
    m, s, _ = balls["ballB"]
    assert f"{m:.5g} +- {s:.3g}" in line and "(n=4)" in line
    assert f"{mean:.5g} +- {sd:.3g}" in out[-1] and "3 ball means" in out[-1]


def test_table_has_a_row_per_shot_per_ball_and_overall(lab, tmp_path, capsys):
    table = tmp_path / "cor.csv"
    result, _ = run_json(capsys, "cor", lab, "--table", table)
    lines = table.read_text().splitlines()
    assert lines[0] == "kind,ball,file,count,cor,cor_sd,impact_speed_m_s,impact_speed_m_s_sd"
    assert len(lines) == 1 + 12 + 3 + 1
    last = lines[-1].split(",")
    assert last[0] == "all" and float(last[4]) == pytest.approx(
        result["overall"]["cor"]["mean"], rel=1e-11)


def test_off_speed_records_are_used_with_a_warning_naming_the_file(tmp_path, capsys):
    write_record(tmp_path / "ballZ_01.csv", 0.5, 9000.0, 26.9)
    off = write_record(tmp_path / "ballZ_02.csv", 0.5, 9000.0, 27.6)  # +0.78 m/s
    result, err = run_json(capsys, "cor", tmp_path)
    warned = [line for line in err.splitlines() if line.startswith("warning:")]
    assert len(warned) == 1 and str(off) in warned[0] and "+-0.6 m/s" in warned[0]
    assert result["overall"]["shots"] == 2
    assert result["overall"]["cor"]["sd"] is None  # one ball: no SD of the ball means (null)
    assert result["balls"][0]["cor"]["sd"] == 0.0 and result["balls"][0]["count"] == 2


def test_a_nominal_speed_keeps_each_records_own_impact_speed(tmp_path, capsys):
    """--impact-speed-m-s is the method's nominal speed: the shots keep their records' own
    inbound speeds (side files), and the off-nominal note names the nominal."""
    speeds = [26.7, 26.9]
    for k, v in enumerate(speeds, start=1):
        write_record(tmp_path / f"b-{k}.csv", 0.45, 7000.0, v)
    result, _ = run_json(capsys, "cor", tmp_path, "--impact-speed-m-s", 26.8)
    assert [s["impact_speed_m_s"] for s in result["shots"]] == pytest.approx(speeds, rel=1e-12)
    assert result["nominal_speed_m_s"] == 26.8


def test_mass_flag_serves_records_without_a_side_file_mass(tmp_path):
    speeds = [26.7, 26.9]
    for k, v in enumerate(speeds, start=1):
        write_record(tmp_path / f"b-{k}.csv", 0.45, 7000.0, v, mass_kg=0.18, side_mass=False)
    with pytest.raises(InputError, match="no ball mass"):
        from_records("dynamic-stiffness", [tmp_path])
    result = from_records("dynamic-stiffness", [tmp_path], mass_kg=0.18)
    ds = [7000.0**2 / (0.18 * v * v) for v in speeds]
    assert result["balls"][0]["ball"] == "b"
    assert result["overall"]["dynamic_stiffness_n_m"]["mean"] == pytest.approx(np.mean(ds),
                                                                                rel=REL)


def test_compression_curves_give_the_force_at_a_quarter_inch(tmp_path, capsys):
    # straight lines F = k d (d in mm in the file, not on 6.35 mm): linear interpolation is exact
    stiffness = {"s1": [180e3, 186e3, 177e3], "s2": [201e3, 195e3, 199e3]}
    grid_mm = np.array([0.0, 0.8, 2.1, 3.3, 4.9, 6.0, 6.7, 7.5])
    for ball, ks in stiffness.items():
        for k, slope in enumerate(ks, start=1):
            rows = "".join(f"{float(d)!r},{float(slope * d * 1e-3)!r}\n" for d in grid_mm)
            (tmp_path / f"{ball}_{k}.csv").write_text("deflection_mm,force_n\n" + rows)
    result, _ = run_json(capsys, "compression", tmp_path)
    check_against(result, "force_at_6_35_mm_n",
                  {b: [k * 6.35e-3 for k in ks] for b, ks in stiffness.items()})
    check_against(result, "force_at_6_35_mm_lbf",
                  {b: [k * 6.35e-3 / 4.4482216152605 for k in ks] for b, ks in stiffness.items()})


# --------------------------------------------------------------------------- ball ids, methods


@pytest.mark.parametrize("name, pattern, ball", [
    ("ballA_01.csv", None, "ballA"), ("ball-7-3.csv", None, "ball-7"),
    ("lot4_ball_B_12.wav", None, "lot4_ball_B"), ("single.csv", None, "single"),
    ("shot3_ballQ.csv", r"ball\w+", "ballQ"), ("x_B17_s2.csv", r"_(B\d+)_", "B17"),
    ("run2-id=K9.csv", r"id=(?P<ball>\w+)", "K9")])
def test_ball_id_from_the_file_name(tmp_path, name, pattern, ball):
    assert ball_id_function(pattern)(tmp_path / name) == ball


def test_methods_by_name_or_designation_and_their_facts():
    assert get_method("F1887") is METHODS["cor"] and get_method("astm f2845").name == \
        "dynamic-stiffness"
    assert get_method("F1888").nominal == pytest.approx(0.25 * 0.0254, rel=1e-15)
    assert SIXTY_MPH_M_S == pytest.approx(60 * 1609.344 / 3600, rel=1e-15)
    assert LBF_N / INCH_M == pytest.approx(175.1268, rel=1e-6)


def test_list_names_each_method_with_a_line(capsys):
    capsys.readouterr()
    assert cli.main(["standard", "--list"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert len(out) == len(METHODS)
    for line, (name, method) in zip(out, METHODS.items()):
        assert line.startswith(name) and method.designation in line


# --------------------------------------------------------------------------- bad input


def test_bad_input(bad_input, lab, tmp_path):
    folder = str(lab)
    bad_input(["standard", "bogus", folder], "unknown", "cor", "dynamic-stiffness",
              "compression")
    bad_input(["standard", "cor", folder, "--ball", "cricket-universal"], "not both")
    bad_input(["standard", "cor"], "FILES_OR_DIRS", "--ball")
    bad_input(["standard"], "METHOD", "--list")
    bad_input(["standard", "cor", folder, "--mass-kg", "145"], "--mass-kg", "grams")
    bad_input(["standard", "dynamic-stiffness", "--ball", "cricket-universal", "--mass-kg",
               "0.16"], "--mass-kg", "own mass")
    bad_input(["standard", "cor", folder, "--table", str(tmp_path / "t.txt")], "--table", ".csv")
    bad_input(["standard", "cor", folder, "--ball-id-pattern", "nomatch(\\d+)"],
              "--ball-id-pattern", "ballA_01")
    bad_input(["standard", "cor", folder, "--ball-id-pattern", "ball(["], "regular expression")
    empty = tmp_path / "empty"
    empty.mkdir()
    bad_input(["standard", "cor", str(empty)], str(empty), "no test records")
    short = tmp_path / "short"
    short.mkdir()
    (short / "s_1.csv").write_text("deflection_mm,force_n\n0,0\n2,300\n5,800\n")
    bad_input(["standard", "compression", str(short)], "s_1.csv", "6.35 mm")
    bad_input(["standard", "compression", str(short), "--mass-kg", "0.15"], "does not use")
    bad_input(["standard", "cor", "--ball", "baseball", "--impact-speed-m-s", "60"],
              "--impact-speed-m-s 60", "looks like mph", "26.82 m/s")


# --------------------------------------------------------------------------- on a ball model

#: a coarse mesh for speed; the comparison is with the same run, so exact
COARSE = 3e-3


@pytest.fixture(scope="module")
def reference_run():
    from ballimpact.fe import load_ball, simulate

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)  # 26.8 m/s past the table's 25 m/s
        ball = load_ball("cricket-universal", impact_speed_m_s=SIXTY_MPH_M_S)
        return ball, simulate(ball, SIXTY_MPH_M_S, SolverOptions(element_size_m=COARSE))


def test_model_cor_and_dynamic_stiffness_equal_the_fe_run(reference_run, capsys):
    _, run = reference_run
    result, _ = run_json(capsys, "cor", "--ball", "cricket-universal", "--element-size-m",
                         COARSE)
    assert result["result"]["cor"] == pytest.approx(run.cor, rel=REL)
    assert result["cost"]["steps"] == run.steps and result["cost"]["elements"] == run.elements
    assert result["cost"]["wall_time_s"] > 0
    capsys.readouterr()
    assert cli.main(["standard", "dynamic-stiffness", "--ball", "cricket-universal",
                     "--element-size-m", str(COARSE)]) == 0
    out = capsys.readouterr().out
    ds = run.peak_force_n**2 / (run.mass_kg * SIXTY_MPH_M_S**2)  # (F/v)^2 / m, the run's m
    shown = float(re.search(r"([\d.e+]+) N/m", out).group(1))
    assert shown == pytest.approx(ds, rel=1e-4)  # printed to 5 digits
    assert re.search(rf"cost: [\d.]+ s wall, {run.steps} steps, {run.elements} elements", out)
    with pytest.warns(InputWarning, match="outside the table"):  # 26.8 m/s past its 25 m/s
        direct = on_model("dynamic-stiffness", "cricket-universal",
                          options=SolverOptions(element_size_m=COARSE))
    assert direct["result"]["dynamic_stiffness_n_m"] == pytest.approx(ds, rel=REL)


def test_model_compression_equals_fe_compress(reference_run, capsys):
    from ballimpact.fe import compress

    ball, _ = reference_run
    curve = compress(ball, 6.35e-3, options=SolverOptions(element_size_m=COARSE))
    result, _ = run_json(capsys, "compression", "--ball", "cricket-universal",
                         "--element-size-m", COARSE)
    assert result["result"]["force_at_6_35_mm_n"] == pytest.approx(curve.force_n[-1], rel=REL)
    assert result["result"]["force_at_6_35_mm_lbf"] == pytest.approx(
        curve.force_n[-1] / 4.4482216152605, rel=REL)
    assert result["cost"]["increments"] == curve.increments


def test_a_noisy_records_uncertainty_is_given_in_each_unit_of_the_method(tmp_path, capsys):
    """A noisy record: each shot's standard uncertainty in every unit the method reports, the
    lbf/in one the N/m one over 175.1268 (both from the record's bootstrap, docs/features.md)."""
    from ballimpact.records.pulses import hunt_crossley_pulse, load_cell_record

    pulse, duration, _ = hunt_crossley_pulse(0.5, SIXTY_MPH_M_S, MASS_KG)
    record = load_cell_record(pulse, duration, 100e3, noise=0.01, rng=np.random.default_rng(2))
    path = tmp_path / "ballA_01.csv"
    path.write_text("time_s,force_n\n" + "".join(
        f"{t!r},{f!r}\n" for t, f in zip(record.time_s.tolist(), record.force_n.tolist())))
    path.with_suffix(".json").write_text(json.dumps(
        {"impact_speed_m_s": SIXTY_MPH_M_S, "mass_kg": MASS_KG}))
    result, _ = run_json(capsys, "dynamic-stiffness", tmp_path)
    u = result["shots"][0]["uncertainty"]
    assert u["dynamic_stiffness_n_m"] > 0 and u["peak_force_n"] > 0
    assert u["dynamic_stiffness_lbf_in"] == pytest.approx(
        u["dynamic_stiffness_n_m"] / 175.12683524647637, rel=1e-12)
    cor, _ = run_json(capsys, "cor", tmp_path)
    shot = cor["shots"][0]
    assert set(shot["uncertainty"]) == {"cor"} and shot["uncertainty"]["cor"] > 0
