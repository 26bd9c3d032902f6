"""Speed sweeps (`simulate --speed-m-s 5,10,20,30`) and ball comparisons (`compare`), issue 26
item 5: the batched sweep equals single runs, its rows against independent computations, a
compared pair of similar balls against the similarity closed form, and bad input.

Coarse mesh (3 mm elements) throughout: every run here shares one compiled program per batch
size (the universal ball's structure), so the file costs two compilations."""

from __future__ import annotations

import csv
import itertools
import json
import math

import numpy as np
import pytest

from ballimpact import cli
from ballimpact.errors import InputError
from ballimpact.fe import SolverOptions, load_ball, simulate
from ballimpact.balls.ball import universal_spec
from ballimpact.fe.sweep import (
    DIFFERENCE_KEYS,
    ROW_KEYS,
    compare_rows,
    parse_speeds,
    run_sweep,
    sweep_balls,
    sweep_figure,
    sweep_row,
)

COARSE = ["--element-size-m", "3e-3"]
OPTIONS = SolverOptions(element_size_m=3e-3)
#: five speeds: on a CPU two vmapped groups of four, the second padded
SPEEDS = (5.0, 10.0, 20.0, 30.0, 15.0)
#: float64 round-off over a run, relative
ROUND_OFF = 1e-9


def _main(capsys, *argv):
    capsys.readouterr()
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def universal_sweep():
    """The cricket-universal preset (table 7-3 interpolated per speed) at `SPEEDS` as one batch,
    and each speed's single run."""
    with pytest.warns(Warning):  # 5 and 30 m/s lie outside table 7-3: end rows held
        balls = sweep_balls("cricket-universal", SPEEDS)
    sweep = run_sweep(balls, SPEEDS, OPTIONS, label="cricket-universal")
    singles = [simulate(b, s, OPTIONS) for b, s in zip(balls, SPEEDS)]
    return sweep, singles


# --------------------------------------------------------------------------- parsing


def test_parse_speeds_keeps_order_and_values():
    assert parse_speeds("5,10,20.5,3e1") == (5.0, 10.0, 20.5, 30.0)
    assert parse_speeds(" 7 ") == (7.0,)


@pytest.mark.parametrize("text, words", [
    ("5,fast", "item 2 of '5,fast': 'fast' is not a number"),
    ("5,,10", "item 2 of '5,,10': empty"),
    ("5,10,", "item 3"),
    ("10,20,10.0", "10 m/s is given twice"),
    ("5,nan", "'nan' is not a finite number"),
    ("fast", "'fast' is not a number"),
])
def test_parse_speeds_refuses(text, words):
    with pytest.raises(InputError, match=words):
        parse_speeds(text)


# --------------------------------------------------------------------------- the sweep


def test_batched_sweep_equals_single_runs(universal_sweep):
    """One batch (two vmapped groups, the second padded) against five single runs: the same
    steps and, to float64 round-off, the same figures and force histories."""
    sweep, singles = universal_sweep
    assert sweep.speeds_m_s == SPEEDS
    for batched, single in zip(sweep.results, singles):
        assert batched.impact_speed_m_s == single.impact_speed_m_s
        assert batched.ball_name == single.ball_name
        assert batched.steps == single.steps
        a, b = sweep_row(batched), sweep_row(single)
        for key in ROW_KEYS:
            assert a[key] == pytest.approx(b[key], rel=ROUND_OFF, abs=0.0), key
        fa, fb = batched.history["contact_force_n"], single.history["contact_force_n"]
        assert np.max(np.abs(fa - fb)) <= ROUND_OFF * np.max(fb)


def test_each_speed_runs_its_own_table_7_3_constants(universal_sweep):
    sweep, _ = universal_sweep
    for ball, speed in zip(sweep.balls, SPEEDS):
        want = load_ball("cricket-universal", impact_speed_m_s=min(max(speed, 5.5), 25.0))
        assert ball.to_dict()["layers"] == want.to_dict()["layers"]
    c10 = {s: b.to_dict()["layers"][0]["material"]["c10_pa"] for b, s in zip(sweep.balls, SPEEDS)}
    assert len({c10[10.0], c10[15.0], c10[20.0]}) == 3  # inside the table: constants of their own


def _compression_from_force(result) -> float:
    """The centre's largest displacement toward the plane (m) from the contact force alone:
    v = -v_in + (1/m) integral of F, then the displacement, both by the trapezoidal rule from the
    first touch at t = 0 (the only external force on the ball is the plane's)."""
    h = result.history
    t = np.concatenate([[0.0], h["time_s"]])
    f = np.concatenate([[0.0], h["contact_force_n"]])
    dt = np.diff(t)
    v = -result.impact_speed_m_s + np.concatenate(
        [[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * dt)]) / result.mass_kg
    z = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * dt)])
    return float(-np.min(z))


def test_rows_against_independent_computations(universal_sweep):
    """Dynamic stiffness F^2/(m v^2) and rebound speed from the run's own figures; the centre's
    largest displacement (from the centre's height history) against the load-cell route, the
    contact force twice integrated, within 1e-4."""
    sweep, _ = universal_sweep
    for result, row in zip(sweep.results, sweep.rows()):
        v = result.impact_speed_m_s
        assert row["dynamic_stiffness_n_m"] == pytest.approx(
            result.peak_force_n ** 2 / (result.mass_kg * v * v), rel=1e-14)
        assert row["rebound_speed_m_s"] == pytest.approx(result.cor * v, rel=1e-14)
        assert row["max_deflection_m"] == pytest.approx(_compression_from_force(result),
                                                        rel=1e-4)
        assert 0 < row["max_deflection_m"] < result.outer_radius_m
    # a faster impact: a larger peak force and deflection, a shorter contact (this ball)
    rows = sorted(sweep.rows(), key=lambda r: r["impact_speed_m_s"])
    for slow, fast in itertools.pairwise(rows):
        assert fast["peak_force_n"] > slow["peak_force_n"]
        assert fast["max_deflection_m"] > slow["max_deflection_m"]
        assert fast["contact_time_s"] < slow["contact_time_s"]


def test_cli_sweep_json_table_and_plot(capsys, tmp_path, universal_sweep):
    """`simulate --speed-m-s 30,5,10,20`: one batch, rows ascending, equal to the library's
    sweep; the CSV table holds the same numbers; the plot is a PNG with three panels."""
    sweep, _ = universal_sweep
    table, plot = tmp_path / "sweep.csv", tmp_path / "sweep.png"
    code, out, err = _main(capsys, "simulate", "--ball", "cricket-universal", "--speed-m-s",
                           "30,5,10,20", *COARSE, "--json", "--table", table, "--plot", plot)
    assert code == 0, err
    data = json.loads(out)
    assert data["speeds_m_s"] == [5.0, 10.0, 20.0, 30.0]
    want = {r["impact_speed_m_s"]: r for r in sweep.rows()}
    for row in data["sweep"]:
        for key in ROW_KEYS:
            assert row[key] == pytest.approx(want[row["impact_speed_m_s"]][key], rel=ROUND_OFF)
    with open(table) as handle:
        read = list(csv.DictReader(handle))
    assert [float(r["impact_speed_m_s"]) for r in read] == data["speeds_m_s"]
    for written, row in zip(read, data["sweep"]):
        for key in ROW_KEYS:  # 10 significant digits in the file
            assert float(written[key]) == pytest.approx(row[key], rel=1e-9)
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert data["table"] == str(table) and data["plot"] == str(plot)


def test_cli_sweep_text_table(capsys):
    code, out, err = _main(capsys, "simulate", "--ball", "cricket-universal", "--speed-m-s",
                           "20,10,5,30", *COARSE)  # four: the compiled batch of the sweep
    assert code == 0, err
    lines = out.splitlines()
    assert "4 speeds in one batched run" in lines[0]
    assert "COR" in lines[1] and "stiff MN/m" in lines[1]
    assert [float(line.split()[0]) for line in lines[2:6]] == [5.0, 10.0, 20.0, 30.0]


def test_single_speed_keeps_the_one_run_output(capsys, universal_sweep):
    """One speed is today's run of one impact (the same JSON keys, no `sweep`), and equals the
    single run at that speed."""
    _, singles = universal_sweep
    code, out, err = _main(capsys, "simulate", "--ball", "cricket-universal", "--speed-m-s",
                           "10", *COARSE, "--json")
    assert code == 0, err
    data = json.loads(out)
    assert "sweep" not in data and "features" in data and "materials" in data
    assert data["impact_speed_m_s"] == 10.0
    assert data["peak_force_n"] == pytest.approx(singles[1].peak_force_n, rel=ROUND_OFF)
    assert data["cor"] == pytest.approx(singles[1].cor, rel=ROUND_OFF)


def test_sweep_plot_axes_are_returned():
    """The plot functions draw on the Axes given and return them (no pyplot)."""
    pytest.importorskip("matplotlib")

    class Fake:  # a sweep's shape, without running anything
        label = "fake"
        speeds_m_s = (10.0, 20.0)
        results = ()

        @staticmethod
        def rows():
            return [{"impact_speed_m_s": 10.0, "cor": 0.5, "peak_force_n": 4e3,
                     "contact_time_s": 1e-3}, {"impact_speed_m_s": 20.0, "cor": 0.4,
                                                "peak_force_n": 9e3, "contact_time_s": 9e-4}]

    figure = sweep_figure([Fake()])
    axes = figure.axes
    assert len(axes) == 3
    x, y = axes[1].lines[0].get_data()
    assert list(x) == [10.0, 20.0] and list(y) == [4.0, 9.0]  # kN
    assert list(axes[2].lines[0].get_data()[1]) == pytest.approx([1.0, 0.9])  # ms


# --------------------------------------------------------------------------- compare


@pytest.fixture(scope="module")
def similar_files(tmp_path_factory):
    """Ball A (the universal ball's 20 m/s constants) and ball B: moduli x 4, tau1 x 1/2, same
    size and density. B at 2v keeps rho v^2 / mu0 and tau1 v / R of A at v: the same
    dimensionless impact (COR equal, force x 4 = (2v / v)^2, times x 1/2)."""
    folder = tmp_path_factory.mktemp("compare")
    material = load_ball("cricket-universal", impact_speed_m_s=20.0).to_dict()
    layer = material["layers"][0]
    m = layer["material"]
    params = {"c10_pa": m["c10_pa"], "c01_pa": m["c01_pa"], "g1": m["prony"][0]["g"],
              "tau1_s": m["prony"][0]["tau_s"]}
    scaled = {"c10_pa": 4 * params["c10_pa"], "c01_pa": 4 * params["c01_pa"],
              "g1": params["g1"], "tau1_s": params["tau1_s"] / 2}
    a, b = folder / "a.json", folder / "b.json"
    a.write_text(json.dumps(universal_spec(params, layer["outer_radius_m"],
                                           layer["density_kg_m3"], name="ball-a")))
    b.write_text(json.dumps(universal_spec(scaled, layer["outer_radius_m"],
                                           layer["density_kg_m3"], name="ball-b")))
    return a, b


def test_compare_similar_balls_against_the_closed_form(capsys, tmp_path, similar_files):
    """compare A and B at 5, 10, 20, 40 m/s: B at 2v against A at v by similarity (COR equal,
    peak force x 4, contact time x 1/2, deflection equal) to 1e-6; the differences of the table
    against those computed here from the two balls' rows."""
    a, b = similar_files
    table, plot = tmp_path / "compare.csv", tmp_path / "compare.png"
    code, out, err = _main(capsys, "compare", "--ball", a, "--ball", b, "--speed-m-s",
                           "5,10,20,40", *COARSE, "--json", "--table", table, "--plot", plot)
    assert code == 0, err
    data = json.loads(out)
    assert data["balls"] == [str(a), str(b)] and data["reference_ball"] == str(a)
    rows = {(r["ball"], r["impact_speed_m_s"]): r for r in data["comparison"]}
    assert len(rows) == 8
    for v in (5.0, 10.0, 20.0):
        ra, rb = rows[(str(a), v)], rows[(str(b), 2 * v)]
        assert rb["cor"] == pytest.approx(ra["cor"], abs=1e-6)
        assert rb["peak_force_n"] == pytest.approx(4 * ra["peak_force_n"], rel=1e-6)
        assert rb["contact_time_s"] == pytest.approx(ra["contact_time_s"] / 2, rel=1e-6)
        assert rb["max_deflection_m"] == pytest.approx(ra["max_deflection_m"], rel=1e-6)
        # F^2 / (m v^2) scales as the moduli: x 4
        assert rb["dynamic_stiffness_n_m"] == pytest.approx(4 * ra["dynamic_stiffness_n_m"],
                                                            rel=1e-6)
    for v in (5.0, 10.0, 20.0, 40.0):
        ra, rb = rows[(str(a), v)], rows[(str(b), v)]
        assert rb["cor_difference"] == pytest.approx(rb["cor"] - ra["cor"], abs=1e-15)
        assert rb["peak_force_difference_percent"] == pytest.approx(
            100 * (rb["peak_force_n"] / ra["peak_force_n"] - 1), rel=1e-12)
        assert rb["contact_time_difference_percent"] == pytest.approx(
            100 * (rb["contact_time_s"] / ra["contact_time_s"] - 1), rel=1e-12)
        assert all(ra[k] == 0.0 for k in DIFFERENCE_KEYS)
        assert rb["peak_force_difference_percent"] > 0 > rb["contact_time_difference_percent"]
    with open(table) as handle:
        read = list(csv.DictReader(handle))
    assert len(read) == 8 and read[1]["ball"] == str(b)
    assert float(read[1]["cor_difference"]) == pytest.approx(
        rows[(str(b), 5.0)]["cor_difference"], rel=1e-9, abs=1e-15)
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_compare_rows_of_a_ball_with_itself_are_zero(universal_sweep):
    sweep, _ = universal_sweep
    for row in compare_rows([sweep, sweep]):
        assert all(row[k] == 0.0 for k in DIFFERENCE_KEYS)
    assert len(compare_rows([sweep, sweep])) == 2 * len(SPEEDS)


def test_compare_text_output(capsys, similar_files):
    a, b = similar_files
    code, out, err = _main(capsys, "compare", "--ball", a, "--ball", b, "--speed-m-s", "10",
                           *COARSE)
    assert code == 0, err
    assert f"differences from {a}" in out
    line_b = next(line for line in out.splitlines() if str(b) in line)
    cor_b = float(line_b.split()[2])
    assert math.isfinite(cor_b) and 0 < cor_b < 1


# --------------------------------------------------------------------------- bad input

UNIVERSAL = ["simulate", "--ball", "cricket-universal"]


@pytest.mark.parametrize("speeds, fragments", [
    ("10,fast", ("--speed-m-s", "'fast' is not a number")),
    ("10,,20", ("--speed-m-s", "item 2", "empty")),
    ("10,20,10", ("--speed-m-s", "given twice")),
    ("10,nan", ("--speed-m-s", "not a finite number")),
    ("fast", ("--speed-m-s", "'fast' is not a number")),  # one speed: as before the sweeps
    ("nan", ("--speed-m-s", "not a finite number")),
    ("10,100", ("impact speed 100 m/s is outside", "--allow speed-range")),
    ("1e6", ("impact speed 1e+06 m/s is outside",)),
])
def test_simulate_bad_speed_lists(bad_input, speeds, fragments):
    bad_input(UNIVERSAL + ["--speed-m-s", speeds], *fragments)


def test_simulate_sweep_refusals(bad_input, tmp_path):
    bad_input(UNIVERSAL + ["--speed-m-s", "10,20", "--solver", "3d"],
              "--speed-m-s", "axisymmetric solver only")
    bad_input(UNIVERSAL + ["--speed-m-s", "10,20", "--csv", tmp_path / "h.csv"],
              "--csv", "--table")
    bad_input(UNIVERSAL + ["--speed-m-s", "10,20", "--table", tmp_path / "no" / "t.csv"],
              "--table", "does not exist")
    bad_input(UNIVERSAL + ["--speed-m-s", "10,20", "--plot", tmp_path / "p.svg"], "--plot")
    bad_input(UNIVERSAL + ["--speed-m-s", "10,-5"], "impact_speed_m_s")
    bad_input(UNIVERSAL + ["--speed-m-s", "10", "--solver", "3d", "--table", tmp_path / "t.csv"],
              "--table")


def test_compare_bad_input(bad_input, tmp_path, similar_files):
    a, _ = similar_files
    speeds = ["--speed-m-s", "10,20"]
    bad_input(["compare", "--ball", "cricket-universal", *speeds], "--ball", "two or more")
    bad_input(["compare", "--ball", "cricket-universal", "--ball", "cricket-universal", *speeds],
              "--ball", "cricket-universal is given twice")
    spelled = a.parent / ".." / a.parent.name / a.name  # the same file, another spelling
    bad_input(["compare", "--ball", a, "--ball", spelled, *speeds], "given twice", str(a))
    bad_input(["compare", "--ball", "cricket-universal", "--ball", "no-such-ball", *speeds],
              "no-such-ball", "neither a preset")
    bad_input(["compare", "--ball", "cricket-universal", "--ball", a, "--speed-m-s", "10,90"],
              "impact speed 90 m/s is outside")
    bad_input(["compare", "--ball", "cricket-universal", "--ball", a, "--speed-m-s", "10,x"],
              "--speed-m-s", "'x' is not a number")
    bad_input(["compare", "--ball", "cricket-universal", "--ball", a, *speeds, "--plot",
               tmp_path / "p.jpg"], "--plot")


def test_one_speed_parses_to_a_number_as_before_the_sweeps():
    parser = cli.build_parser()
    args = parser.parse_args(UNIVERSAL + ["--impact-speed-m-s", "12.5"])
    assert args.speed_m_s == 12.5 and isinstance(args.speed_m_s, float)
    args = parser.parse_args(UNIVERSAL + ["--speed-m-s", "20,12.5"])
    assert args.speed_m_s == (20.0, 12.5)
