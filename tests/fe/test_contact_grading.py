"""Mesh grading to the expected Hertz contact radius (`Options3D.contact_elements`)."""

import math

import numpy as np
import pytest

from ballimpact.errors import InputError
from ballimpact.balls.ball import BallModel, Layer
from ballimpact.constitutive import material_from_dict
from ballimpact.oblique import ImpactCondition, Options3D
from ballimpact.fe.hex.contact_grading import grading_for_contact
from ballimpact.fe.engine import contact_resolution_note
from ballimpact.fe.estimates import hertz_contact_radius_m
from ballimpact.fe.hex.mesh import GRADING_RANGE, ball_mesh, pole_spacing_m
from ballimpact.fe import Hexahedral, estimate, load_ball

BALL = BallModel("sphere", (Layer("sphere", 0.036, 800.0, material_from_dict(
    {"model": "linear_elastic", "youngs_modulus_pa": 1e8, "poissons_ratio": 0.23})),))


def test_contact_radius_is_hertz_and_grading_reaches_it():
    """a = sqrt(R delta_max), delta_max = (15 m v^2 / (16 E* sqrt(R)))^(2/5) computed here (1e-6:
    the solver integrates the Hertz motion numerically); the
    grading found puts the asked number of elements across it (to 1e-9), and the mesh built
    with it has that spacing at the pole (its node nearest the pole, to 1e-9)."""
    e_star = 1e8 / (1 - 0.23 ** 2)
    delta = (15 * BALL.mass_kg * 2.0 ** 2 / (16 * e_star * math.sqrt(0.036))) ** 0.4
    for elements in (3.0, 5.0):
        grading, a = grading_for_contact(BALL, 2.0, 16, elements)
        assert a == pytest.approx(math.sqrt(0.036 * delta), rel=1e-6)
        assert pole_spacing_m(0.036, 16, grading) == pytest.approx(a / elements, rel=1e-9)
        mesh = ball_mesh([0.036], 16, grading, half=True)
        outer = mesh.nodes_m[mesh.contact_nodes]
        r = np.hypot(outer[:, 0], outer[:, 1])
        nearest = np.min(r[r > 1e-12])
        arc = 0.036 * math.asin(nearest / 0.036)
        assert arc == pytest.approx(a / elements, rel=1e-6)


def test_options_choose_the_grading_for_the_slowest_normal_speed():
    conditions = [ImpactCondition(2.0, 0.0), ImpactCondition(4.0, 60.0)]   # v_n 2 and 2
    est = estimate(BALL, conditions, geometry=Hexahedral(Options3D(divisions=8,
                                                                   contact_elements=2.0)))
    graded, _ = grading_for_contact(BALL, 2.0, 8, 2.0)
    assert est.elements == estimate(
        BALL, conditions, geometry=Hexahedral(Options3D(divisions=8, pole_grading=graded))).elements
    assert graded > 1.0


def test_unreachable_contact_resolution_names_the_divisions():
    with pytest.raises(InputError, match=r"contact_elements = 30: .* \(use divisions >= \d+"):
        grading_for_contact(BALL, 2.0, 16, 30.0)
    with pytest.raises(InputError, match="contact_elements"):
        Options3D(contact_elements=0.0)


def test_cli_contact_elements_bad_input(bad_input, tmp_path):
    bad_input(["simulate", "--ball", "cricket-universal", "--speed-m-s", "10",
               "--contact-elements", "3"], "--contact-elements", "--solver 3d")
    bad_input(["simulate", "--solver", "3d", "--ball", "cricket-universal", "--speed-m-s", "10",
               "--contact-elements", "100"], "contact_elements = 100", "[0.5, 50]")
    bad_input(["simulate", "--solver", "3d", "--ball", "cricket-universal", "--speed-m-s", "10",
               "--divisions", "8", "--contact-elements", "40"], "contact_elements = 40",
              "use divisions >=")


def _chosen(options, speed_m_s, angle_deg=0.0, ball=BALL):
    geometry = Hexahedral(options).checked(ball, [ImpactCondition(speed_m_s, angle_deg)], None)
    return geometry.options


def test_default_mesh_and_penalty_come_from_the_contact():
    """Options3D's defaults (issue 43): a small contact (0.25 m/s on the 100 MPa sphere, a / R
    0.07, one element of the default grading across it) gets the grading that puts 3 elements
    across the Hertz radius and 3 times the penalty; a ball impact's wide contact (a cricket
    ball at 20 m/s, 7.6 elements) keeps grading 2 and penalty 1; what the user gives is kept.
    The normal speed decides: 0.5 m/s at 60 degrees is 0.25 m/s normal."""
    small = _chosen(Options3D(), 0.25)
    grading, a = grading_for_contact(BALL, 0.25, 16, 3.0)
    assert small.pole_grading == pytest.approx(grading, rel=1e-12) and grading > 2.0
    assert a / pole_spacing_m(0.036, 16, small.pole_grading) == pytest.approx(3.0, rel=1e-9)
    assert small.penalty_scale == 3.0 and small.contact_elements is None
    assert _chosen(Options3D(), 0.5, 60.0) == small
    cricket = load_ball("cricket-universal", impact_speed_m_s=20.0)
    wide = _chosen(Options3D(), 20.0, ball=cricket)
    assert (wide.pole_grading, wide.penalty_scale) == (2.0, 1.0)
    given = _chosen(Options3D(pole_grading=1.5, penalty_scale=2.0), 0.25)
    assert (given.pole_grading, given.penalty_scale) == (1.5, 2.0)
    # a contact spanned by 3 to 4 elements of grading 2: the mesh kept, the penalty raised
    mid = _chosen(Options3D(), 3.0, ball=cricket)
    across = hertz_contact_radius_m(cricket, 3.0) / pole_spacing_m(cricket.outer_radius_m, 16, 2.0)
    assert 3.0 < across < 4.0 and (mid.pole_grading, mid.penalty_scale) == (2.0, 3.0)


def test_a_contact_the_divisions_cannot_resolve_takes_the_finest_pole_and_is_warned():
    """4 divisions cannot put 3 elements across the 0.002 m/s contact (0.37 mm; 0.69 mm at the
    pole at the largest grading): that grading, and the run's 'contact not resolved' note."""
    chosen = _chosen(Options3D(divisions=4), 0.002)
    assert chosen.pole_grading == GRADING_RANGE[1] and chosen.penalty_scale == 3.0
    note = contact_resolution_note(BALL, 0.002, Hexahedral(chosen).pole_element_m(BALL))
    assert note.startswith("contact not resolved") and "spans 0.54 elements" in note


def test_export_keeps_the_default_grading():
    """A deck's mesh has no impact to grade for: grading 2 (`DEFAULT_POLE_GRADING`)."""
    from ballimpact.export.geometry import estimate_elements

    assert estimate_elements(BALL, "3d") == estimate_elements(BALL, "3d", pole_grading=2.0)


def test_cli_penalty_scale_bad_input(bad_input):
    """--penalty-scale has no fixed default any more; a value given is still checked, for the
    3D, the axisymmetric and the compression solvers alike."""
    for argv in (["simulate", "--solver", "3d", "--ball", "cricket-universal", "--speed-m-s", "10",
                  "--penalty-scale", "0"],
                 ["simulate", "--ball", "cricket-universal", "--speed-m-s", "10",
                  "--penalty-scale", "500"],
                 ["compress", "--ball", "baseball", "--deflection-m", "0.002",
                  "--penalty-scale", "-1"]):
        bad_input(argv, "penalty_scale = ", "allowed range (0, 100]")
