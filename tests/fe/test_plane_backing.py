"""The axisymmetric ball on a moving plane (`fe.backing.PlaneBacking`; docs/equipment.md, "A
backed plane"): the fixed-plane limit, momentum and energy, the backing's acceleration, bad
input."""

import math

import numpy as np
import pytest

from ballimpact import fe
from ballimpact.errors import InputError
from ballimpact.fe.backing import PlaneBacking
from ballimpact.fe.hex.target import load_target

SPEED = 19.0  # m/s: McIntosh & Janda's (2003) slowest helmet test


@pytest.fixture(scope="module")
def ball():
    return fe.load_ball("cricket-men", impact_speed_m_s=SPEED)


@pytest.fixture(scope="module")
def fixed(ball):
    return fe.simulate(ball, SPEED)


def _backing_velocity(result) -> float:
    return float(result.history["backing_velocity_z_m_s"][-1])


def test_a_huge_free_mass_is_the_fixed_plane(ball, fixed):
    huge = PlaneBacking((1e6 ** -0.5,), (0.0,), ((0.0,),))
    run = fe.simulate(ball, SPEED, target=huge)
    assert run.cor == pytest.approx(fixed.cor, rel=1e-5)
    assert run.peak_force_n == pytest.approx(fixed.peak_force_n, rel=1e-5)
    assert run.contact_time_s == pytest.approx(fixed.contact_time_s, rel=1e-5)
    assert run.target == "backing" and fixed.target == "rigid plane"
    assert "backing_z_m" not in fixed.history  # the fixed plane's histories are as before


@pytest.mark.parametrize("mass_kg", [1.0, 5.0])
def test_a_free_mass_conserves_momentum_and_takes_the_force(ball, mass_kg):
    run = fe.simulate(ball, SPEED, target=PlaneBacking.free_mass(mass_kg))
    h, m = run.history, run.mass_kg
    momentum = m * h["centre_velocity_z_m_s"] + mass_kg * h["backing_velocity_z_m_s"]
    assert np.max(np.abs(momentum / (-m * SPEED) - 1.0)) < 1e-9
    # the backing's speed m (1 + e) v / (m + M), e the relative COR of this collision
    backing_speed = -_backing_velocity(run)
    e = run.cor + backing_speed / SPEED
    assert backing_speed == pytest.approx(m * (1 + e) * SPEED / (m + mass_kg), rel=1e-9)
    # a free rigid backing's acceleration is the contact force over its mass, sample by sample
    assert np.allclose(-h["backing_acceleration_z_m_s2"] * mass_kg, h["contact_force_n"],
                       rtol=1e-9, atol=1e-9 * run.peak_force_n)
    e_ = run.energies_j
    assert abs(e_["backing_balance_error"]) < 1e-6
    assert abs(run.energy_balance_error) < 1e-3
    assert e_["backing_energy_j"] == pytest.approx(0.5 * mass_kg * backing_speed ** 2, rel=1e-6)
    assert e_["contact_dissipation_j"] >= 0.0
    # a lighter backing takes more of the ball's momentum: the ball rebounds slower
    assert run.cor < 0.56


def test_a_neck_spring_and_damper_hold_the_backing(ball):
    mass, k, c = 5.0, 2e4, 50.0
    run = fe.simulate(ball, SPEED, target=PlaneBacking.free_mass(mass, k, c))
    h = run.history
    z, v, a = (h[f"backing_{q}"] for q in ("z_m", "velocity_z_m_s", "acceleration_z_m_s2"))
    # the backing's equation at every step: M a = -F - c v - k z (v at the half step: 1e-3)
    residual = mass * a + h["contact_force_n"] + k * z + c * v
    assert np.max(np.abs(residual)) < 1e-3 * run.peak_force_n
    en = run.energies_j
    assert en["backing_damping_j"] > 0.0
    assert abs(en["backing_balance_error"]) < 1e-6


def test_bad_backings_are_refused(ball):
    with pytest.raises(InputError, match=r"mass_kg = 4500.*grams"):
        PlaneBacking.free_mass(4500.0)
    with pytest.raises(InputError, match="spring_n_m"):
        PlaneBacking.free_mass(5.0, spring_n_m=-1.0)
    with pytest.raises(InputError, match="damping_1_s.*2 x 2"):
        PlaneBacking((1.0, 1.0), (0.0, 10.0), ((0.0,),))
    with pytest.raises(InputError, match="frequencies_hz.*allowed range"):
        PlaneBacking((1.0,), (2e5,), ((0.0,),))
    with pytest.raises(InputError, match="semi-definite"):
        PlaneBacking((1.0,), (0.0,), ((-1.0,),))
    with pytest.raises(InputError, match="no motion at the impact point"):
        PlaneBacking((0.0,), (0.0,), ((0.0,),))
    # a backing about as light as the ball's contact nodes: the increment would not be stable
    with pytest.raises(InputError, match="heaviest contact node"):
        fe.simulate(ball, SPEED, target=PlaneBacking.free_mass(1e-4))
    # the 3D geometry meshes flat slabs: no plane on a backing, no spherical cap
    three_d = fe.Hexahedral(fe.Options3D(divisions=4))
    with pytest.raises(InputError, match="axisymmetric geometry"):
        fe.simulate(ball, SPEED, geometry=three_d, target=PlaneBacking.free_mass(5.0))
    with pytest.raises(InputError, match="sphere_radius_m.*axisymmetric"):
        fe.simulate(ball, SPEED, geometry=three_d, target=load_target("cricket-helmet"))


def test_modal_form_matches_the_mass_form():
    backing = PlaneBacking.free_mass(4.0, 1e4, 20.0)
    assert backing.high_frequency_mass_kg == pytest.approx(4.0)
    assert backing.arrays()["backing_omega2_1_s2"][0] == pytest.approx(1e4 / 4.0)
    assert backing.arrays()["backing_damping_1_s"][0, 0] == pytest.approx(20.0 / 4.0)
    assert float(np.asarray(backing.frequencies_hz)[0]) == pytest.approx(
        math.sqrt(1e4 / 4.0) / (2 * math.pi))


def test_a_batch_of_backings_is_the_runs_one_by_one(ball):
    """One vmapped run with a backing per run (`fe.simulate_batch(target=[...])`) gives each
    run's figures as its own run does; backings of other structures are refused by name."""
    backings = [PlaneBacking.free_mass(m) for m in (1.0, 5.0, 20.0)]
    batch = fe.simulate_batch(ball, SPEED, target=backings)
    assert [r.target for r in batch] == [b.name for b in backings]
    for run, backing in zip(batch, backings):
        alone = fe.simulate(ball, SPEED, target=backing)
        assert run.cor == pytest.approx(alone.cor, rel=1e-9, abs=1e-12)
        assert _backing_velocity(run) == pytest.approx(_backing_velocity(alone), rel=1e-9)
    assert batch[0].cor < batch[1].cor < batch[2].cor  # lighter backings take more momentum
    two_modes = PlaneBacking((1.0, 0.5), (0.0, 100.0), ((0.0, 0.0), (0.0, 0.0)))
    with pytest.raises(InputError, match="share one structure"):
        fe.simulate_batch(ball, SPEED, target=[backings[0], two_modes])
    with pytest.raises(InputError, match="one target or 2"):
        fe.simulate_batch(ball, [SPEED, 20.0], target=backings)


def test_the_estimate_counts_the_backings_history(ball):
    """`fe.estimate`'s history memory counts a backing's columns (`Kernel.history_names`)."""
    from ballimpact.fe.axi.kernel import BACKING_HISTORY, HISTORY

    plain = fe.estimate(ball, SPEED)
    backed = fe.estimate(ball, SPEED, target=PlaneBacking.free_mass(5.0))
    columns = len(HISTORY) + len(BACKING_HISTORY) + 2  # and the one mode's q and q'
    per_column = plain.memory_bytes / len(HISTORY)
    assert backed.memory_bytes / backed.steps == pytest.approx(
        per_column / plain.steps * columns, rel=1e-12)
