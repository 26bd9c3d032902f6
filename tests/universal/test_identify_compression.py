"""A compression test beside an impact (issue 42, item 4): `identify --compression` squeezes the
identified homogeneous ball as the ball was squeezed and judges its curve; a one-layer
calibration against both kinds of test that misses says so. Both name the layered path. (The
whole path, with the layered calibration, is `examples/layered_from_tests.py`, asserted in
tests/calibrate/test_calibrate_slow.py.)"""

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

from ballimpact.calibrate.compression import CompressionTest
from ballimpact.calibrate.files import warn_one_layer
from ballimpact.errors import InputWarning
from ballimpact.universal.compression_check import LAYERED_PATH, judge_compression
from ballimpact.verdict import COMPRESSION_TOLERANCE, Tolerances, judge


def _verdict() -> dict:
    """A passing impact verdict to add the compression criterion to."""
    comparison = {"force_nrmse": 0.01, "cor_error": 0.0, "contact_time_relative_error": 0.0,
                  "peak_force_relative_error": 0.0}
    return judge(comparison, Tolerances())


@pytest.fixture(scope="module")
def ball_and_curve():
    """The cricket-universal ball and its own long-term curve to 3 mm in 5 increments, on the
    mesh `identify`'s check uses (`fe.compress`'s default)."""
    from ballimpact.fe import compress, load_ball

    spec = load_ball("cricket-universal", impact_speed_m_s=20.0).to_dict()
    curve = compress(load_ball(spec), 0.003, steps=5)
    return spec, curve


def test_the_balls_own_curve_passes(ball_and_curve):
    spec, curve = ball_and_curve
    test = CompressionTest("own", curve.deflection_m[1:], curve.force_n[1:], steps=5)
    check = judge_compression(_verdict(), spec, test)
    assert check["passed"] and check["criteria"]["compression"]["passed"]
    assert check["compression"]["compression_nrmse"] < 1e-9
    assert check["tolerances"]["compression"] == COMPRESSION_TOLERANCE


def test_a_stiffer_ball_misses_and_names_the_layered_path(ball_and_curve):
    spec, curve = ball_and_curve
    force = 1.25 * curve.force_n[1:]  # the measured ball is 25% stiffer when squeezed slowly
    test = CompressionTest("stiff", curve.deflection_m[1:], force, steps=5, source="stiff.csv")
    check = judge_compression(_verdict(), spec, test)
    own = curve.force_n[1:]
    expected = 0.2 * math.sqrt(np.mean(own ** 2)) / own.max()  # (F - 1.25 F) / (1.25 max F)
    assert check["compression"]["compression_nrmse"] == pytest.approx(expected, rel=1e-9)
    assert check["compression"]["end_force_relative_error"] == pytest.approx(-0.2, rel=1e-9)
    assert not check["passed"] and not check["criteria"]["compression"]["passed"]
    (words,) = check["missed"]
    assert "one homogeneous layer" in words and LAYERED_PATH in words
    assert "--max-compression-error" in words and "-20.0%" in words
    # a looser tolerance lets it pass
    assert judge_compression(_verdict(), spec, test, tolerance=0.2)["passed"]


# ---- the one-layer calibration's warning --------------------------------------------------------
IMPACT, SQUEEZE = SimpleNamespace(kind="impact"), SimpleNamespace(kind="compression")
ONE, TWO = {"layers": [{}]}, {"layers": [{}, {}]}


def _result(impact: dict, compression: float) -> dict:
    return {"stages": [{"chosen": {"objectives": {"compression": compression}}},
                       {"chosen": {"objectives": impact}}]}


def _warnings(template, tests, result) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warn_one_layer(template, tests, result)
    return [str(w.message) for w in caught if issubclass(w.category, InputWarning)]


def test_one_layer_missing_the_impact_says_so():
    result = _result({"nrmse": 0.048, "cor": 0.009, "contact_time": 0.077}, 0.031)
    (words,) = _warnings(ONE, [IMPACT, SQUEEZE], result)
    assert "one homogeneous layer" in words and "Layered balls from tests" in words
    assert "contact_time 0.077 > 0.04" in words and "nrmse" not in words


def test_one_layer_missing_the_compression_says_so():
    result = _result({"nrmse": 0.01, "cor": 0.001, "contact_time": 0.005}, 0.08)
    (words,) = _warnings(ONE, [IMPACT, SQUEEZE], result)
    assert "compression 0.08 > 0.05" in words


@pytest.mark.parametrize("template, tests, impact", [
    (TWO, [IMPACT, SQUEEZE], {"contact_time": 0.077}),    # already layered
    (ONE, [IMPACT], {"contact_time": 0.077}),             # no compression test: nothing to tie
    (ONE, [IMPACT, SQUEEZE], {"nrmse": 0.01, "contact_time": 0.01}),  # both matched
])
def test_no_warning_where_one_layer_is_not_in_question(template, tests, impact):
    assert _warnings(template, tests, _result(impact, 0.01)) == []
