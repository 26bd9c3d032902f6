"""Angle sweeps from Python (`oblique.sweep`): the rows, the ball's k^2, the small-strain
Poisson's ratio and where the elastic-sphere reference applies; one sweep equals the command
line's (`ballimpact simulate --solver 3d --angle-deg ...`, tests/cli/test_cli_angle_sweep.py)."""

import math

import pytest

from ballimpact.errors import InputWarning
from ballimpact.fe import Hexahedral, ImpactCondition, Options3D, load_ball
from ballimpact.balls.ball import BallModel, Layer
from ballimpact.fe.hex.target import Target
from ballimpact.constitutive import material_from_dict
from ballimpact.oblique.rigid_body import normalised_incidence
from ballimpact.oblique.sweep import (
    ROW_FIELDS,
    angle_sweep,
    angle_sweep_summary,
    ball_k2,
    plot_angle_sweep,
    reference_obstacle,
    small_strain_poissons_ratio,
)

R, RHO, E, NU = 0.036, 800.0, 1e8, 0.3
ELASTIC = {"model": "linear_elastic", "youngs_modulus_pa": E, "poissons_ratio": NU}
SPEED, FRICTION = 3.0, 0.3


@pytest.fixture(scope="module")
def coarse_sweep():
    """Two angles of an elastic sphere in one batch on a coarse mesh, through the `start` hook
    (which keeps the estimate it gets and the times its progress is called at)."""
    ball = BallModel("sphere", (Layer("sphere", R, RHO, material_from_dict(ELASTIC)),))
    estimates, times = [], []

    def start(cost):
        estimates.append(cost)
        return times.append

    # the coarse mesh (its grading and penalty given: the defaults would resolve the contact), said
    coarse = Options3D(divisions=6, pole_grading=2.0, penalty_scale=1.0)
    with pytest.warns(InputWarning, match="^contact not resolved"):
        sweep = angle_sweep(ball, ImpactCondition(SPEED, friction=FRICTION), [40.0, 10.0],
                            geometry=Hexahedral(coarse), start=start)
    return ball, sweep, estimates, times


def test_a_sweep_runs_from_python_with_its_rows_and_reference(coarse_sweep):
    """A row per angle in ascending order with every field, Psi by its definition with the
    run's own normal COR, and the elastic-sphere reference at the sphere's Poisson's ratio."""
    _, sweep, _, _ = coarse_sweep
    assert [row["angle_deg"] for row in sweep.rows] == [10.0, 40.0]
    assert all(set(row) == set(ROW_FIELDS) for row in sweep.rows)
    for row, result in zip(sweep.rows, sweep.results):
        theta = math.radians(row["angle_deg"])
        assert row["psi"] == pytest.approx(normalised_incidence(
            SPEED * math.sin(theta), SPEED * math.cos(theta), 0.0, R, FRICTION,
            result.normal_cor), rel=1e-12)
        assert result.energy_balance_error < 0.01
    assert sweep.reference["poissons_ratio"] == pytest.approx(NU, abs=1e-9)
    assert sweep.k2 == pytest.approx(0.4, rel=1e-12) and sweep.wall_time_s > 0


def test_the_start_hook_gets_the_batch_estimate_and_gives_the_progress(coarse_sweep):
    _, sweep, estimates, times = coarse_sweep
    (cost,) = estimates
    assert cost.runs == 2 and cost.elements == sweep.results[0].elements
    assert cost.steps >= max(r.steps for r in sweep.results)  # on the high side
    assert times and times == sorted(times) and times[-1] > sweep.results[0].contact_time_s


def test_sweep_summary_and_plot(coarse_sweep, tmp_path):
    ball, sweep, _, _ = coarse_sweep
    out = angle_sweep_summary(sweep, ball)
    assert out["ball"] == "sphere" and out["speed_m_s"] == SPEED
    assert out["friction"] == FRICTION and out["spin_rad_s"] == 0.0
    assert out["target"] == "rigid plane" and out["elements"] == sweep.results[0].elements
    assert out["half_model"] is True and out["k2"] == sweep.k2
    assert out["runs"] is sweep.rows and out["reference"] is sweep.reference
    assert out["reference_note"].startswith("elastic sphere on a rigid plane")
    assert out["plot"] is None and out["wall_time_s"] == sweep.wall_time_s
    png = tmp_path / "sweep.png"
    assert plot_angle_sweep(sweep, png, ball) == str(png)
    assert png.read_bytes().startswith(b"\x89PNG\r\n\x1a\n") and png.stat().st_size > 10_000


@pytest.mark.parametrize("nu", [-0.2, 0.0, 0.23, 0.3, 0.45, 0.499])
def test_poissons_ratio_from_the_small_strain_moduli(nu):
    material = material_from_dict({"model": "linear_elastic", "youngs_modulus_pa": 5e7,
                                   "poissons_ratio": nu})
    assert small_strain_poissons_ratio(material) == pytest.approx(nu, abs=1e-9)


def test_k2_of_layered_balls():
    """0.4 for uniform density whatever the layers; a thin heavy shell tends to 2/3
    (k^2 = 2/3 (1 - q^5) / (1 - q^3) / ... exactly: I = 2/5 m_shell R^2 (1 - q^5) / (1 - q^3))."""
    mat = material_from_dict(ELASTIC)
    uniform = BallModel("u", (Layer("core", 0.02, RHO, mat), Layer("cover", R, RHO, mat)))
    assert ball_k2(uniform) == pytest.approx(0.4, rel=1e-12)
    q = 0.95
    shell = BallModel("s", (Layer("core", q * R, 1e-9 * RHO, mat), Layer("cover", R, RHO, mat)))
    assert ball_k2(shell) == pytest.approx(0.4 * (1 - q ** 5) / (1 - q ** 3), rel=1e-6)
    assert 0.6 < ball_k2(shell) < 2 / 3


def test_reference_applies_only_to_a_homogeneous_elastic_ball_on_the_plane_without_spin():
    elastic = BallModel("e", (Layer("sphere", R, RHO, material_from_dict(ELASTIC)),))
    plain = ImpactCondition(SPEED, 20.0, 0.0, FRICTION)
    assert reference_obstacle(elastic, None, plain) is None
    universal = load_ball("cricket-universal", impact_speed_m_s=10.0)
    assert len(universal.layers) > 1 or universal.layers[0].material.prony
    why = reference_obstacle(universal, None, plain)
    assert why is not None and ("layers" in why or "viscoelastic" in why)
    viscous = BallModel("v", (Layer("sphere", R, RHO, material_from_dict(
        {**ELASTIC, "prony": [{"g": 0.3, "tau_s": 1e-4}]})),))
    assert "viscoelastic" in reference_obstacle(viscous, None, plain)
    assert "3 layers" in reference_obstacle(load_ball("cricket-3layer", SPEED), None, plain)
    slab = Target.from_dict({"name": "plate", "half_width_m": 0.1, "layers": [
        {"thickness_m": 0.02, "density_kg_m3": 1200.0,
         "material": {"model": "linear_elastic", "youngs_modulus_pa": 2e9,
                      "poissons_ratio": 0.3}}]})
    assert "slab" in reference_obstacle(elastic, slab, plain)
    assert "spin" in reference_obstacle(elastic, None, ImpactCondition(SPEED, 20.0, -30.0,
                                                                      FRICTION))
    assert "spin" in reference_obstacle(elastic, None, ImpactCondition(
        SPEED, 20.0, 0.0, FRICTION, spin_z_rad_s=10.0))
    assert "friction" in reference_obstacle(elastic, None, ImpactCondition(SPEED, 20.0))
