"""One engine, the geometry a plug-in (`fe.engine`): `fe.simulate(ball, condition,
geometry=Axisymmetric(...) | Hexahedral(...))` runs both geometries through one driver and one
result type, and the former entry points are thin aliases that give the same bits with a
`FutureWarning`."""

import dataclasses
import math

import numpy as np
import pytest

from ballimpact import fe
from ballimpact.errors import InputError
from ballimpact.fe import (Axisymmetric, Hexahedral, ImpactCondition, ImpactResult, Options3D,
                           SolverOptions, load_ball)

SPEED_M_S = 20.0
BALL = load_ball("cricket-universal", impact_speed_m_s=SPEED_M_S)
AXI = Axisymmetric(SolverOptions(element_size_m=4e-3))
HEX = Hexahedral(Options3D(divisions=6))


def test_one_call_runs_either_geometry_into_one_result_type():
    """The same call, the geometry swapped: both results are `ImpactResult`s with the same
    history names for the same quantities; the 3D one's normal figures agree with the
    axisymmetric one's at a normal impact (coarse meshes: peak force and COR within 10%), the
    axisymmetric one's tangential figures are empty."""
    axi = fe.simulate(BALL, ImpactCondition(SPEED_M_S), geometry=AXI)
    hexa = fe.simulate(BALL, ImpactCondition(SPEED_M_S), geometry=HEX)
    assert isinstance(axi, ImpactResult) and isinstance(hexa, ImpactResult)
    assert (axi.geometry, hexa.geometry) == ("axisymmetric", "3d")
    for name in ("time_s", "contact_force_n", "centre_velocity_z_m_s", "kinetic_energy_j",
                 "energy_balance_error", "viscous_dissipation_j"):
        assert name in axi.history and name in hexa.history, name
    assert hexa.peak_force_n == pytest.approx(axi.peak_force_n, rel=0.1)
    assert hexa.cor == pytest.approx(axi.cor, rel=0.1)
    assert math.isnan(axi.tangential_cor) and axi.rebound_spin_rad_s == 0.0
    assert axi.energy_balance_error < 0.01 and hexa.energy_balance_error < 0.01
    # a speed is a normal impact's condition
    by_speed = fe.simulate(BALL, SPEED_M_S, geometry=AXI)
    np.testing.assert_array_equal(by_speed.history["contact_force_n"],
                                  axi.history["contact_force_n"])


def test_former_entry_points_give_the_same_bits_with_a_future_warning():
    from ballimpact.fe import solver
    from ballimpact.oblique import simulate_oblique

    condition = ImpactCondition(SPEED_M_S, angle_deg=30.0, friction=0.3)
    new = fe.simulate(BALL, condition, geometry=HEX)
    with pytest.warns(FutureWarning, match="oblique.simulate_oblique is fe.simulate"):
        old = simulate_oblique(BALL, condition, HEX.options)
    assert new.history_digest() == old.history_digest()
    assert new.summary() | {"wall_time_s": 0} == old.summary() | {"wall_time_s": 0}
    with pytest.warns(FutureWarning, match="fe.solver.estimate_run is fe.estimate"):
        assert solver.estimate_run(BALL, SPEED_M_S, AXI.options).steps == fe.estimate(
            BALL, SPEED_M_S, geometry=AXI).steps


def test_a_batch_of_balls_and_a_batch_of_conditions():
    """Several balls of one structure (axisymmetric) and several conditions of one ball (3D)
    through `fe.simulate_batch`: each member equals its single run to round-off."""
    balls = [BALL, load_ball("cricket-universal", impact_speed_m_s=25.0)]
    batch = fe.simulate_batch(balls, [SPEED_M_S, 25.0], geometry=AXI)
    single = fe.simulate(balls[1], 25.0, geometry=AXI)
    assert batch[1].cor == pytest.approx(single.cor, rel=1e-9)
    conditions = [ImpactCondition(SPEED_M_S, angle_deg=a, friction=0.3) for a in (0.0, 40.0)]
    runs = fe.simulate_batch(BALL, conditions, geometry=HEX)
    assert [r.condition for r in runs] == conditions
    assert runs[1].tangential_cor < 1.0 and runs[1].rebound_angle_deg > 0.0


def test_what_a_geometry_cannot_run_is_refused_by_name():
    target = fe.hex.target.Target.from_dict({"name": "pad", "half_width_m": 0.1, "layers": [
        {"thickness_m": 0.02, "density_kg_m3": 100.0,
         "material": {"model": "linear_elastic", "youngs_modulus_pa": 1e7,
                      "poissons_ratio": 0.3}}]}, where="target")
    with pytest.raises(InputError, match="target = str: expected a PlaneBacking or a Target"):
        fe.simulate(BALL, SPEED_M_S, geometry=AXI, target="pad.json")
    with pytest.raises(InputError, match="half_width_m = 0.01 m is less than the ball's radius"):
        fe.simulate(BALL, SPEED_M_S, geometry=AXI,
                    target=dataclasses.replace(target, half_width_m=0.01))
    with pytest.raises(InputError, match="normal impacts without spin"):
        fe.simulate(BALL, ImpactCondition(SPEED_M_S, angle_deg=10.0), geometry=AXI)
    with pytest.raises(InputError, match="geometry = .*expected fe.Axisymmetric"):
        fe.simulate(BALL, SPEED_M_S, geometry="3d")
    with pytest.raises(InputError, match="options: give the settings inside geometry"):
        fe.simulate(BALL, SPEED_M_S, SolverOptions(), geometry=AXI)
    with pytest.raises(InputError, match="Axisymmetric\\(options\\): expected SolverOptions"):
        Axisymmetric(Options3D())
    with pytest.raises(InputError, match="condition: one impact condition"):
        fe.simulate(BALL, [SPEED_M_S, 30.0], geometry=AXI)
