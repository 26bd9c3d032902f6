"""Explicit FE ball against closed forms and conservation laws (docs/fe.md "Verification"):
Hertz (peak force and contact time), energy balance, dissipation = kinetic energy lost, layered =
homogeneous, a vmap batch = single runs, clear errors."""

import math

import numpy as np
import pytest

from ballimpact.errors import InputError, SimulationError
from ballimpact.balls.ball import BallModel, Layer
from ballimpact.constitutive import material_from_dict
from ballimpact.fe import SolverOptions, simulate, simulate_batch

RADIUS, DENSITY, E, SPEED = 0.036, 800.0, 10e6, 1.0
# Hertz needs the contact patch (radius ~7 mm here) resolved: 2 mm elements, 0.5 mm at the pole.
HERTZ_MESH = dict(element_size_m=2e-3, pole_element_size_m=0.5e-3)
NO_BULK_VISCOSITY = dict(bulk_viscosity_linear=0.0, bulk_viscosity_quadratic=0.0)


def _sphere(material: dict, name="sphere", radii=(RADIUS,), density=DENSITY) -> BallModel:
    mat = material_from_dict(material)
    return BallModel(name, tuple(Layer(f"l{i}", r, density, mat) for i, r in enumerate(radii)))


def _hertz(mass, nu):
    e_star = E / (1 - nu ** 2)
    delta = (15 * mass * SPEED ** 2 / (16 * e_star * math.sqrt(RADIUS))) ** 0.4
    return 4 / 3 * e_star * math.sqrt(RADIUS) * delta ** 1.5, \
        2.868 * (mass ** 2 / (RADIUS * e_star ** 2 * SPEED)) ** 0.2


@pytest.fixture(scope="module")
def elastic_045():
    ball = _sphere({"model": "linear_elastic", "youngs_modulus_pa": E, "poissons_ratio": 0.45})
    return simulate(ball, SPEED, SolverOptions(**HERTZ_MESH, **NO_BULK_VISCOSITY))


def test_hertz_peak_force_and_contact_time(elastic_045):
    peak, contact = _hertz(elastic_045.mass_kg, 0.45)
    assert elastic_045.peak_force_n == pytest.approx(peak, rel=0.03)
    assert elastic_045.contact_time_s == pytest.approx(contact, rel=0.03)


def test_hertz_nearly_incompressible_does_not_lock():
    ball = _sphere({"model": "linear_elastic", "youngs_modulus_pa": E, "poissons_ratio": 0.495})
    result = simulate(ball, SPEED, SolverOptions(**HERTZ_MESH, **NO_BULK_VISCOSITY))
    peak, contact = _hertz(result.mass_kg, 0.495)
    assert result.peak_force_n == pytest.approx(peak, rel=0.05)
    assert result.contact_time_s == pytest.approx(contact, rel=0.05)


def test_elastic_impact_conserves_energy(elastic_045):
    assert elastic_045.cor > 0.98
    assert elastic_045.energy_balance_error < 0.01
    # the centre-of-mass velocity is constant after separation (momentum conservation)
    h = elastic_045.history
    after = h["time_s"] > elastic_045.contact_time_s + 2 * elastic_045.stable_time_increment_s
    assert np.ptp(h["centre_velocity_z_m_s"][after]) < 1e-9 * SPEED


def test_viscoelastic_dissipation_equals_kinetic_energy_lost():
    ball = _sphere({"model": "neo_hookean", "c10_pa": 2e6, "d1_per_pa": 0.0,
                    "prony": [{"g": 0.5, "k": 0.0, "tau_s": 2e-4}]})
    # a long margin after separation lets the branches relax (tau = 0.2 ms)
    result = simulate(ball, 5.0, SolverOptions(element_size_m=3e-3, end_margin=1.5))
    e = result.energies_j
    lost = 0.5 * result.mass_kg * 5.0 ** 2 * (1 - result.cor ** 2)
    assert 0.1 < result.cor < 0.95
    assert e["viscous_dissipation_j"] + e["bulk_viscous_dissipation_j"] == pytest.approx(lost, rel=0.01)
    assert result.energy_balance_error < 0.01


def test_bulk_viscosity_dissipates_what_the_ball_loses():
    """An elastic ball whose only loss is bulk viscosity (raised to make it measurable)."""
    ball = _sphere({"model": "neo_hookean", "c10_pa": 2e6, "d1_per_pa": 1e-7})
    result = simulate(ball, 10.0, SolverOptions(element_size_m=3e-3, bulk_viscosity_linear=0.6,
                                                bulk_viscosity_quadratic=2.0))
    e = result.energies_j
    lost = 0.5 * result.mass_kg * 10.0 ** 2 * (1 - result.cor ** 2)  # rigid-body energy lost
    vibration = e["kinetic_energy_j"] - 0.5 * result.mass_kg * (result.cor * 10.0) ** 2
    assert result.cor < 0.99 and result.energy_balance_error < 0.01
    assert e["bulk_viscous_dissipation_j"] > 0.2 * lost
    # no Prony terms: internal work = strain energy + bulk-viscous dissipation, so nothing is
    # left for viscous dissipation unless the bulk-viscous power is booked wrongly
    assert abs(e["viscous_dissipation_j"]) < 0.01 * e["bulk_viscous_dissipation_j"]
    # what the ball lost went into bulk viscosity and the vibration it carries away (its strain,
    # hourglass included, and kinetic parts)
    stored = e["strain_energy_j"] + e["hourglass_energy_j"]
    assert e["bulk_viscous_dissipation_j"] + stored + vibration == pytest.approx(lost, rel=0.01)


def test_cor_falls_as_relaxation_grows():
    cors = []
    for g in (0.1, 0.4, 0.7):
        ball = _sphere({"model": "neo_hookean", "c10_pa": 2e6,
                        "prony": [{"g": g, "k": 0.0, "tau_s": 2e-4}]})
        result = simulate(ball, 5.0, SolverOptions(element_size_m=4e-3))
        assert min(v for k, v in result.energies_j.items() if k != "contact_work_j") >= 0.0
        cors.append(result.cor)
    assert cors[0] > cors[1] > cors[2]


def test_layered_ball_of_one_material_is_the_homogeneous_ball():
    spec = {"model": "mooney_rivlin", "c10_pa": 4.0e6, "c01_pa": -0.4e6,
            "prony": [{"g": 0.5, "k": 0.0, "tau_s": 1e-4}]}
    radii = (0.02, 0.031, RADIUS)
    layered = _sphere(spec, "layered", radii)
    homogeneous = _sphere(spec, "homogeneous")
    options = SolverOptions(element_size_m=3e-3, mesh_radii_m=radii)  # the same mesh for both
    a, b = simulate(layered, 15.0, options), simulate(homogeneous, 15.0, options)
    assert a.elements == b.elements and a.steps == b.steps
    for name in ("contact_force_n", "centre_velocity_z_m_s", "kinetic_energy_j"):
        np.testing.assert_allclose(a.history[name], b.history[name], rtol=1e-6,
                                   atol=1e-9 * np.max(np.abs(b.history[name])))
    assert a.cor == pytest.approx(b.cor, rel=1e-6)


def test_vmap_batch_equals_single_runs():
    rng = np.random.default_rng(3)
    balls = []
    for i in range(16):
        c10 = rng.uniform(3e6, 6e6)
        spec = {"model": "mooney_rivlin", "c10_pa": c10, "c01_pa": -rng.uniform(0, 0.1) * c10,
                "prony": [{"g": rng.uniform(0.3, 0.8), "k": 0.0, "tau_s": rng.uniform(5e-5, 2e-4)}]}
        balls.append(_sphere(spec, f"set{i}", density=rng.uniform(780, 860)))
    options = SolverOptions(element_size_m=4e-3)
    batch = simulate_batch(balls, 10.0, options)  # groups of 4 on a CPU, the last one padded
    assert simulate_batch(balls[:3], 10.0, options, group_size=16)[2].cor == pytest.approx(
        batch[2].cor, rel=1e-12)
    for ball, together in zip(balls, batch):
        alone = simulate(ball, 10.0, options)
        assert together.steps == alone.steps
        np.testing.assert_allclose(together.history["contact_force_n"],
                                   alone.history["contact_force_n"], rtol=1e-9,
                                   atol=1e-9 * alone.peak_force_n)
        assert together.cor == pytest.approx(alone.cor, rel=1e-9)
        assert together.contact_time_s == pytest.approx(alone.contact_time_s, rel=1e-9)
    assert len({round(r.peak_force_n) for r in batch}) > 8  # the sets really differ


def test_inverted_element_is_a_clear_error():
    ball = _sphere({"model": "neo_hookean", "c10_pa": 2e3})  # far too soft for 40 m/s
    with pytest.raises(SimulationError, match="inverted element or non-finite|energy balance"):
        simulate(ball, 40.0, SolverOptions(element_size_m=4e-3))


@pytest.mark.parametrize("options, key", [
    (dict(element_size_m=-1.0), "element_size_m"),
    (dict(element_size_m=float("inf")), r"element_size_m = inf: expected a finite number"),
    (dict(time_step_scale=2.5), "time_step_scale"),
    (dict(penalty_scale=0.0), "penalty_scale"),
    (dict(bulk_viscosity_linear=-0.1), "bulk_viscosity_linear"),
])
def test_bad_options_name_the_field(options, key):
    with pytest.raises(InputError, match=key):
        SolverOptions(**options)


def test_bad_speed_is_an_input_error():
    ball = _sphere({"model": "neo_hookean", "c10_pa": 2e6})
    with pytest.raises(InputError, match="impact_speed_m_s"):
        simulate(ball, -3.0)


def test_messages_show_plain_numbers_not_numpy_reprs():
    """NumPy 2 writes numpy scalars as np.float64(...) with !r: messages show plain numbers."""
    from ballimpact.constitutive.stability import mooney_rivlin_drucker
    from ballimpact.oblique import ImpactCondition, Options3D

    ball = _sphere({"model": "neo_hookean", "c10_pa": 2e6})
    cases = [
        (lambda: simulate(ball, np.float64(-3.0)),
         "impact_speed_m_s = -3: allowed range (0, inf) m/s"),
        (lambda: simulate_batch([ball, ball], np.array([10.0, np.nan])), "impact_speed_m_s = nan"),
        (lambda: SolverOptions(element_size_m=np.float64(-1e-3)), "element_size_m = -0.001"),
        (lambda: SolverOptions(chunk_steps=np.int64(0)), "chunk_steps = 0"),
        (lambda: ImpactCondition(np.float64(2e3)), "speed_m_s = 2000"),
        (lambda: Options3D(time_step_scale=np.float64(2.5)), "time_step_scale = 2.5"),
        (lambda: material_from_dict({"model": "neo_hookean", "c10_pa": np.float64(np.inf)}),
         "c10_pa = inf: expected a finite number in (0, inf)"),
        (lambda: mooney_rivlin_drucker(1e6, 0.0, np.float64(-1.0), 2.0), "stretch_min = -1"),
    ]
    for call, words in cases:
        with pytest.raises(InputError) as error:
            call()
        assert words in str(error.value) and "np." not in str(error.value), str(error.value)
    assert repr(ImpactCondition(np.float64(20.0))).startswith("ImpactCondition(speed_m_s=20.0,")
