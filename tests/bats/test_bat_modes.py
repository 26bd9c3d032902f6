"""The bat's Timoshenko beam and its modes against closed forms (issue 41): Euler-Bernoulli
free-free and pinned-free frequencies of a slender beam, the roots of Timoshenko's free-free
frequency equation for a stocky beam, the exact element stiffness, mesh convergence, and the
rigid-body modes."""

import numpy as np
import pytest
from scipy.optimize import brentq

from ballimpact.bats import PRESETS, DEFAULT_ELEMENTS, Grip, load_bat, modes
from ballimpact.bats.beam import element_matrices

E, NU, RHO = 200e9, 0.3, 7800.0
K_CIRCLE = 6 * (1 + NU) / (7 + 6 * NU)  # Cowper 1966, solid circle
FREE_FREE_BETA_L = (4.7300, 7.8532, 10.9956)  # Euler-Bernoulli free-free roots
PINNED_FREE_BETA_L = 3.9266  # Euler-Bernoulli pinned-free, first flexural root


def rod(length_m, diameter_m):
    """A uniform solid steel rod, as a bat specification."""
    return {"name": "rod", "length_m": length_m,
            "profile": [[0.0, diameter_m / 2], [length_m, diameter_m / 2]],
            "material": {"youngs_modulus_pa": E, "density_kg_m3": RHO, "poissons_ratio": NU}}


def rod_constants(diameter_m):
    area, second = np.pi * diameter_m ** 2 / 4, np.pi * diameter_m ** 4 / 64
    return E * second, K_CIRCLE * E / (2 * (1 + NU)) * area, RHO * area, RHO * second


def euler_bernoulli_hz(beta_l, length_m, diameter_m):
    ei, _, rho_a, _ = rod_constants(diameter_m)
    return beta_l ** 2 * np.sqrt(ei / (rho_a * length_m ** 4)) / (2 * np.pi)


def timoshenko_free_free_det(omega, ei, kga, rho_a, rho_i, length):
    """Determinant of the free-free boundary conditions (theta' = 0, w' - theta = 0 at both
    ends) of the uniform Timoshenko beam below the cut-off frequency: solutions
    (cosh ax, p sinh ax), (sinh ax, p cosh ax), (cos bx, q sin bx), (sin bx, -q cos bx)."""
    w2 = omega ** 2
    roots = np.roots([ei * kga, w2 * (kga * rho_i + rho_a * ei), rho_a * w2 * (rho_i * w2 - kga)])
    a, b = np.sqrt(max(roots.real)), np.sqrt(-min(roots.real))
    p, q = (kga * a ** 2 + rho_a * w2) / (kga * a), (rho_a * w2 - kga * b ** 2) / (kga * b)
    th, c, s = np.tanh(a * length), np.cos(b * length), np.sin(b * length)
    e = 1.0 / np.cosh(a * length)  # the rows at x = L divided by cosh(aL)
    matrix = np.array([
        [p * a, 0.0, q * b, 0.0],  # theta'(0)
        [0.0, a - p, 0.0, b + q],  # w'(0) - theta(0)
        [p * a, p * a * th, q * b * c * e, q * b * s * e],  # theta'(L)
        [(a - p) * th, a - p, -(b + q) * s * e, (b + q) * c * e]])  # w'(L) - theta(L)
    return np.linalg.det(matrix)


def timoshenko_free_free_hz(length_m, diameter_m, count):
    """The lowest roots of Timoshenko's free-free frequency equation (bracketed on a grid)."""
    constants = rod_constants(diameter_m)
    top = 1.2 * euler_bernoulli_hz(FREE_FREE_BETA_L[count - 1], length_m, diameter_m)
    grid = 2 * np.pi * np.linspace(top / 400, top, 4000)
    values = [timoshenko_free_free_det(w, *constants, length_m) for w in grid]
    roots = [brentq(timoshenko_free_free_det, grid[i], grid[i + 1], (*constants, length_m),
                    xtol=1e-12) for i in range(len(grid) - 1) if values[i] * values[i + 1] < 0]
    return np.array(roots[:count]) / (2 * np.pi)


def test_element_stiffness_is_the_exact_timoshenko_one():
    """The interdependent interpolation gives Przemieniecki's exact uniform-element stiffness."""
    h, ei, kga = 0.05, 3.0e3, 4.0e6
    phi = 12 * ei / (kga * h ** 2)
    k, _ = element_matrices(h, ei, kga, 1.0, 1e-4)
    exact = ei / ((1 + phi) * h ** 3) * np.array([
        [12, 6 * h, -12, 6 * h], [6 * h, (4 + phi) * h ** 2, -6 * h, (2 - phi) * h ** 2],
        [-12, -6 * h, 12, -6 * h], [6 * h, (2 - phi) * h ** 2, -6 * h, (4 + phi) * h ** 2]])
    assert np.max(np.abs(k[0] - exact)) < 1e-12 * np.max(np.abs(exact))


def test_slender_free_free_matches_euler_bernoulli():
    length, diameter = 2.0, 0.02  # L/D = 100
    result = modes(rod(length, diameter), count=5)
    expected = [euler_bernoulli_hz(b, length, diameter) for b in FREE_FREE_BETA_L]
    errors = result.flexural_frequencies_hz / expected - 1
    print("slender free-free, relative to Euler-Bernoulli:", errors)
    assert np.all(np.abs(errors) < 0.005)


def test_timoshenko_equation_solver_reduces_to_euler_bernoulli():
    """The test's own reference: for a slender rod its roots approach Euler-Bernoulli's."""
    roots = timoshenko_free_free_hz(2.0, 0.01, 2)  # L/D = 200
    expected = [euler_bernoulli_hz(b, 2.0, 0.01) for b in FREE_FREE_BETA_L[:2]]
    assert np.allclose(roots, expected, rtol=5e-4)


def test_stocky_free_free_matches_timoshenko_equation():
    length, diameter = 0.25, 0.05  # L/D = 5
    result = modes(rod(length, diameter), count=4)
    fe = result.flexural_frequencies_hz
    exact = timoshenko_free_free_hz(length, diameter, 2)
    bernoulli = np.array([euler_bernoulli_hz(b, length, diameter) for b in FREE_FREE_BETA_L[:2]])
    print("stocky: FE", fe, "Timoshenko", exact, "Euler-Bernoulli", bernoulli,
          "FE/Timoshenko - 1", fe / exact - 1, "Timoshenko/EB", exact / bernoulli)
    assert np.all(np.abs(fe / exact - 1) < 0.01)
    assert np.all(fe < 0.95 * bernoulli)


def test_pinned_free_matches_euler_bernoulli():
    length, diameter = 2.0, 0.02
    result = modes(rod(length, diameter), support="pivot", pivot_m=0.0, count=3)
    assert result.rigid_count == 1 and result.frequencies_hz[0] < 1e-3 * result.frequencies_hz[1]
    expected = euler_bernoulli_hz(PINNED_FREE_BETA_L, length, diameter)
    error = result.flexural_frequencies_hz[0] / expected - 1
    print("pinned-free first flexural, relative error:", error)
    assert abs(error) < 0.005


@pytest.mark.parametrize("name", PRESETS)
def test_mesh_convergence(name):
    coarse = modes(name, count=5).flexural_frequencies_hz
    fine = modes(name, count=5, elements=2 * DEFAULT_ELEMENTS).flexural_frequencies_hz
    change = np.abs(coarse / fine - 1)
    print(name, "N -> 2N change of the first three flexural frequencies:", change)
    assert np.all(change < 1e-3)


@pytest.mark.parametrize("name", PRESETS)
def test_rigid_body_modes(name):
    result = modes(name, count=6)
    f = result.frequencies_hz
    assert result.rigid_count == 2
    print(name, "rigid-body frequencies (Hz):", f[:2], "first flexural:", f[2])
    assert np.all(f[:2] < 1e-3 * f[2])
    phi, m = result.vectors, result.beam.mass
    gram = phi.T @ m @ phi
    assert np.allclose(gram, np.eye(result.count), atol=1e-9)  # mass-normalised, orthogonal
    assert np.max(np.abs(gram[:2, 2:])) < 1e-9
    assert np.allclose(result.modal_masses_kg, 1.0)


def test_interpolation_agrees_with_nodes_and_slope():
    result = modes("baseball-wood-34in", count=4)
    nodes = result.nodes_m
    assert np.allclose(result.deflection(nodes), result.deflections, atol=1e-12)
    assert np.allclose(result.rotation(nodes), result.rotations, atol=1e-9)
    x, dx = np.array([0.3, 0.71]), 1e-6
    numeric = (result.deflection(x + dx) - result.deflection(x - dx)) / (2 * dx)
    assert np.allclose(result.slope(x), numeric, rtol=1e-5, atol=1e-8)
    m_eff = result.effective_mass_kg(0.71)
    assert m_eff.shape == (4, 1) and np.all(m_eff > 0)
    point = result.impact_point(0.71)
    assert np.allclose(point["deflection"], result.deflection(0.71)[:, 0])
    assert np.allclose(point["effective_mass_kg"], m_eff[:, 0])
    # rigid modes at x: translation (1/sqrt(m)) and rotation about the centre of mass give
    # 1/m + (x - cm)^2 / I_cm: the rigid bat's inverse effective mass there
    from ballimpact.bats import bat_properties
    props = bat_properties("baseball-wood-34in")
    inverse = np.sum(point["deflection"][:2] ** 2)
    expected = 1 / props.mass_kg + (0.71 - props.centre_of_mass_m) ** 2 / props.moi_cm_kg_m2
    assert inverse == pytest.approx(expected, rel=1e-3)


def test_fewer_modes_than_rigid_ones():
    result = modes("baseball-wood-34in", count=1)
    assert result.count == 1 and result.rigid_count == 1


def test_pivot_and_grip():
    bat = load_bat("baseball-wood-34in")
    pivot = modes(bat, support="pivot", pivot_m=0.15, count=3)
    assert pivot.rigid_count == 1 and np.any(np.isclose(pivot.nodes_m, 0.15))
    i = int(np.argmin(np.abs(pivot.nodes_m - 0.15)))
    assert np.all(pivot.deflections[:, i] == 0.0)
    gripped = modes(bat, grip=Grip(stiffness_n_m=2e4, damping_n_s_m=20.0), count=4)
    assert gripped.rigid_count == 0 and 0 < gripped.frequencies_hz[0] < 100
    free = modes(bat, count=4)
    # springs at the handle stiffen the bat: its first flexural mode rises, but stays near
    assert free.frequencies_hz[2] < gripped.frequencies_hz[2] < 1.2 * free.frequencies_hz[2]
    assert gripped.modal_damping().shape == (4, 4)
