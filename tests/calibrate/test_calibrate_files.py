"""`calibrate.files` (the library side of `ballimpact calibrate`'s tests and outputs), called
from Python."""

import json
import math

import numpy as np
import pytest

from ballimpact.calibrate.compression import CompressionTest
from ballimpact.calibrate.files import calibration_tests, write_results
from ballimpact.calibrate.problem import CalibrationTest
from ballimpact.errors import InputError


class _Features:
    values = {"P15": 20.0}


def _curve(folder, name):
    path = folder / f"{name}.csv"
    path.write_text("# platen test\ndeflection_mm,force_n\n0,0\n1,150\n2,420\n")
    return path


def test_tests_are_named_by_stem_and_the_curves_read_in_si(tmp_path):
    (tmp_path / "b").mkdir()
    features = _Features()
    tests = calibration_tests(
        [(tmp_path / "ball.csv", features, None), (tmp_path / "b" / "ball.csv", features, "core")],
        [(_curve(tmp_path, "ball"), None), (_curve(tmp_path, "core"), "core")],
        compression_rate_m_s=0.01, compression_steps=5)
    assert [type(t) for t in tests] == [CalibrationTest] * 2 + [CompressionTest] * 2
    assert [t.name for t in tests] == ["ball", "ball-1", "ball-2", "core"]
    assert tests[1].layers == "core" and tests[0].impact_speed_m_s == 20.0
    curve = tests[2]
    assert curve.deflection_m == pytest.approx(np.array([0.0, 1e-3, 2e-3]))
    assert curve.force_n == pytest.approx(np.array([0.0, 150.0, 420.0]))
    assert (curve.rate_m_s, curve.steps, curve.layers) == (0.01, 5, None)
    assert tests[3].layers == "core" and tests[3].source == str(tmp_path / "core.csv")


@pytest.mark.parametrize("options, message", [
    ({"compression_rate_m_s": -1.0},
     r"--compression-rate-m-s = -1: allowed range \(0, inf\) m/s \(the platen speed"),
    ({"compression_rate_m_s": math.inf}, "--compression-rate-m-s = inf"),
    ({"compression_steps": 0}, r"--compression-steps = 0: allowed range \[1, inf\)$"),
])
def test_bad_compression_options(tmp_path, options, message):
    with pytest.raises(InputError, match=message):
        calibration_tests([], [(_curve(tmp_path, "c"), None)], **options)


def test_results_written_to_the_folder(tmp_path):
    result = {"ball": {"name": "b-calibrated", "layers": []}, "evaluations": 3,
              "wall_time_s": math.nan}
    write_results(tmp_path, result)
    assert result["ball_file"] == str(tmp_path / "calibrated-ball.json")
    assert json.loads((tmp_path / "calibrated-ball.json").read_text()) == result["ball"]
    saved = json.loads((tmp_path / "calibration.json").read_text())
    assert saved["evaluations"] == 3 and saved["wall_time_s"] is None  # NaN: null in JSON
    assert saved["ball_file"] == result["ball_file"]
