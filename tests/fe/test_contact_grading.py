"""Mesh grading to the expected Hertz contact radius (`Options3D.contact_elements`)."""

import math

import numpy as np
import pytest

from ballimpact.errors import InputError
from ballimpact.balls.ball import BallModel, Layer
from ballimpact.constitutive import material_from_dict
from ballimpact.oblique import ImpactCondition, Options3D
from ballimpact.fe.hex.contact_grading import grading_for_contact
from ballimpact.fe.hex.mesh import pole_spacing_m
from ballimpact.fe.hex.mesh import ball_mesh
from ballimpact.fe import Hexahedral, estimate

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
