"""The closed form of a ball on a thin liner over a free backing (`protect.liner`;
docs/equipment.md, "What a liner's stiffness implies"): its limits, and the FE liner against
it (slow)."""

import math
import warnings

import numpy as np
import pytest

from ballimpact import fe
from ballimpact.errors import InputError, InputWarning
from ballimpact.fe.backing import PlaneBacking
from ballimpact.fe.hex.target import Target
from ballimpact.material.modes import confined_stress, deformation_stress
from ballimpact.protect.liner import liner_impact

R, M_BALL, BACKING = 0.036, 0.16, 5.0
E_BALL, NU_BALL = 2e9, 0.3
E_STAR = E_BALL / (1.0 - NU_BALL ** 2)
#: the helmet preset's EPS (elastic) and a softer-shouldered foam, each 2 mm thick
EPS = (8e6, 20.0)
FOAM = (8e6, 2.0)


def _liner(mu_pa: float, alpha: float, thickness_m: float = 2e-3, nu: float = 0.0,
           backing: float | None = BACKING) -> Target:
    spec = {"name": "liner", "half_width_m": 0.04,
            "layers": [{"name": "liner", "thickness_m": thickness_m, "density_kg_m3": 70.0,
                        "material": {"model": "ogden_hyperfoam", "moduli": "instantaneous",
                                     "terms": [{"mu_pa": mu_pa, "alpha": alpha, "nu": nu}]}}]}
    if backing is not None:
        spec["backing"] = {"mass_kg": backing}
    return Target.from_dict(spec)


def test_a_foam_of_nu_0_in_confined_compression_is_its_uniaxial_test():
    stretch = np.linspace(0.3, 1.0, 15)
    layer = _liner(*EPS).layers[0]
    confined = confined_stress(layer.material, stretch)
    uniaxial = deformation_stress("ogden_hyperfoam", layer.material.hyperelastic_constants(),
                                  "uniaxial", stretch)
    assert np.allclose(confined, uniaxial, rtol=1e-9, atol=1e-3)
    # closed form of one nu = 0 term: P = 2 mu / alpha (l^(alpha - 1) - 1 / l)
    mu, alpha = EPS
    assert np.allclose(confined, 2 * mu / alpha * (stretch ** (alpha - 1) - 1 / stretch),
                       rtol=1e-9, atol=1e-3)
    # nu > 0: the confined column is stiffer than the free one
    bulky = _liner(*EPS, nu=0.3).layers[0].material
    free = deformation_stress("ogden_hyperfoam", bulky.hyperelastic_constants(), "uniaxial",
                              stretch[:-1])
    assert np.all(confined_stress(bulky, stretch[:-1]) < free)  # more negative: stiffer
    with pytest.raises(InputError, match="confined compression"):
        confined_stress(fe.load_ball("cricket-men", impact_speed_m_s=19.0).layers[0].material,
                        stretch)


def test_small_compressions_are_the_linear_bed_of_springs():
    """A slow rigid ball: F = pi R E h^-1 d^2 (E = 2 mu for nu = 0), the energy pi R E d^3
    / (3 h) = mu v^2 / 2."""
    layer = _liner(*FOAM).layers[0]
    speed = 0.01
    est = liner_impact(R, M_BALL, math.inf, layer, BACKING, speed)
    reduced = M_BALL * BACKING / (M_BALL + BACKING)
    c = math.pi * R * 2 * FOAM[0] / layer.thickness_m
    d = (1.5 * reduced * speed ** 2 / c) ** (1 / 3)
    assert est.max_compression * layer.thickness_m == pytest.approx(d, rel=0.01)
    assert est.peak_force_n == pytest.approx(c * d ** 2, rel=0.02)
    assert est.bare_peak_force_n == math.inf and est.factor == 0.0


def test_a_stiff_liner_is_the_bare_backing_and_a_soft_one_bottoms_out():
    stiff = liner_impact(R, M_BALL, E_STAR, _liner(1e13, 2.0).layers[0], BACKING, 2.0)
    assert stiff.factor == pytest.approx(1.0, abs=0.01)
    with pytest.raises(InputError, match="liner 'liner': bottoms out"):
        liner_impact(R, M_BALL, E_STAR, _liner(*EPS).layers[0], BACKING, 5.0)


@pytest.fixture(scope="module")
def ball():
    rho = M_BALL / (4.0 / 3.0 * math.pi * R ** 3)
    return fe.load_ball({"name": "stiff", "layers": [
        {"name": "ball", "outer_radius_m": R, "density_kg_m3": rho,
         "material": {"model": "linear_elastic", "youngs_modulus_pa": E_BALL,
                      "poissons_ratio": NU_BALL}}]}, allow={"ball-units"})


@pytest.mark.slow
@pytest.mark.parametrize("foam, speed, factor_tolerance", [(EPS, 1.0, 0.05), (FOAM, 2.0, 0.15)])
def test_the_fe_liner_lowers_the_acceleration_by_the_factor_its_stiffness_implies(
        ball, foam, speed, factor_tolerance):
    """A stiff elastic ball on 2 mm of foam over a free 5 kg mass, and on the bare mass
    (`PlaneBacking.free_mass`), axisymmetric with 0.4 mm pole elements: the backing's peak
    accelerations' ratio against `liner_impact`'s factor, the liner's compression against its.

    Measured: EPS at 1 m/s factor 0.170 against 0.169, compression 0.450 against 0.451; the
    alpha-2 foam at 2 m/s 0.372 against 0.338 (+10%: the columns' shear coupling, left out by
    the closed form, stiffens the FE layer at a contact radius of 4 thicknesses), compression
    0.461 against 0.453. The bare mass: Hertz within 0.1% (1176 N)."""
    geometry = fe.Axisymmetric(fe.SolverOptions(pole_element_size_m=0.4e-3))
    target = _liner(*foam)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)  # speeds below the checked range
        bare = fe.simulate(ball, speed, geometry=geometry,
                           target=PlaneBacking.free_mass(BACKING), allow={"speed-range"})
        lined = fe.simulate(ball, speed, geometry=geometry, target=target,
                            allow={"speed-range"})
    est = liner_impact(R, M_BALL, E_STAR, target.layers[0], BACKING, speed)
    bare_g = -np.min(bare.history["backing_acceleration_z_m_s2"])
    lined_g = -np.min(lined.history["backing_acceleration_z_m_s2"])
    assert bare.peak_force_n == pytest.approx(est.bare_peak_force_n, rel=0.01)
    assert lined_g / bare_g == pytest.approx(est.factor, rel=factor_tolerance)
    assert lined_g / bare_g >= est.factor * 0.99  # the columns alone are the softer bound
    assert lined.energies_j["target_liner_max_compression"] == pytest.approx(
        est.max_compression, rel=0.03)
    assert abs(lined.energy_balance_error) < 1e-4


@pytest.mark.parametrize("args, fragments", [
    ((36.0, M_BALL, E_STAR, BACKING, 1.0), ("2 x ball_radius_m = 72", "millimetres")),
    ((R, 160.0, E_STAR, BACKING, 1.0), ("ball_mass_kg = 160.0", "grams")),
    ((R, M_BALL, 2000.0, BACKING, 1.0), ("ball_modulus_pa = 2000: allowed range [10000, inf) Pa",
                                         "MPa")),
    ((R, M_BALL, E_STAR, 5000.0, 1.0), ("backing_mass_kg = 5000", "grams")),
    ((R, M_BALL, E_STAR, BACKING, -1.0), ("speed_m_s = -1",)),
])
def test_unit_slips_are_named(args, fragments):
    radius, mass, modulus, backing, speed = args
    with pytest.raises(InputError) as err:
        liner_impact(radius, mass, modulus, _liner(*FOAM).layers[0], backing, speed)
    message = str(err.value)
    assert "\n" not in message and all(f in message for f in fragments), message


@pytest.mark.slow
def test_the_default_mesh_reads_the_factor_high(ball):
    """The same runs on the default mesh (1.5 mm elements): the bare ball's Hertz patch (2.1 mm
    at 1 m/s) spans 1.4 elements (the run warns), so the bare peak reads 2-4% low and the
    factor high. Measured: EPS 0.191 against 0.169 (+13%), the alpha-2 foam 0.387 against
    0.338 (+14%); the liner's compression -2.0% / +0.6%."""
    for foam, speed in ((EPS, 1.0), (FOAM, 2.0)):
        target = _liner(*foam)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", InputWarning)
            bare = fe.simulate(ball, speed, target=PlaneBacking.free_mass(BACKING),
                               allow={"speed-range"})
            lined = fe.simulate(ball, speed, target=target, allow={"speed-range"})
        est = liner_impact(R, M_BALL, E_STAR, target.layers[0], BACKING, speed)
        ratio = (np.min(lined.history["backing_acceleration_z_m_s2"])
                 / np.min(bare.history["backing_acceleration_z_m_s2"]))
        assert est.factor < ratio < 1.2 * est.factor
        assert lined.energies_j["target_liner_max_compression"] == pytest.approx(
            est.max_compression, rel=0.03)
