"""Calibration of layered FE balls: parameter paths and bad input, gradients through the explicit
solver against central finite differences, Levenberg-Marquardt on a closed-form problem, decision
making, the search's checkpoint and resume, stages, and the command end to end (coarse meshes)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from ballimpact.calibrate import (
    CalibrationProblem,
    CalibrationTest,
    Stage,
    calibrate,
    decide,
    free_parameter,
    parse_stage,
    search,
    smooth_misfits,
    standard_runs,
)
from ballimpact.calibrate.gradient import central_differences, levenberg_marquardt
from ballimpact.calibrate.problem import get_value, with_values
from ballimpact.cli import main
from ballimpact.errors import InputError
from ballimpact.fe import SolverOptions, load_ball, simulate
from ballimpact.balls.ball import CRICKET_3LAYER_SPEC, UNIVERSAL_DENSITY_KG_M3, universal_spec
from ballimpact.records.features import extract_features
from ballimpact.identifiability import identification_notes, standard_errors

COARSE = SolverOptions(element_size_m=4e-3)
MAT = "layers.ball.material."
TRUTH = {"c10_pa": 4.0e6, "c01_pa": -0.4e6, "g1": 0.7, "tau1_s": 8e-5}
START = {"c10_pa": 4.5e6, "c01_pa": -0.3e6, "g1": 0.6, "tau1_s": 1e-4}
BOUNDS = {MAT + "c10_pa": (3e6, 7e6), MAT + "c01_pa": (-1e6, 0.5e6),
          MAT + "prony.0.g": (0.3, 0.9), MAT + "prony.0.tau_s": (2e-5, 5e-4)}


def universal(params) -> dict:
    return universal_spec(params, 0.036, UNIVERSAL_DENSITY_KG_M3)


@pytest.fixture(scope="module")
def synthetic_test():
    fe = simulate(load_ball(universal(TRUTH)), 20.0, COARSE)
    return CalibrationTest("synthetic", extract_features(fe.record()))


def homogeneous_problem(test, objectives=("nrmse", "cor", "contact_time")):
    template = universal(START)
    return CalibrationProblem(template, [test], [free_parameter(template, p, *b)
                                                 for p, b in BOUNDS.items()], objectives)


# ---- paths and bad input ---------------------------------------------------------------------
def test_paths_resolve_by_layer_name_or_index():
    spec = load_ball("cricket-3layer").to_dict()
    assert get_value(spec, "layers.core.material.c10_pa") == 4.72e6
    assert get_value(spec, "layers.0.material.prony.0.g") == 0.41
    assert get_value(spec, "layers.midsole.material.terms.0.mu_pa") == 70.3e6
    changed = with_values(spec, {"layers.cover.material.c01_pa": -0.2e6})
    assert get_value(changed, "layers.cover.material.c01_pa") == -0.2e6
    assert get_value(spec, "layers.cover.material.c01_pa") == -0.5e6  # the template is kept


@pytest.mark.parametrize("path, low, high, message", [
    ("layers.core.material.c11_pa", 1e6, 2e6, "unknown parameter path"),
    ("layers.kernel.material.c10_pa", 1e6, 2e6, "no entry 'kernel'"),
    ("layers.core.material.c10_pa", 7e6, 3e6, "bounds reversed"),
    ("layers.core.material.prony.0.g", 0.0, 1.2, "outside the material's valid range"),
    ("layers.core.outer_radius_m", 0.01, 0.02, "radii are fixed"),
    ("layers.core.material.model", 0.0, 1.0, "not a number"),
    ("layers.core.material.prony.0.k", 0.0, 0.5, "must stay above 0"),
])
def test_bad_free_parameters_are_named(path, low, high, message):
    spec = load_ball("cricket-3layer").to_dict()
    with pytest.raises(InputError, match=message) as error:
        free_parameter(spec, path, low, high)
    assert path in str(error.value)


def test_cli_bad_input_exits_2(tmp_path, capsys):
    fe = simulate(load_ball(universal(TRUTH)), 20.0, COARSE)
    record = fe.record()
    csv = tmp_path / "test.csv"
    np.savetxt(csv, np.column_stack([record.time_s, record.force_n]), delimiter=",",
               header="time_s,force_n", comments="")
    base = ["calibrate", "--ball", "cricket-universal", "--element-size-m", "4e-3", "--mass-kg", "0.16",
            "--method", "gradient"]
    cases = [
        ([f"--test={csv}", "--free", "layers.ball.material.c10_pa=3e6:7e6"], "no impact speed"),
        ([f"--test={csv}:20", "--free", "layers.ball.material.c11_pa=3e6:7e6"],
         "unknown parameter path"),
        ([f"--test={csv}:20", "--free", "layers.ball.material.c10_pa=7e6:3e6"], "reversed"),
        ([f"--test={csv}:20", "--free", "layers.ball.material.prony.0.g=0.5:1.5"],
         "valid range"),
        ([f"--test={csv}:fast", "--free", "layers.ball.material.c10_pa=3e6:7e6"],
         "not a number"),
        ([f"--test={csv}:20", "--free", "layers.ball.material.c10_pa=3e6:7e6",
          "--objectives", "nrmse,speed"], "--objectives"),
        ([f"--test={csv}:20", "--free", "layers.ball.material.c10_pa=3e6:7e6",
          "--stage", "free=layers.cover.*"], "matches none"),
        ([f"--test={csv}:20:kernel", "--free", "layers.ball.material.c10_pa=3e6:7e6"],
         "--test test: test layers = 'kernel'"),
        ([f"--test={csv}:20", "--free", "layers.ball.material.c10_pa=3e6:7e6",
          "--stage", "name=../up"], "--stage name="),
        ([f"--test={csv}:20", "--free", "layers.ball.material.c10_pa=3e6:7e6",
          "--stage", "objectives=cor,spin"], "--stage stage1: objectives=cor,spin"),
        ([f"--test={csv}:20", "--free", "layers.ball.material.c10_pa=3e6:7e6",
          "--precision", "float32"], "--precision float32"),
        ([f"--test={csv}:20", "--free", "layers.ball.material.c10_pa=3e6:7e6",
          "--max-evaluations", "0"], "--max-evaluations"),
    ]
    for args, message in cases:
        assert main(base + args) == 2, args
        err = capsys.readouterr().err
        assert message in err, (args, err)


def test_invalid_combinations_are_failed_designs(synthetic_test):
    """Each bound alone gives a valid ball, but C10 + C01 <= 0 at a corner does not: that design
    fails with its reason instead of stopping the search."""
    template = universal(START)
    problem = CalibrationProblem(template, [synthetic_test], [
        free_parameter(template, MAT + "c10_pa", 1e6, 5e6),
        free_parameter(template, MAT + "c01_pa", -2e6, 0.0)], ("nrmse",))
    from ballimpact.calibrate.evaluate import evaluate

    done = evaluate(problem, np.array([[0.0, 0.0], [0.8, 0.8]]), COARSE)
    assert "not a valid ball" in done.failed[0] and np.isnan(done.objectives[0, 0])
    assert done.failed[1] is None and np.isfinite(done.objectives[1, 0])


# ---- gradients through the solver ------------------------------------------------------------
def _check_gradients(misfit, u, h=1e-5):
    """Forward-mode, reverse-mode and central-difference gradients of the sum of squares."""
    r, jac = misfit.evaluate(u, "jacobian")
    forward = 2.0 * jac[:, :-1].T @ r
    total, reverse = misfit.evaluate(u, "grad")
    assert total == pytest.approx(r @ r, rel=1e-12)
    central = central_differences(misfit, u, h)
    np.testing.assert_allclose(forward, central, rtol=0.01)
    np.testing.assert_allclose(reverse[:-1], central, rtol=0.01)
    return central


def test_gradients_of_a_homogeneous_ball_match_central_differences(synthetic_test):
    """d(misfit)/d(C10, C01, g1, tau1) by jax.jacfwd and jax.grad through the whole explicit run
    against central differences of the run, within 1% (float64)."""
    problem = homogeneous_problem(synthetic_test)
    misfit = smooth_misfits(problem, COARSE, standard_runs(problem, problem.start_unit(),
                                                           COARSE))[0]
    central = _check_gradients(misfit, problem.start_unit())
    assert np.all(np.abs(central) > 1e-4)  # every parameter matters here


def test_gradients_of_one_layer_of_the_3layer_ball():
    truth = with_values(CRICKET_3LAYER_SPEC, {"layers.core.material.c10_pa": 5.2e6})
    fe = simulate(load_ball(truth), 15.0, COARSE)
    test = CalibrationTest("ball", extract_features(fe.record()))
    paths = {"layers.core.material.c10_pa": (3e6, 7e6), "layers.core.material.c01_pa": (-1e6, 0.0),
             "layers.core.material.prony.0.g": (0.2, 0.6),
             "layers.core.material.prony.0.tau_s": (2e-5, 3e-4)}
    problem = CalibrationProblem(CRICKET_3LAYER_SPEC, [test],
                                 [free_parameter(CRICKET_3LAYER_SPEC, p, *b)
                                  for p, b in paths.items()])
    misfit = smooth_misfits(problem, COARSE, standard_runs(problem, problem.start_unit(),
                                                           COARSE))[0]
    _check_gradients(misfit, problem.start_unit())


def test_misfit_is_the_nrmse_on_its_window(synthetic_test):
    """At the truth the fixed-increment run reproduces the test within the time discretisation:
    the smooth misfit's force part (an NRMSE^2) is small, and far from it large."""
    problem = homogeneous_problem(synthetic_test, objectives=("nrmse",))
    truth = problem.unit({MAT + "c10_pa": 4.0e6, MAT + "c01_pa": -0.4e6,
                          MAT + "prony.0.g": 0.7, MAT + "prony.0.tau_s": 8e-5})
    misfit = smooth_misfits(problem, COARSE, standard_runs(problem, truth, COARSE))[0]
    r_truth = misfit.evaluate(truth)
    r_start = misfit.evaluate(problem.start_unit())
    assert np.sqrt(r_truth @ r_truth) < 0.01
    assert np.sqrt(r_start @ r_start) > 0.05


# ---- Levenberg-Marquardt ---------------------------------------------------------------------
def test_levenberg_marquardt_solves_a_bounded_least_squares_problem():
    """Rosenbrock's residuals (minimum at (1, 1), here at u = (0.75, 0.75) of [-1, 1.5]) and a
    problem whose unconstrained minimum lies outside the box (it stops on the bound)."""
    def to_x(u):
        return -1.0 + 2.5 * u

    def residuals(u):
        x = to_x(u)
        return np.array([10 * (x[1] - x[0] ** 2), 1 - x[0]])

    def jacobian(u):
        x = to_x(u)
        return np.array([[-20 * x[0], 10.0], [-1.0, 0.0]]) * 2.5

    u, r, _, _ = levenberg_marquardt(residuals, jacobian, np.array([0.1, 0.9]), 200)
    np.testing.assert_allclose(to_x(u), [1.0, 1.0], atol=1e-4)

    u, r, _, _ = levenberg_marquardt(lambda u: np.array([u[0] - 2.0, u[1] - 0.3]),
                                     lambda u: np.eye(2), np.array([0.5, 0.5]), 50)
    np.testing.assert_allclose(u, [1.0, 0.3], atol=1e-4)
    assert u[0] == 1.0  # held on its bound


# ---- standard errors ---------------------------------------------------------------------------
def test_standard_errors_of_undetermined_parameters_are_infinite():
    """A parameter without effect (a zero column of the Jacobian) or two that only act together
    (proportional columns) get an infinite standard error, never the 0 of a pseudo-inverse; the
    determined ones keep s^2 (J^T J)^-1, whatever the scale of their column."""
    rng = np.random.default_rng(0)
    jac = rng.normal(size=(60, 4)) * [1e6, 1.0, 1e-3, 1.0]
    r = 0.1 * rng.normal(size=60)
    expected = np.sqrt(np.diag(r @ r / 56 * np.linalg.inv(jac.T @ jac)))
    np.testing.assert_allclose(standard_errors(jac, r), expected, rtol=1e-9)

    no_effect = jac.copy()
    no_effect[:, 1] = 0.0
    sigma = standard_errors(no_effect, r)
    assert np.isinf(sigma[1]) and np.all(np.isfinite(sigma[[0, 2, 3]]))
    # the others are estimated as if the parameter were not there
    rest = no_effect[:, [0, 2, 3]]
    np.testing.assert_allclose(sigma[[0, 2, 3]], np.sqrt(np.diag(
        r @ r / 56 * np.linalg.inv(rest.T @ rest))), rtol=1e-9)

    together = jac.copy()
    together[:, 3] = -2e3 * together[:, 2]
    sigma = standard_errors(together, r)
    assert np.all(np.isinf(sigma[2:])) and np.all(np.isfinite(sigma[:2]))
    assert np.all(np.isinf(standard_errors(jac[:4], r[:4])))  # no degrees of freedom


def test_not_identified_parameters_are_listed_with_a_note():
    values = {"c10_pa": 4.8e6, "c01_pa": -1e5, "tau_s": 1e-4, "g": 0.5}
    error = {"c10_pa": 2e4, "c01_pa": 3e5, "tau_s": math.inf, "g": 0.5}
    assert identification_notes(values, error, "the tests do not determine it") == {
        "c01_pa": "c01_pa: not identified (standard error 3e+05 > value -1e+05)",
        "tau_s": "tau_s: not identified (standard error inf: the tests do not determine it)"}


# ---- decision making -------------------------------------------------------------------------
def test_decisions_on_a_known_front():
    x = np.linspace(0.0, 1.0, 41)
    front = np.column_stack([x, (1 - np.sqrt(x)) ** 2])  # symmetric, knee at x = 0.25
    knee = decide(front)
    assert front[knee.index, 0] == pytest.approx(0.25, abs=0.03)
    assert "knee" in knee.reason
    assert decide(front, "pseudo-weights", [1.0, 0.0]).index == 0  # all weight on objective 1
    assert decide(front, "pseudo-weights", [0.0, 1.0]).index == len(x) - 1
    asf = decide(front, "asf", [0.5, 0.5])
    assert front[asf.index, 0] == pytest.approx(front[asf.index, 1], abs=0.05)
    assert decide(front, "asf", [0.9, 0.1]).index < asf.index  # objective 1 matters more
    assert decide(front, "high-tradeoff").method == "high-tradeoff"
    with pytest.raises(InputError, match="--weights"):
        decide(front, "asf", [1.0])


# ---- search, checkpoint and resume ------------------------------------------------------------
def test_search_resumes_from_its_checkpoint(synthetic_test, tmp_path):
    problem = homogeneous_problem(synthetic_test)
    first = search(problem, COARSE, population=6, generations=2, seed=3, out=tmp_path)
    assert first.fe_runs == 12 and len(first.unit) == 12
    assert (tmp_path / "evaluations.parquet").exists() and (tmp_path / "evaluations.csv").exists()
    with pytest.raises(InputError, match="--resume"):
        search(problem, COARSE, population=6, generations=2, seed=3, out=tmp_path)
    other = homogeneous_problem(synthetic_test)
    other.free[0] = free_parameter(other.template, MAT + "c10_pa", 3e6, 6e6)
    with pytest.raises(InputError, match="bounds of " + MAT + "c10_pa"):
        search(other, COARSE, population=6, generations=3, seed=3, out=tmp_path, resume=True)
    with pytest.raises(InputError, match="--seed 3 \\(now 4\\)"):
        search(problem, COARSE, population=6, generations=3, seed=4, out=tmp_path, resume=True)
    more = search(problem, COARSE, population=6, generations=3, seed=3, out=tmp_path,
                  resume=True)
    assert more.fe_runs == 6  # only the new generation ran
    fewer = search(problem, COARSE, population=6, generations=1, seed=3, out=tmp_path,
                   resume=True)
    assert fewer.fe_runs == 0 and len(fewer.unit) == 6
    import pyarrow.parquet as pq  # the replay of part of the search kept the whole checkpoint

    assert pq.read_table(tmp_path / "evaluations.parquet").num_rows == 18
    np.testing.assert_array_equal(more.unit[:12], first.unit)
    np.testing.assert_array_equal(more.objectives[:12], first.objectives)
    front = more.pareto()
    assert len(front) >= 1
    f = more.objectives[front]
    for i in range(len(f)):  # no front member dominates another
        assert not np.any(np.all(f <= f[i], axis=1) & np.any(f < f[i], axis=1))


# ---- stages and the command -------------------------------------------------------------------
def test_parse_stage():
    stage = parse_stage("free=*c10_pa,*c01_pa; tests=core; objectives=nrmse,contact_time", 0)
    assert stage == Stage("stage1", ("*c10_pa", "*c01_pa"), ("core",), ("nrmse", "contact_time"))
    with pytest.raises(InputError, match="KEY=VALUE"):
        parse_stage("c10", 0)


def test_staged_calibration_freezes_earlier_stages(synthetic_test):
    """The thesis' split: hyperelastic constants on the force curve, then the Prony term on COR;
    the second stage starts from the first's result."""
    bounds = {MAT + "c10_pa": (3e6, 7e6), MAT + "prony.0.g": (0.3, 0.9)}
    result = calibrate(universal(START), [synthetic_test], bounds, COARSE, method="gradient",
                       stages=[Stage("hyperelastic", ("*c10_pa",), None, ("nrmse",)),
                               Stage("prony", ("*prony.0.g",), None, ("cor",))],
                       max_evaluations=12, verbose=False)
    first, second = result["stages"]
    assert list(first["chosen"]["parameters"]) == [MAT + "c10_pa"]
    assert list(second["chosen"]["parameters"]) == [MAT + "prony.0.g"]
    ball = result["ball"]
    assert get_value(ball, MAT + "c10_pa") == pytest.approx(first["chosen"]["parameters"][
        MAT + "c10_pa"])
    assert second["chosen"]["objectives"]["cor"] < 0.01
    assert result["evaluations"] > 0


def test_cli_calibrate_end_to_end(synthetic_test, tmp_path, capsys):
    fe = simulate(load_ball(universal(TRUTH)), 20.0, COARSE)
    record = fe.record()
    csv = tmp_path / "ball.csv"
    np.savetxt(csv, np.column_stack([record.time_s, record.force_n]), delimiter=",",
               header="time_s,force_n", comments="")
    (tmp_path / "ball.json").write_text(json.dumps({"impact_speed_m_s": 20.0,
                                                    "rebound_speed_m_s": fe.rebound_speed_m_s,
                                                    "mass_kg": fe.mass_kg}))
    template = tmp_path / "template.json"
    template.write_text(json.dumps(universal(START)))
    out = tmp_path / "out"
    code = main(["calibrate", "--ball", str(template), "--test", str(csv),
                 "--free", "layers.ball.material.c10_pa=3e6:7e6",
                 "--free", "layers.ball.material.prony.0.g=0.3:0.9",
                 "--element-size-m", "4e-3", "--method", "nsga2+gradient", "--population", "6",
                 "--generations", "2", "--max-evaluations", "10", "--out", str(out), "--json"])
    assert code == 0
    result = json.loads(capsys.readouterr().out)
    for key in ("chosen", "pareto", "evaluations", "wall_time_s", "ball", "stages"):
        assert key in result
    assert result["pareto"] and result["evaluations"] > 12
    refinement = result["stages"][0]["refinement"]
    assert refinement["misfit"] < refinement["start_misfit"]  # from the chosen design
    # both constants shape the pulse: finite standard errors, well below their values
    assert refinement["not_identified"] == [] and result["not_identified"] == []
    for path, se in refinement["standard_error"].items():
        assert 0 < se < 0.1 * abs(refinement["values"][path]), path
    assert result["chosen"]["objectives"]["nrmse"] < 0.05  # c01, tau1 stay off the truth
    ball = load_ball(out / "calibrated-ball.json")
    assert ball.layers[0].material.prony[0].g == pytest.approx(
        result["chosen"]["parameters"]["layers.ball.material.prony.0.g"])
    for name in ("pareto.png", "convergence.png", "pulses.png", "evaluations.parquet",
                 "pareto.csv"):
        assert (out / "calibration" / name).exists(), name
