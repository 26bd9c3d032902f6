"""Similarity of homogeneous universal balls (docs/universal.md, "Any solid ball"): a ball scaled
in size, density, moduli and tau1 by the dimensionless groups gives the same dimensionless pulse,
and a test of any size maps onto the model's reference ball exactly."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from ballimpact.errors import InputError
from ballimpact.records.features import extract_features
from ballimpact.fe import SolverOptions, load_ball, simulate
from ballimpact.balls.ball import universal_spec
from ballimpact.universal.similarity import (BallSize, check_size, groups, map_features,
                                             map_params)

PARAMS = {"c10_pa": 5.0e6, "c01_pa": -0.4e6, "g1": 0.5, "tau1_s": 4e-5}
REFERENCE = BallSize(0.036, 0.16)


def _run(params, size: BallSize, speed_m_s: float):
    """FE run (float64) of a universal ball of `size` on a mesh of R / 12 elements."""
    spec = universal_spec(params, size.radius_m, size.density_kg_m3, "long_term", "similar")
    ball = load_ball(spec, allow={"ball-units"})
    return simulate(ball, speed_m_s, SolverOptions(element_size_m=size.radius_m / 12,
                                                   precision="float64"))


@pytest.fixture(scope="module")
def pair():
    """The reference ball at 25 m/s, and a ball 0.6x its size, 1.4x its density, 2.5x its
    moduli at the speed and tau1 that keep rho v^2 / mu0 and tau1 v / R."""
    scaled = BallSize(0.6 * REFERENCE.radius_m, 0.6 ** 3 * 1.4 * REFERENCE.mass_kg)
    speed = 25.0 * math.sqrt(2.5 / 1.4)
    params = {"c10_pa": 2.5 * PARAMS["c10_pa"], "c01_pa": 2.5 * PARAMS["c01_pa"],
              "g1": PARAMS["g1"], "tau1_s": PARAMS["tau1_s"] * 0.6 * 25.0 / speed}
    return ((_run(PARAMS, REFERENCE, 25.0), REFERENCE, 25.0, PARAMS),
            (_run(params, scaled, speed), scaled, speed, params))


def test_scaled_ball_has_the_same_groups(pair):
    (_, size_a, v_a, p_a), (_, size_b, v_b, p_b) = pair
    ga, gb = groups(p_a, size_a, v_a), groups(p_b, size_b, v_b)
    assert gb == pytest.approx(ga, rel=1e-12)


def test_dimensionless_pulses_equal_to_1e_6(pair):
    (a, size_a, v_a, _), (b, size_b, v_b, _) = pair
    assert a.steps == b.steps
    ha, hb = a.history, b.history
    t_a = ha["time_s"] * v_a / size_a.radius_m
    t_b = hb["time_s"] * v_b / size_b.radius_m
    f_a = ha["contact_force_n"] / size_a.scale("force", v_a)
    f_b = hb["contact_force_n"] / size_b.scale("force", v_b)
    assert np.max(np.abs(t_a - t_b)) <= 1e-6 * t_a[-1]
    assert np.max(np.abs(f_a - f_b)) <= 1e-6 * f_a.max()
    assert abs(a.cor - b.cor) <= 1e-6


def test_features_map_onto_the_reference_ball(pair):
    """The scaled ball's features, mapped to the reference ball at the same speed, equal those of
    the reference ball run at that speed with the mapped constants."""
    _, (b, size_b, v_b, p_b) = pair
    mapped_params = map_params(p_b, size_b, REFERENCE)
    reference_run = _run(mapped_params, REFERENCE, v_b)
    want = extract_features(reference_run.record()).values
    got = map_features(extract_features(b.record()).values, size_b, REFERENCE)
    for key in want:
        assert got[key] == pytest.approx(want[key], rel=1e-6, abs=1e-9), key
    back = map_params(mapped_params, REFERENCE, size_b)
    assert back == pytest.approx(p_b, rel=1e-12)
    assert groups(mapped_params, REFERENCE, v_b) == pytest.approx(groups(p_b, size_b, v_b),
                                                                  rel=1e-12)


@pytest.mark.parametrize("diameter, mass, words", [
    (72.0, 0.16, "looks like millimetres; use 0.072"),
    (0.072, 160.0, "looks like grams given as kg (use 0.16)"),
    (0.0, 0.16, "positive diameter"),
    (0.5, 0.16, "outside 0.01..0.4 m"),
])
def test_implausible_sizes_are_named(diameter, mass, words):
    with pytest.raises(InputError, match=re.escape(words)):
        check_size(diameter, mass)


def test_a_density_no_ball_has_fails_the_ball_units_check():
    with pytest.raises(InputError, match="density"):
        check_size(0.3, 0.01)  # 0.7 kg/m^3
