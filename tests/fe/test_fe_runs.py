"""The runs of `ballimpact simulate` from Python (`fe.runs`): a ball with its moduli overridden,
the sweep's speed check, one impact and a speed sweep with the `start` hook between the estimate
and the run, and their JSON summaries; the files of one run (`fe.output.write_run_files`).
Coarse meshes (4 mm) keep them quick."""

import numpy as np
import pytest

from ballimpact.errors import InputError, InputWarning
from ballimpact.fe import Axisymmetric, Hexahedral, Options3D, SolverOptions, load_ball
from ballimpact.fe.output import RunFiles, write_run_files
from ballimpact.fe.progress import RunEstimate
from ballimpact.fe.runs import (
    check_sweep_speeds,
    impact_summary,
    load_model,
    run_impact,
    run_speed_sweep,
    simulate_impact,
    simulate_speeds,
    speed_sweep_summary,
)
from ballimpact.fe.sweep import ROW_KEYS, sweep_json_row, sweep_row
from ballimpact.oblique.sweep import simulate_angles

COARSE = SolverOptions(element_size_m=4e-3)
BALL, SPEED = "cricket-universal", 20.0
#: float64 round-off over a run, relative (a batched run against the single one)
ROUND_OFF = 1e-9
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


class Recorder:
    """A `start` hook that keeps the estimates it gets and the times its progress is called at."""

    def __init__(self):
        self.estimates, self.times = [], []

    def __call__(self, cost):
        self.estimates.append(cost)
        return self.times.append


@pytest.fixture(scope="module")
def one_run():
    ball = load_model(BALL, SPEED)
    start = Recorder()
    return ball, run_impact(ball, SPEED, Axisymmetric(COARSE), start=start), start


def test_load_model_reads_the_preset_and_overrides_its_moduli():
    plain, model = load_ball(BALL, impact_speed_m_s=SPEED), load_model(BALL, SPEED)
    assert model.to_dict() == plain.to_dict()
    instantaneous = load_model(BALL, SPEED, moduli="instantaneous")
    assert {layer.material.moduli for layer in instantaneous.layers} == {"instantaneous"}
    assert [layer.outer_radius_m for layer in instantaneous.layers] == [
        layer.outer_radius_m for layer in plain.layers]
    with pytest.raises(InputError, match="moduli"):
        load_model(BALL, SPEED, moduli="short")


def test_sweep_speeds_are_checked_against_the_fe_range():
    check_sweep_speeds([10.0, 30.0])
    check_sweep_speeds([10.0, -5.0, float("nan")])  # left to load_ball, which names the field
    with pytest.raises(InputError, match="impact speed 100 m/s is outside"):
        check_sweep_speeds([10.0, 100.0])
    with pytest.warns(InputWarning, match="^speed-range"):
        check_sweep_speeds([100.0], allow={"speed-range"})


def test_run_impact_estimates_then_starts_then_runs(one_run):
    ball, result, start = one_run
    (cost,) = start.estimates
    assert isinstance(cost, RunEstimate) and cost.elements == result.elements
    assert cost.steps >= result.steps  # the estimate is on the high side
    assert start.times and start.times == sorted(start.times)  # progress after every chunk
    assert start.times[-1] >= result.history["time_s"][-1] > result.contact_time_s  # to the end
    assert result.impact_speed_m_s == SPEED and 0.0 < result.cor < 1.0
    assert result.energy_balance_error < 0.01


def test_impact_summary_holds_the_features_ball_and_constants(one_run):
    ball, result, _ = one_run
    out = impact_summary(result, ball)
    assert {k: out[k] for k in result.summary()} == result.summary()
    assert out["features"]["P6"] == pytest.approx(result.peak_force_n, rel=0.01)
    assert out["features"]["P1"] == pytest.approx(result.contact_time_s, rel=0.02)
    assert out["materials"] == ball.to_dict()
    used = out["material_constants_used"]
    assert [u["layer"] for u in used] == [layer.name for layer in ball.layers]
    assert [u["model"] for u in used] == [layer.material.model for layer in ball.layers]
    assert "target_specification" not in out


def test_run_files_are_the_histories_row_and_plot(one_run, tmp_path):
    _, result, _ = one_run
    csv, table, plot = tmp_path / "h.csv", tmp_path / "t.csv", tmp_path / "p.png"
    written = write_run_files(result, RunFiles(csv=csv, table=table, plot=plot))
    assert written == {"csv": str(csv), "table": str(table), "plot": str(plot)}
    history = np.genfromtxt(csv, delimiter=",", names=True)
    assert list(history.dtype.names) == list(result.history)
    assert len(history) == result.steps
    assert np.allclose(history["contact_force_n"], result.history["contact_force_n"], rtol=1e-9)
    row = np.genfromtxt(table, delimiter=",", names=True, dtype=None, encoding="utf-8")
    want = sweep_json_row(result)
    assert list(row.dtype.names) == list(want)
    for key in ("cor", "peak_force_n", "contact_time_s", "energy_balance_error"):
        assert float(row[key]) == pytest.approx(want[key], rel=1e-9)
    assert plot.read_bytes().startswith(PNG_MAGIC)
    assert write_run_files(result, RunFiles()) == {}


def test_sweep_json_row_adds_the_runs_figures(one_run):
    _, result, _ = one_run
    row = sweep_json_row(result)
    assert list(row) == [*ROW_KEYS, "energy_balance_error", "steps", "ball_name"]
    assert {k: row[k] for k in ROW_KEYS} == sweep_row(result)
    assert row["steps"] == result.steps and row["ball_name"] == result.ball_name


def test_speed_sweep_is_one_batch_equal_to_the_single_runs(one_run):
    _, single, _ = one_run
    start = Recorder()
    sweep = run_speed_sweep(BALL, [SPEED, 10.0], COARSE, moduli="long_term", label="u",
                            start=start)
    assert sweep.speeds_m_s == (SPEED, 10.0) and sweep.label == "u"
    assert len(start.estimates) == 1 and start.estimates[0].runs == 2
    assert single.cor == pytest.approx(sweep.results[0].cor, rel=ROUND_OFF)
    assert single.peak_force_n == pytest.approx(sweep.results[0].peak_force_n, rel=ROUND_OFF)
    out = speed_sweep_summary(sweep)
    assert out["ball"] == "u" and out["speeds_m_s"] == [SPEED, 10.0]
    assert out["sweep"] == [sweep_json_row(r) for r in sweep.results]
    assert [r["impact_speed_m_s"] for r in out["sweep"]] == [SPEED, 10.0]
    assert out["moduli"] == "long_term" and out["elements"] == single.elements
    assert out["integration"] == "reduced" and out["precision"] == "float64"
    assert out["materials"] == [b.to_dict() for b in sweep.balls]
    assert out["materials"][0]["name"] != out["materials"][1]["name"]  # per-speed constants
    with pytest.raises(InputError, match="impact speed 100 m/s is outside"):
        run_speed_sweep(BALL, [10.0, 100.0], COARSE)


def test_simulate_impact_is_the_run_its_summary_and_files(one_run, tmp_path):
    """`simulate_impact`, the command's one call: the same run as `run_impact`, the estimate
    announcing nothing for an axisymmetric run, its JSON object with the files written."""
    _, result, _ = one_run
    start = Recorder()
    again, out = simulate_impact(BALL, SPEED, Axisymmetric(COARSE), start=start,
                                 files=RunFiles(csv=tmp_path / "h.csv"))
    assert again.cor == pytest.approx(result.cor, rel=ROUND_OFF)
    assert out["csv"] == str(tmp_path / "h.csv") and "features" in out
    assert len(start.estimates) == 1 and start.estimates[0].announce == ""
    assert start.estimates[0].chunk_steps == COARSE.chunk_steps


@pytest.mark.parametrize("call, flag", [
    (lambda tmp: simulate_impact(BALL, SPEED, Hexahedral(), files=RunFiles(table=tmp / "t.csv")),
     "--table"),
    (lambda tmp: simulate_speeds(BALL, [10.0, 20.0], files=RunFiles(csv=tmp / "h.csv")),
     "--csv"),
    (lambda tmp: simulate_speeds(BALL, [10.0, 20.0], target="foam-pad"), "--target"),
    (lambda tmp: simulate_impact(BALL, SPEED, files=RunFiles(plot=tmp / "p.jpg")), "--plot"),
    (lambda tmp: simulate_impact(BALL, SPEED, Hexahedral(Options3D(slab_depth_growth=1.5))),
     "--slab-depth-growth"),
    (lambda tmp: simulate_angles(BALL, SPEED, [10.0, 30.0], files=RunFiles(vtk=tmp / "s.pvd")),
     "--vtk"),
    (lambda tmp: simulate_angles(BALL, SPEED, [10.0, 30.0], files=RunFiles(plot=tmp / "p.png")),
     "--plot: the normalised axes"),
])
def test_the_library_runs_refuse_before_anything_runs(call, flag, tmp_path):
    """What the command line refused is refused by its one call, naming the flag, before any
    estimate, mesh or compilation."""
    with pytest.raises(InputError, match=flag):
        call(tmp_path)
