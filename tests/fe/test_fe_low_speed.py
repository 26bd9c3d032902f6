"""Slow impacts, the textbook Hertz case (issue 24): a homogeneous linear-elastic ball at 0.1,
0.3 and 1 m/s against the Hertz closed form (`closedform.hertz_impact`), and the warning when
the contact patch is narrower than the mesh resolves (`fe.engine.contact_resolution_note`)."""

import math
import warnings

import pytest

from ballimpact.errors import InputWarning
from ballimpact.fe import SolverOptions, load_ball, simulate
from ballimpact.fe import engine
from ballimpact.fe.estimates import hertz_contact_radius_m
from ballimpact.closedform import hertz_impact

E_PA, NU, RADIUS_M, DENSITY = 1.0e7, 0.3, 0.036, 1000.0
#: Saint Venant-Kirchhoff: linear at the small strains of a slow impact (stretches 0.97-1.02)
BALL = {"name": "hertz", "layers": [{"outer_radius_m": RADIUS_M, "density_kg_m3": DENSITY,
                                     "material": {"model": "linear_elastic",
                                                  "youngs_modulus_pa": E_PA,
                                                  "poissons_ratio": NU}}]}
#: a coarse 3 mm mesh (720 elements) refined to 0.5 mm at the pole: the contact patch spans 5.9
#: pole elements at 0.1 m/s (on the default 1.5 mm mesh, unrefined, 1.95: the contact time then
#: reads 4.9% long, docs/fe.md)
REFINED = SolverOptions(element_size_m=3e-3, pole_element_size_m=5e-4)
SPEEDS = (0.1, 0.3, 1.0)
#: measured: peak force -0.5%, +0.4%, +2.1% and contact time +1.6%, +0.2%, -0.9% at 0.1, 0.3,
#: 1 m/s (the force's error grows with the contact radius over the ball's, 0.08 to 0.2, where
#: Hertz's half-space assumption weakens; 1.5 mm refined to 0.5 mm gives the same within 0.4%)
FORCE_TOLERANCE, TIME_TOLERANCE = 0.04, 0.03


@pytest.fixture(scope="module")
def runs():
    ball = load_ball(BALL)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        results = [simulate(ball, speed, REFINED) for speed in SPEEDS]
    return results, [str(w.message) for w in caught]


@pytest.mark.parametrize("index", range(len(SPEEDS)))
def test_slow_impacts_follow_hertz(runs, index):
    results, _ = runs
    result, speed = results[index], SPEEDS[index]
    _, peak_n, contact_s = hertz_impact(E_PA, NU, RADIUS_M, result.mass_kg, speed)
    assert result.peak_force_n == pytest.approx(peak_n, rel=FORCE_TOLERANCE)
    assert result.contact_time_s == pytest.approx(contact_s, rel=TIME_TOLERANCE)
    assert result.cor > 0.99  # elastic: only the bulk viscosity takes a little
    assert result.energy_balance_error < 1e-4


def test_contact_time_grows_as_hertz_says(runs):
    """t_c ~ v^(-1/5): from 1 to 0.1 m/s the contact lengthens by 10^0.2 = 1.585."""
    results, _ = runs
    ratio = results[0].contact_time_s / results[2].contact_time_s
    assert ratio == pytest.approx(10 ** 0.2, rel=0.03)


def test_resolved_runs_do_not_warn(runs):
    _, messages = runs
    assert not [m for m in messages if m.startswith("contact not resolved")], messages


def test_unresolved_contact_warns_before_meshing(monkeypatch):
    """At 0.01 m/s the patch (Hertz radius ~1.2 mm) spans 0.8 of the default 1.5 mm elements."""
    ball = load_ball(BALL)
    assert hertz_contact_radius_m(ball, 0.01) < 2 * 1.5e-3
    note = engine.contact_resolution_note(ball, 0.01, 1.5e-3)
    assert note.startswith("contact not resolved: at 0.01 m/s") and "pole_element_size_m" in note
    assert engine.contact_resolution_note(ball, 0.1, 5e-4) is None

    def refuse(*args, **kwargs):
        raise RuntimeError("meshed")
    monkeypatch.setattr(engine, "kernel_for", refuse)
    with pytest.warns(InputWarning, match="^contact not resolved"), \
            pytest.raises(RuntimeError, match="meshed"):
        simulate(ball, 0.01)


def test_contact_radius_is_the_hertz_one():
    """A homogeneous linear ball: the estimate is exactly Hertz's sqrt(R y_max)."""
    ball = load_ball(BALL)
    y_max = hertz_impact(E_PA, NU, RADIUS_M, ball.mass_kg, 0.3)[0]
    assert hertz_contact_radius_m(ball, 0.3) == pytest.approx(math.sqrt(RADIUS_M * y_max))
