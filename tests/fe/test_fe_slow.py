"""Longer FE checks (pytest -m slow): mesh and penalty convergence of the universal ball at 25 m/s."""

import pytest

from ballimpact.balls.ball import load_ball
from ballimpact.fe import SolverOptions, simulate

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def universal_25():
    ball = load_ball("cricket-universal", impact_speed_m_s=25.0)
    default = SolverOptions()
    return ball, default, simulate(ball, 25.0, default)


def test_mesh_convergence_universal_25(universal_25):
    ball, default, coarse = universal_25
    fine = simulate(ball, 25.0, SolverOptions(element_size_m=default.element_size_m / 2))
    assert fine.peak_force_n == pytest.approx(coarse.peak_force_n, rel=0.02)
    assert fine.contact_time_s == pytest.approx(coarse.contact_time_s, rel=0.02)


def test_penalty_convergence_universal_25(universal_25):
    ball, default, base = universal_25
    stiff = simulate(ball, 25.0, SolverOptions(penalty_scale=2 * default.penalty_scale))
    assert stiff.peak_force_n == pytest.approx(base.peak_force_n, rel=0.02)
    assert stiff.contact_time_s == pytest.approx(base.contact_time_s, rel=0.02)
