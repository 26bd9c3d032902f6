"""The 3D solver on converged meshes (issue 12, "Must show"): normal impacts equal the
axisymmetric solver, rigid-body limits over a sweep of incidence, the thesis' oblique case, and a
deformable target against Hertz. About 8 minutes on 2 cores."""

import math

import numpy as np
import pytest

from ballimpact.fe import load_ball
from ballimpact.balls.ball import BallModel, Layer
from ballimpact.constitutive import material_from_dict
from ballimpact.fe import SolverOptions, simulate
from ballimpact.oblique import (ImpactCondition, Options3D, Target, simulate_oblique,
                                simulate_oblique_batch)
from ballimpact.oblique.plots import sweep_points
from ballimpact.oblique.rigid_body import rigid_lines

pytestmark = pytest.mark.slow

R, RHO = 0.036, 800.0
NO_BULK_VISCOSITY = dict(bulk_viscosity_linear=0.0, bulk_viscosity_quadratic=0.0)


def _sphere(material) -> BallModel:
    return BallModel("sphere", (Layer("l", R, RHO, material_from_dict(material)),))


def test_universal_ball_normal_impact_equals_the_axisymmetric_solver():
    ball = load_ball("cricket-universal", impact_speed_m_s=25.0)
    three = simulate_oblique(ball, ImpactCondition(25.0), Options3D(divisions=20))
    axi = simulate(ball, 25.0)
    assert three.peak_force_n == pytest.approx(axi.peak_force_n, rel=0.03)
    assert three.contact_time_s == pytest.approx(axi.contact_time_s, rel=0.03)
    assert three.normal_cor == pytest.approx(axi.cor, abs=0.01)


def test_three_layer_ball_with_hyperfoam_equals_the_axisymmetric_solver():
    """Layers bonded at shared nodes, Mooney-Rivlin core and cover, a hyperfoam mantle (3D
    principal stretches from eigenvalues)."""
    ball = load_ball("cricket-3layer")
    three = simulate_oblique(ball, ImpactCondition(20.8), Options3D(divisions=12))
    axi = simulate(ball, 20.8)
    assert three.peak_force_n == pytest.approx(axi.peak_force_n, rel=0.03)
    assert three.contact_time_s == pytest.approx(axi.contact_time_s, rel=0.03)
    assert three.normal_cor == pytest.approx(axi.cor, abs=0.01)
    assert three.energy_balance_error < 0.01


def test_hertz_case_equals_the_axisymmetric_solver_and_hertz():
    nu, e, v = 0.45, 10e6, 3.0
    ball = _sphere({"model": "linear_elastic", "youngs_modulus_pa": e, "poissons_ratio": nu})
    three = simulate_oblique(ball, ImpactCondition(v),
                             Options3D(divisions=16, pole_grading=3.0, **NO_BULK_VISCOSITY))
    axi = simulate(ball, v, SolverOptions(element_size_m=2e-3, pole_element_size_m=0.5e-3,
                                          **NO_BULK_VISCOSITY))
    e_star, m = e / (1 - nu ** 2), ball.mass_kg
    delta = (15 * m * v ** 2 / (16 * e_star * math.sqrt(R))) ** 0.4
    for reference in ((axi.peak_force_n, axi.contact_time_s),
                      (4 / 3 * e_star * math.sqrt(R) * delta ** 1.5, 2.94 * delta / v)):
        assert three.peak_force_n == pytest.approx(reference[0], rel=0.03)
        assert three.contact_time_s == pytest.approx(reference[1], rel=0.03)
    assert three.normal_cor == pytest.approx(axi.cor, abs=0.01)
    assert three.energy_balance_error < 0.01


def test_rigid_body_limits_over_a_sweep_of_incidence():
    """Gross sliding (Psi > 7): spin w'R = 2.5 mu (1 + e_n) v_n and the tangential change
    mu (1 + e_n) v_n within 3%; below the transition the spin follows neither line exactly but
    stays between the rolling line's value and the sliding limit."""
    ball = _sphere({"model": "linear_elastic", "youngs_modulus_pa": 100e6, "poissons_ratio": 0.3})
    mu, v_n = 0.1, 2.0
    psis = (2.0, 4.0, 10.0, 14.0, 20.0)
    conditions = []
    for psi in psis:
        theta = math.atan(psi * mu * 1.98 / 2)
        conditions.append(ImpactCondition(v_n / math.cos(theta), math.degrees(theta), 0.0, mu))
    results = simulate_oblique_batch(ball, conditions, Options3D(divisions=12, pole_grading=3.0))
    pts = sweep_points(results)
    spin_rigid, dv_rigid = rigid_lines(pts["psi"])
    sliding = pts["psi"] > 8.0
    assert np.sum(sliding) == 3
    assert np.allclose(pts["spin"][sliding], 2.5, rtol=0.03)
    assert np.allclose(pts["tangential_change"][sliding], 1.0, rtol=0.03)
    gripping = ~sliding
    assert np.all(pts["spin"][gripping] > spin_rigid[gripping])
    assert np.all(pts["spin"][gripping] < 2.5)
    assert max(r.energy_balance_error for r in results) < 0.01


def test_thesis_oblique_case():
    """Universal ball, 37 m/s, 34 degrees to the surface (56 from the normal), friction 0.3."""
    ball = load_ball("cricket-universal", impact_speed_m_s=25.0)
    r = simulate_oblique(ball, ImpactCondition(37.0, 56.0, 0.0, 0.3), Options3D(divisions=16))
    assert r.energy_balance_error < 0.01
    v_n, v_x = 37.0 * math.cos(math.radians(56)), 37.0 * math.sin(math.radians(56))
    assert 0.3 < r.normal_cor < 0.6
    # friction takes at most mu (1 + e_n) v_n of tangential speed, and the ball gains topspin
    assert v_x - r.history["centre_velocity_x_m_s"][-1] <= 0.3 * (1 + r.normal_cor) * v_n * 1.01
    assert 0 < r.rebound_spin_rad_s * R <= 2.5 * 0.3 * (1 + r.normal_cor) * v_n * 1.05
    assert r.rebound_angle_deg > 56.0  # the ball leaves flatter than it came
    assert r.energies_j["frictional_dissipation_j"] > 0


@pytest.mark.parametrize("slab_depth_growth", [None, 1.15])
def test_same_material_half_space_follows_hertz(slab_depth_growth):
    """A sphere on a thick slab of its own material: Hertz with the two moduli in series
    (E* halved), contact 2^0.4 = 1.32 times longer than on the rigid plane; with the slab's
    uniform depth cells and with cells graded from the pole spacing at its surface."""
    nu, e, v = 0.45, 10e6, 3.0
    material = {"model": "linear_elastic", "youngs_modulus_pa": e, "poissons_ratio": nu}
    ball = _sphere(material)
    slab = Target.from_dict({"name": "half-space", "half_width_m": 0.12, "layers": [
        {"thickness_m": 0.08, "density_kg_m3": RHO, "material": material}]})
    r = simulate_oblique(ball, ImpactCondition(v),
                         Options3D(divisions=12, pole_grading=3.0, **NO_BULK_VISCOSITY,
                                   slab_depth_growth=slab_depth_growth),
                         target=slab)
    print(f"slab_depth_growth {slab_depth_growth}: peak force {r.peak_force_n:.1f} N, contact "
          f"time {r.contact_time_s * 1e3:.3f} ms, {r.elements} hexahedra, {r.steps} steps")
    e_star, m = 0.5 * e / (1 - nu ** 2), ball.mass_kg
    delta = (15 * m * v ** 2 / (16 * e_star * math.sqrt(R))) ** 0.4
    assert r.peak_force_n == pytest.approx(4 / 3 * e_star * math.sqrt(R) * delta ** 1.5,
                                           rel=0.04)
    assert r.contact_time_s == pytest.approx(2.94 * delta / v, rel=0.04)
    assert r.energy_balance_error < 0.01
