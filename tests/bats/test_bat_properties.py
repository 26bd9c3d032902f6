"""A bat's mass, centre of mass and moments of inertia against closed forms (issue 41): a
uniform cylinder, a truncated cone, a hollow tube and a rectangular prism (a blade), and the
beam's mass matrix against them."""

import numpy as np
import pytest

from ballimpact.bats import bat_properties, beam_model, load_bat

RHO, L = 650.0, 0.8
MATERIAL = {"youngs_modulus_pa": 12e9, "density_kg_m3": RHO, "shear_modulus_pa": 1e9}


def bat(profile, **extra):
    return load_bat({"name": "shape", "length_m": L, "profile": profile, "material": MATERIAL,
                     **extra})


def check(props, mass, cm, moi_end):
    moi_cm = moi_end - mass * cm ** 2
    got = (props.mass_kg, props.centre_of_mass_m, props.moi_knob_kg_m2, props.moi_cm_kg_m2)
    for value, expected in zip(got, (mass, cm, moi_end, moi_cm)):
        assert value == pytest.approx(expected, rel=1e-9)


def test_uniform_cylinder():
    r = 0.03
    mass = RHO * np.pi * r ** 2 * L
    props = bat_properties(bat([[0.0, r], [L, r]]))
    check(props, mass, L / 2, mass * (L ** 2 / 3 + r ** 2 / 4))
    assert props.moi_cm_kg_m2 == pytest.approx(mass * (L ** 2 / 12 + r ** 2 / 4), rel=1e-9)


def test_truncated_cone():
    """r(x) = r0 + (r1 - r0) x / L: the integrals of r^2, r^2 x, r^2 x^2 and r^4 in closed form."""
    r0, r1 = 0.012, 0.033
    mass = RHO * np.pi * L * (r0 ** 2 + r0 * r1 + r1 ** 2) / 3
    first = RHO * np.pi * L ** 2 * (r0 ** 2 + 2 * r0 * r1 + 3 * r1 ** 2) / 12
    second = RHO * np.pi * L ** 3 * (r0 ** 2 + 3 * r0 * r1 + 6 * r1 ** 2) / 30
    own = RHO * np.pi / 4 * L * (r1 ** 5 - r0 ** 5) / (5 * (r1 - r0))  # integral of rho I dx
    check(bat_properties(bat([[0.0, r0], [L, r1]])), mass, first / mass, second + own)


def test_hollow_tube():
    r, t = 0.033, 0.0028
    ri = r - t
    mass = RHO * np.pi * (r ** 2 - ri ** 2) * L
    props = bat_properties(bat([[0.0, r], [L, r]], wall_thickness_m=t))
    check(props, mass, L / 2, mass * (L ** 2 / 3 + (r ** 2 + ri ** 2) / 4))


def test_blade_prism_after_a_round_handle():
    """A cylinder handle (0..a) and a rectangular blade (a..L): the sum of the two bodies."""
    a, r, width, depth = 0.3, 0.016, 0.108, 0.05
    m1, m2 = RHO * np.pi * r ** 2 * a, RHO * width * depth * (L - a)
    mass = m1 + m2
    cm = (m1 * a / 2 + m2 * (a + L) / 2) / mass
    moi = (m1 * (a ** 2 / 3 + r ** 2 / 4)
           + m2 * ((L - a) ** 2 / 12 + depth ** 2 / 12 + ((a + L) / 2) ** 2))
    spec = bat([[0.0, r], [a, r]], section={"blade": {
        "width_m": width, "profile_thickness": [[a, depth], [L, depth]]}})
    check(bat_properties(spec), mass, cm, moi)


def test_parallel_axis():
    props = bat_properties("baseball-wood-34in")
    assert props.moi_about_kg_m2(0.0) == pytest.approx(props.moi_knob_kg_m2, rel=1e-12)
    assert props.moi_about_kg_m2(props.centre_of_mass_m) == props.moi_cm_kg_m2


@pytest.mark.parametrize("name", ["baseball-wood-34in", "baseball-aluminium-bbcor-34in",
                                  "cricket-willow-sh"])
def test_beam_mass_matrix_carries_the_rigid_properties(name):
    """The FE mass matrix (mid-point sections) moved rigidly: mass and inertia within 0.1%."""
    spec = load_bat(name)
    props, beam = bat_properties(spec), beam_model(spec)
    shift = np.zeros(beam.dofs)
    shift[0::2] = 1.0
    turn = np.zeros(beam.dofs)
    turn[0::2], turn[1::2] = beam.nodes_m, 1.0
    mass, moi = shift @ beam.mass @ shift, turn @ beam.mass @ turn
    print(name, "FE / exact - 1: mass", mass / props.mass_kg - 1, "I_knob",
          moi / props.moi_knob_kg_m2 - 1)
    assert mass == pytest.approx(props.mass_kg, rel=1e-3)
    assert moi == pytest.approx(props.moi_knob_kg_m2, rel=1e-3)
