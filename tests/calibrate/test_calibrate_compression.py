"""Compression tests in `ballimpact calibrate` (`calibrate.compression`): a synthetic
force-deflection curve of a known Mooney-Rivlin core (the FE curve of the truth, written in mm
and kN) calibrated back by the gradient method (finite-difference Levenberg-Marquardt) and by a
small NSGA-II run; the objective against a closed form; stages; and every bad input (exit 2,
one line).

A two-layer ball (core + cover) is the template; the compression test is of the core alone
(`:core`), so the cover's constants cannot matter to it. Mesh 3 mm (210 core elements), 6
increments to 3 mm: a curve takes ~0.1 s once compiled."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

from ballimpact.calibrate import compression as comp
from ballimpact.calibrate.calibration import Stage, calibrate
from ballimpact.calibrate.problem import CalibrationProblem, free_parameter
from ballimpact.cli import main
from ballimpact.fe import SolverOptions, compress, load_ball

OPTIONS = SolverOptions(element_size_m=3e-3)
CORE_RADIUS_M, BALL_RADIUS_M = 0.026, 0.036
TRUE_C10_PA, C01_PA, TEMPLATE_C10_PA = 4.0e6, -1.0e6, 3.0e6
DEFLECTION_M, STEPS = 3e-3, 6
C10 = "layers.core.material.c10_pa"
BOUNDS = (2.0e6, 6.0e6)


def ball_spec(c10_pa=TEMPLATE_C10_PA):
    return {"name": "two-layer", "layers": [
        {"name": "core", "outer_radius_m": CORE_RADIUS_M, "density_kg_m3": 1000.0,
         "material": {"model": "mooney_rivlin", "c10_pa": c10_pa, "c01_pa": C01_PA,
                      "d1_per_pa": 1e-8}},
        {"name": "cover", "outer_radius_m": BALL_RADIUS_M, "density_kg_m3": 1100.0,
         "material": {"model": "mooney_rivlin", "c10_pa": 6e6, "c01_pa": -1.5e6,
                      "d1_per_pa": 1e-8}}]}


@pytest.fixture(scope="module")
def truth_curve():
    """The truth's core curve (the core alone between the platens)."""
    core = load_ball({**ball_spec(TRUE_C10_PA), "layers": ball_spec(TRUE_C10_PA)["layers"][:1]})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return compress(core, DEFLECTION_M, steps=STEPS, options=OPTIONS)


@pytest.fixture(scope="module")
def files(tmp_path_factory, truth_curve):
    """The template ball file and the truth's curve as CSV in mm and kN (with a comment)."""
    folder = tmp_path_factory.mktemp("calibrate-compression")
    ball = folder / "ball.json"
    ball.write_text(json.dumps(ball_spec()))
    csv = folder / "core.csv"
    rows = [f"{float(d) * 1e3!r},{float(f) * 1e-3!r}" for d, f in
            zip(truth_curve.deflection_m[1:], truth_curve.force_n[1:])]
    csv.write_text("# synthetic: C10 4 MPa core\ndeflection_mm,force_kn\n" + "\n".join(rows)
                   + "\n")
    return {"folder": folder, "ball": ball, "csv": csv}


def core_test(files, **extra):
    d, f = comp.read_compression_csv(files["csv"])
    return comp.CompressionTest("core", d, f, "core", steps=STEPS, **extra)


def argv(files, *extra, csv=None):
    return ["calibrate", "--ball", files["ball"], "--compression", f"{csv or files['csv']}:core",
            "--free", f"{C10}={BOUNDS[0]:g}:{BOUNDS[1]:g}", "--element-size-m", "3e-3",
            "--compression-steps", str(STEPS), *extra]


# ---- reading and the objective -----------------------------------------------------------------

def test_csv_units_to_si(files, truth_curve):
    d, f = comp.read_compression_csv(files["csv"])
    # mm -> m and kN -> N; the repr'd numbers round-trip exactly up to the unit factors
    np.testing.assert_allclose(d, truth_curve.deflection_m[1:], rtol=1e-14)
    np.testing.assert_allclose(f, truth_curve.force_n[1:], rtol=1e-14)


def test_objective_is_the_force_nrmse(files, truth_curve):
    """compression_nrmse against the formula computed here: a model curve 3% high everywhere
    has NRMSE = 0.03 sqrt(mean F_k^2) / max F_k; the truth's own curve 0 (round-off)."""
    test = core_test(files)
    assert comp.compare_compression(test, truth_curve)["compression_nrmse"] < 1e-12

    class Scaled:  # the truth's curve times 1.03
        deflection_m, force_n = truth_curve.deflection_m, 1.03 * truth_curve.force_n

        def force_at(self, d):
            return np.interp(d, self.deflection_m, self.force_n)

    expected = 0.03 * math.sqrt(np.mean(test.force_n ** 2)) / test.force_n.max()
    got = comp.compare_compression(test, Scaled())
    assert got["compression_nrmse"] == pytest.approx(expected, rel=1e-12)
    assert got["end_force_relative_error"] == pytest.approx(0.03, rel=1e-12)


# ---- the calibration recovers C10 --------------------------------------------------------------

def test_gradient_recovers_c10(files):
    """Levenberg-Marquardt with the central-difference Jacobian from C10 = 3 MPa back to 4 MPa
    within 1% (the data are the same mesh's curve: the misfit is 0 at the truth); a standard
    error is reported (finite, well below the value)."""
    spec = ball_spec()
    problem = CalibrationProblem(spec, [core_test(files)],
                                 [free_parameter(spec, C10, *BOUNDS)], ("compression",))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = calibrate(spec, problem.tests, {C10: BOUNDS}, OPTIONS, method="gradient",
                           max_evaluations=12, verbose=False)
    c10 = result["chosen"]["parameters"][C10]
    assert abs(c10 / TRUE_C10_PA - 1.0) < 0.01, c10
    assert result["chosen"]["objectives"]["compression"] < 0.01
    refinement = result["stages"][0]["refinement"]
    error = refinement["standard_error"][C10]
    assert math.isfinite(error) and 0.0 <= error < 0.05 * c10
    assert refinement["jacobian"] == "central differences"
    assert result["not_identified"] == []
    assert list(result["stages"][0]["objectives"]) == ["compression"]  # the default


def test_nsga2_recovers_c10(files):
    """A small NSGA-II run (8 designs x 4 generations, one compression solve each) lands
    within 3% of the truth."""
    spec = ball_spec()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = calibrate(spec, [core_test(files)], {C10: BOUNDS}, OPTIONS, method="nsga2",
                           population=8, generations=4, seed=1, verbose=False)
    c10 = result["chosen"]["parameters"][C10]
    assert abs(c10 / TRUE_C10_PA - 1.0) < 0.03, c10
    assert result["evaluations"] >= 8


def test_cli_gradient(files, capsys, tmp_path):
    """The command end to end: the printed value and its standard error, the JSON and the
    files of --out."""
    out = tmp_path / "cal"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        code = main([str(a) for a in argv(files, "--method", "gradient", "--max-evaluations",
                                          "10", "--out", out, "--json")])
    assert code == 0
    result = json.loads(capsys.readouterr().out)
    assert abs(result["chosen"]["parameters"][C10] / TRUE_C10_PA - 1.0) < 0.01
    assert result["chosen"]["per_test"][0]["test"] == "core"
    saved = json.loads((out / "calibrated-ball.json").read_text())
    assert saved["layers"][0]["material"]["c10_pa"] == pytest.approx(
        result["chosen"]["parameters"][C10])
    assert (out / "calibration" / "pulses.png").exists()


# ---- bad input ---------------------------------------------------------------------------------

def write(folder, name, text):
    path = folder / name
    path.write_text(text)
    return path


CSV_CASES = [
    ("nan.csv", "deflection_mm,force_kn\n0.5,0.1\n1,nan\n1.5,0.5\n",
     ["nan.csv: line 3", "force_kn", "not a finite number"]),
    ("word.csv", "deflection_mm,force_kn\n0.5,0.1\n1,abc\n1.5,0.5\n",
     ["word.csv: line 3", "'abc' is not a number"]),
    ("back.csv", "# a comment\ndeflection_mm,force_kn\n0.5,0.1\n1.5,0.3\n1.0,0.5\n",
     ["back.csv: line 5", "does not increase"]),
    ("negative.csv", "deflection_m,force_n\n-0.001,1\n0.001,2\n0.002,5\n",
     ["negative.csv: line 2", "is negative"]),
    ("short.csv", "deflection_m,force_n\n0.001,1\n0.002,5\n",
     ["short.csv", "2 rows", "at least 3"]),
    ("nounit.csv", "deflection,force_n\n0.001,1\n0.002,5\n0.003,9\n",
     ["nounit.csv: line 1", "unknown column 'deflection'", "deflection_mm"]),
    ("noforce.csv", "deflection_m\n0.001\n0.002\n0.003\n",
     ["noforce.csv: line 1", "no force column", "force_kn"]),
    # millimetres in a metres column: 3 m on a 52 mm core
    ("mm.csv", "deflection_m,force_n\n1,100\n2,300\n3,600\n",
     ["mm.csv", "3 m is not below the diameter 0.052 m of layer core",
      "millimetres given as metres", "deflection_mm"]),
    ("deep.csv", "deflection_m,force_n\n0.01,100\n0.02,300\n0.03,600\n",
     ["deep.csv", "above the radius 0.026 m of layer core", "allowed (0, 0.026]"]),
    # kilonewtons under a newton header: the core's ~0.6 kN at 4 mm typed as 0.61
    ("kn.csv", "deflection_mm,force_n\n1,0.08\n2,0.22\n4,0.61\n",
     ["kn.csv", "force at the largest deflection", "looks like kN", "use 610 N"]),
]


@pytest.mark.parametrize("name, text, fragments", CSV_CASES, ids=[c[0] for c in CSV_CASES])
def test_bad_csv(bad_input, files, tmp_path, name, text, fragments):
    bad_input(argv(files, csv=write(tmp_path, name, text)), *fragments)


def test_bad_options(bad_input, files, tmp_path):
    bad_input(argv(files, csv=tmp_path / "missing.csv"), "missing.csv: no such file")
    bad_input(argv(files, "--compression-rate-m-s", "-1"), "--compression-rate-m-s = -1",
              "allowed range (0, inf) m/s")
    bad_input(argv(files, "--compression-rate-m-s", "500"), "rate_m_s = 500",
              "mm/s given as m/s")
    bad_input(["calibrate", "--ball", files["ball"], "--free", f"{C10}=2e6:6e6"],
              "--test or --compression")
    # impact objectives on a stage of compression tests only
    bad_input(argv(files, "--objectives", "nrmse,cor"), "objective nrmse applies to impact "
              "tests only", "core (compression)", "objectives=compression")
    bad_input(argv(files, "--stage", "name=core;tests=core;objectives=contact_time"),
              "--stage core", "contact_time applies to impact tests only")
    bad_input(["calibrate", "--ball", files["ball"], "--compression",
                                           f"{files['csv']}:pith", "--free", f"{C10}=2e6:6e6"],
              "--compression", "no such layer")


def test_objectives_apply_to_their_tests():
    """The rule itself: compression to compression tests, the others to impact tests, and the
    defaults by the kinds of test present."""
    from ballimpact.calibrate.problem import CalibrationTest, applies, default_objectives

    def Impact():
        return CalibrationTest("ball", object())

    core = comp.CompressionTest("core", np.array([1e-3, 2e-3, 3e-3]), np.array([1., 3., 6.]))
    assert applies("compression", core) and not applies("nrmse", core)
    assert applies("nrmse", Impact()) and not applies("compression", Impact())
    assert default_objectives([core]) == ("compression",)
    assert default_objectives([Impact()]) == ("nrmse", "cor", "contact_time")
    assert default_objectives([Impact(), core]) == ("nrmse", "cor", "contact_time",
                                                    "compression")


def test_problem_defaults_to_its_tests_objectives(files):
    """A library `CalibrationProblem` of compression tests alone, without objectives given,
    takes theirs (it took the impact objectives and was refused)."""
    spec = ball_spec()
    problem = CalibrationProblem(spec, [core_test(files)], [free_parameter(spec, C10, *BOUNDS)])
    assert problem.objectives == ("compression",)


def test_mixed_gradient_stage_refused(files, tmp_path, half_sine_record):
    """A gradient stage over a compression and an impact test is refused before any run."""
    from ballimpact.errors import InputError

    record = half_sine_record(tmp_path, contact_s=5e-4)
    code = main(["calibrate", "--ball", str(files["ball"]), "--test", str(record),
                 "--compression", f"{files['csv']}:core", "--free", f"{C10}=2e6:6e6",
                 "--method", "gradient"])
    assert code == 2
    with pytest.raises(InputError, match="separate stages"):
        calibrate(ball_spec(), [core_test(files), _impact(record)], {C10: BOUNDS}, OPTIONS,
                  method="gradient", stages=[Stage("both")], verbose=False)


def _impact(record):
    from ballimpact.calibrate.problem import CalibrationTest
    from ballimpact.records.pipeline import process
    from ballimpact.records.loaders import load_record

    return CalibrationTest("ball", process(load_record(record)).features)
