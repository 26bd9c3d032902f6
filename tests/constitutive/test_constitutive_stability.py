"""Drucker stability of incompressible Mooney-Rivlin sets (ABAQUS's material check)."""

import numpy as np
import pytest

from ballimpact.errors import InputError
from ballimpact.balls.ball import TABLE_7_3, BallModel, Layer, load_ball
from ballimpact.constitutive import MooneyRivlin, NeoHookean
from ballimpact.constitutive.stability import (
    MODES,
    drucker_warnings,
    long_term_mooney_rivlin,
    mode_stretches,
    mooney_rivlin_drucker,
    mooney_rivlin_stress_differences,
    mooney_rivlin_tangent,
)

SETS = [(4.72e6, -0.45e6), (4.5e6, -0.5e6), (1e6, -0.9e6), (1e6, 0.3e6), (0.2e6, 1e6)]


def fd_tangent(c10, c01, l1, l2, h=1e-6):
    """Central differences of t_i(e1, e2) in the logarithmic strains."""
    e = np.array([np.log(l1), np.log(l2)])
    d = np.empty((2, 2))
    for j in range(2):
        step = np.zeros(2)
        step[j] = h
        tp = mooney_rivlin_stress_differences(c10, c01, *(e + step))
        tm = mooney_rivlin_stress_differences(c10, c01, *(e - step))
        d[:, j] = (np.array(tp) - np.array(tm)) / (2 * h)
    return d


def full_stress_differences(c10, c01, l1, l2):
    """t_i from sigma_i = 2 C10 l_i^2 - 2 C01 l_i^-2 - p, written out independently (p = 0)."""
    lam = np.array([l1, l2, 1.0 / (l1 * l2)])
    sigma = 2 * c10 * lam ** 2 - 2 * c01 * lam ** -2.0
    return sigma[0] - sigma[2], sigma[1] - sigma[2]


@pytest.mark.parametrize("c10, c01", SETS)
def test_analytic_tangent_matches_finite_differences(c10, c01):
    rng = np.random.default_rng(1)
    for l1, l2 in rng.uniform(0.3, 3.0, size=(20, 2)):
        t = mooney_rivlin_stress_differences(c10, c01, np.log(l1), np.log(l2))
        assert np.allclose(t, full_stress_differences(c10, c01, l1, l2), rtol=1e-12, atol=1e-6)
        d = mooney_rivlin_tangent(c10, c01, l1, l2)
        assert np.allclose(d, fd_tangent(c10, c01, l1, l2), rtol=1e-6, atol=1e-6 * abs(d).max())
        assert d[0, 1] == d[1, 0]


def test_tangent_at_rest_is_the_shear_modulus():
    """At l = 1: D = 4 (C10 + C01) [[2, 1], [1, 2]], i.e. d(sigma_1 - sigma_3)/d(eps) = 3 mu0 in
    uniaxial tension (Young's modulus of an incompressible solid)."""
    d = mooney_rivlin_tangent(4.72e6, -0.45e6, 1.0, 1.0)
    mu0 = 2 * (4.72e6 - 0.45e6)
    assert np.allclose(d, 2 * mu0 * np.array([[2, 1], [1, 2]]), rtol=1e-14)
    # uniaxial: de2 = -de1 / 2 -> dt1 / de1 = D11 - D12 / 2 = 3 mu0
    assert d[0, 0] - 0.5 * d[0, 1] == pytest.approx(3 * mu0, rel=1e-14)


@pytest.mark.parametrize("c10, c01", [(1e6, 0.0), (4.72e6, 0.0), (1e6, 0.5e6), (1e6, 2e6),
                                      (0.2e6, 1e6), (0.0, 1e6)])
def test_positive_constants_are_stable_everywhere(c10, c01):
    assert mooney_rivlin_drucker(c10, c01, 0.02, 50.0) == []


def test_large_negative_c01_is_unstable_near_rest():
    out = mooney_rivlin_drucker(1e6, -0.9e6, 0.8, 1.25)
    assert {r["mode"] for r in out} == set(MODES)
    # stable in a neighbourhood of l = 1 only
    for r in out:
        assert r["stretch_to"] < 1.0 or r["stretch_from"] > 1.0
        assert 0.9 < r["stretch_to"] or r["stretch_from"] < 1.1


@pytest.mark.parametrize("c10, c01", [(4.72e6, -0.45e6), (4.5e6, -0.5e6), (1e6, -0.9e6),
                                      (6.12e6, -0.35e6)])
def test_edges_in_closed_form(c10, c01):
    """With C01 < 0: A_i = C10 l_i^2 + C01 l_i^-2 < 0 for l_i < r = (-C01 / C10)^(1/4).
    Equibiaxial compression fails exactly at l = r; uniaxial tension (lateral stretch l^-1/2)
    exactly at l = r^-2; equibiaxial at l equals uniaxial at l^-2; planar is symmetric in l, 1/l."""
    r = (-c01 / c10) ** 0.25
    out = mooney_rivlin_drucker(c10, c01, 0.05, 20.0, n=800)
    by_mode = {m: [(x["stretch_from"], x["stretch_to"]) for x in out if x["mode"] == m] for m in MODES}
    uni, equi, planar = by_mode["uniaxial"], by_mode["equibiaxial"], by_mode["planar"]
    assert len(uni) == len(equi) == len(planar) == 2
    assert equi[0][0] == 0.05 and equi[0][1] == pytest.approx(r, rel=1e-9)
    assert uni[1][1] == 20.0 and uni[1][0] == pytest.approx(r ** -2, rel=1e-9)
    assert equi[1][0] == pytest.approx(uni[0][1] ** -0.5, rel=1e-9)
    assert planar[1][0] == pytest.approx(1.0 / planar[0][1], rel=1e-9)


@pytest.mark.parametrize("c10, c01", SETS[:3])
def test_intervals_agree_with_eigenvalues_of_the_fd_tangent(c10, c01):
    """Independent check: at sample stretches, unstable <=> the finite-difference tangent (made
    symmetric) has a non-positive eigenvalue."""
    lo, hi = 0.3, 3.0
    out = mooney_rivlin_drucker(c10, c01, lo, hi)
    for mode in MODES:
        intervals = [(r["stretch_from"], r["stretch_to"]) for r in out if r["mode"] == mode]
        for lam in np.geomspace(lo, hi, 157):
            if any(abs(lam - e) < 1e-4 * lam for iv in intervals for e in iv):
                continue  # too close to an edge for a finite difference
            l1, l2, _ = (float(x) for x in mode_stretches(mode, lam))
            d = fd_tangent(c10, c01, l1, l2)
            eig = np.linalg.eigvalsh(0.5 * (d + d.T))
            if abs(eig.min()) < 1e-6 * abs(eig).max():
                continue  # marginal (C10 = 4.5, C01 = -0.5 in uniaxial tension at exactly 3)
            stable = eig.min() > 0
            inside = any(a <= lam <= b for a, b in intervals)
            assert stable != inside, (mode, lam)


# Unstable ranges of the thesis sets for stretches in [0.3, 3] (rounded to 1e-3).
THESIS = {
    (4.72e6, -0.45e6): [("equibiaxial", 0.3, 0.556), ("equibiaxial", 2.302, 3.0),
                        ("planar", 0.3, 0.320)],
    (4.5e6, -0.5e6): [("equibiaxial", 0.3, 0.577), ("equibiaxial", 2.138, 3.0),
                      ("planar", 0.3, 0.347), ("planar", 2.883, 3.0)],
    (5.24e6, -0.51e6): [("equibiaxial", 0.3, 0.559), ("equibiaxial", 2.279, 3.0),
                        ("planar", 0.3, 0.324)],
    (6.12e6, -0.35e6): [("equibiaxial", 0.3, 0.489), ("equibiaxial", 2.960, 3.0)],
    (4.75e6, -0.47e6): [("equibiaxial", 0.3, 0.561), ("equibiaxial", 2.260, 3.0),
                        ("planar", 0.3, 0.326)],
    (4.02e6, -0.41e6): [("equibiaxial", 0.3, 0.565), ("equibiaxial", 2.228, 3.0),
                        ("planar", 0.3, 0.332)],
}


@pytest.mark.parametrize("c10, c01", list(THESIS))
def test_thesis_sets(c10, c01):
    got = [(r["mode"], round(r["stretch_from"], 3), round(r["stretch_to"], 3))
           for r in mooney_rivlin_drucker(c10, c01, 0.3, 3.0)]
    assert got == THESIS[(c10, c01)]


def test_table_7_3_rows_are_the_thesis_sets():
    assert {(r["c10_pa"], r["c01_pa"]) for r in TABLE_7_3} <= set(THESIS)


def test_marginal_point_is_not_an_interval():
    """C10 = 4.5, C01 = -0.5: uniaxial tension is exactly marginal at l = 3 (A2 = A3 = 0)."""
    assert not [r for r in mooney_rivlin_drucker(4.5e6, -0.5e6, 0.3, 3.0) if r["mode"] == "uniaxial"]


def test_drucker_warnings_for_the_presets():
    ball = load_ball("cricket-3layer")
    msgs = drucker_warnings(ball, 0.3, 3.0)
    assert len(msgs) == 3 + 4
    assert all("midsole" not in m for m in msgs)  # hyperfoam is not checked
    assert sum("'core'" in m for m in msgs) == 3 and sum("'cover'" in m for m in msgs) == 4
    assert any("'core'" in m and "equibiaxial" in m and "0.3 to 0.5557" in m for m in msgs)
    # long-term and instantaneous constants differ by a positive factor: the same ranges
    inst = drucker_warnings(ball.with_moduli("instantaneous"), 0.3, 3.0)
    assert [m.split(") is ")[1] for m in inst] == [m.split(") is ")[1] for m in msgs]
    assert drucker_warnings(ball, 0.7, 1.5) == []
    universal = load_ball("cricket-universal", 10.0)
    assert len(drucker_warnings(universal, 0.3, 3.0)) == 2


def test_long_term_constants():
    m = MooneyRivlin(c10_pa=4e6, c01_pa=-1e6, moduli="instantaneous",
                     prony=load_ball("cricket-3layer").layers[0].material.prony)
    assert long_term_mooney_rivlin(m) == pytest.approx((4e6 * 0.59, -1e6 * 0.59), rel=1e-14)
    assert long_term_mooney_rivlin(NeoHookean(c10_pa=1e6)) == (1e6, 0.0)
    ball = BallModel("nh", (Layer("a", 0.03, 1000.0, NeoHookean(c10_pa=1e6)),))
    assert drucker_warnings(ball, 0.01, 100.0) == []


@pytest.mark.parametrize("args, key", [((0.0, 3.0), "stretch_min"), ((2.0, 1.0), "stretch_max"),
                                       ((0.5, float("inf")), "stretch_max")])
def test_bad_ranges(args, key):
    with pytest.raises(InputError, match=key):
        mooney_rivlin_drucker(1e6, 0.0, *args)
    with pytest.raises(InputError, match="mode = 'shear'"):
        mode_stretches("shear", 1.2)


# ---- every material: the general check from the material's own energy -------------------------
from ballimpact.constitutive import LinearElastic, material_from_dict  # noqa: E402
from ballimpact.constitutive.stability import (  # noqa: E402
    checked,
    drucker_unstable,
    stable_range,
    tangent,
)


def _intervals(out):
    return [(r["mode"], r["stretch_from"], r["stretch_to"]) for r in out]


@pytest.mark.parametrize("c10, c01", SETS + [(6.12e6, -0.35e6), (4.02e6, -0.41e6)])
def test_general_check_reproduces_the_analytic_mooney_rivlin(c10, c01):
    """The general path (jax on the material's energy) against the closed-form Mooney-Rivlin
    check: the same intervals to 1e-6 in stretch, t and D to 1e-9."""
    mat = MooneyRivlin(c10_pa=c10, c01_pa=c01)
    general = _intervals(drucker_unstable(mat, 0.05, 20.0))
    analytic = _intervals(mooney_rivlin_drucker(c10, c01, 0.05, 20.0))
    assert [g[0] for g in general] == [a[0] for a in analytic]
    np.testing.assert_allclose([g[1:] for g in general], [a[1:] for a in analytic], rtol=1e-6)
    for mode in MODES:
        lam = np.geomspace(0.2, 5.0, 9)
        t, d = tangent(mat, mode, lam)
        l1, l2, _ = mode_stretches(mode, lam)
        t_ref = np.stack(mooney_rivlin_stress_differences(c10, c01, np.log(l1), np.log(l2)), -1)
        d_ref = mooney_rivlin_tangent(c10, c01, l1, l2)
        np.testing.assert_allclose(t, t_ref, rtol=1e-9, atol=1e-9 * np.abs(t_ref).max())
        np.testing.assert_allclose(d, d_ref, rtol=1e-9, atol=1e-9 * np.abs(d_ref).max())


def test_general_check_keeps_the_marginal_point_and_the_thesis_sets():
    assert _intervals(drucker_unstable(MooneyRivlin(c10_pa=4.5e6, c01_pa=-0.5e6), 0.3, 3.0)) == [
        ("equibiaxial", 0.3, pytest.approx(0.5774, abs=1e-4)),
        ("equibiaxial", pytest.approx(2.138, abs=1e-3), 3.0),
        ("planar", 0.3, pytest.approx(0.3469, abs=1e-4)),
        ("planar", pytest.approx(2.883, abs=1e-3), 3.0)]
    for (c10, c01), rows in THESIS.items():
        got = [(m, round(a, 3), round(b, 3))
               for m, a, b in _intervals(drucker_unstable(MooneyRivlin(c10_pa=c10, c01_pa=c01),
                                                          0.3, 3.0))]
        assert got == rows


def _yeoh_reference(c10, c20, c30, l1, l2):
    """t_i = f'(I1) dI1/de_i and D_ij = f'' dI1/de_i dI1/de_j + f' d2I1/de_i de_j, written out:
    I1 = x1 + x2 + x3 with x_i = l_i^2, x3 = 1 / (x1 x2); dI1/de_i = 2 (x_i - x3),
    d2I1/de_i de_j = 4 x_i delta_ij + 4 x3."""
    x = np.array([l1 ** 2, l2 ** 2])
    x3 = 1.0 / (x[0] * x[1])
    y = x.sum() + x3 - 3
    f1 = c10 + 2 * c20 * y + 3 * c30 * y * y
    f2 = 2 * c20 + 6 * c30 * y
    g = 2 * (x - x3)
    return f1 * g, f2 * np.outer(g, g) + f1 * (4 * np.diag(x) + 4 * x3)


def _ogden_reference(terms, l1, l2):
    """t_i = sum 2 mu / a (l_i^a - l3^a), D_ij = sum 2 mu (l_i^a delta_ij + l3^a)."""
    lam = np.array([l1, l2])
    l3 = 1.0 / (l1 * l2)
    t = sum(2 * m / a * (lam ** a - l3 ** a) for m, a in terms)
    d = sum(2 * m * (np.diag(lam ** a) + l3 ** a) for m, a in terms)
    return t, d


YEOH_SOFT = {"model": "yeoh", "c10_pa": 1.0e6, "c20_pa": -0.1e6, "c30_pa": 0.002e6}
OGDEN_MIXED = {"model": "ogden", "terms": [{"mu_pa": 0.6e6, "alpha": 1.5},
                                           {"mu_pa": -0.2e6, "alpha": -1.0}]}


@pytest.mark.parametrize("spec", [YEOH_SOFT, OGDEN_MIXED])
def test_general_tangent_matches_closed_forms(spec):
    mat = material_from_dict(spec)
    for mode in MODES:
        lam = np.geomspace(0.3, 4.0, 7)
        t, d = tangent(mat, mode, lam)
        for k, (l1, l2, _) in enumerate(zip(*mode_stretches(mode, lam))):
            if spec["model"] == "yeoh":
                t_ref, d_ref = _yeoh_reference(1e6, -0.1e6, 0.002e6, l1, l2)
            else:
                t_ref, d_ref = _ogden_reference([(0.6e6, 1.5), (-0.2e6, -1.0)], l1, l2)
            np.testing.assert_allclose(t[k], t_ref, rtol=1e-9, atol=1e-9 * np.abs(t_ref).max())
            np.testing.assert_allclose(d[k], d_ref, rtol=1e-9, atol=1e-9 * np.abs(d_ref).max())


@pytest.mark.parametrize("spec", [YEOH_SOFT, OGDEN_MIXED])
def test_unstable_ranges_agree_with_closed_form_tangents(spec):
    """These sets are unstable somewhere in [0.1, 10]; at every sample, inside an interval <=>
    the closed-form tangent has a non-positive eigenvalue."""
    mat = material_from_dict(spec)
    out = drucker_unstable(mat, 0.1, 10.0)
    assert out  # unstable somewhere
    for mode in MODES:
        intervals = [(a, b) for m, a, b in _intervals(out) if m == mode]
        for lam in np.geomspace(0.1, 10.0, 131):
            if any(abs(lam - e) < 1e-6 * lam for iv in intervals for e in iv):
                continue
            l1, l2, _ = (float(v) for v in mode_stretches(mode, lam))
            if spec["model"] == "yeoh":
                d = _yeoh_reference(1e6, -0.1e6, 0.002e6, l1, l2)[1]
            else:
                d = _ogden_reference([(0.6e6, 1.5), (-0.2e6, -1.0)], l1, l2)[1]
            stable = np.linalg.eigvalsh(d).min() > 0
            assert stable != any(a <= lam <= b for a, b in intervals), (mode, lam)


def test_positive_yeoh_and_ogden_sets_are_stable_everywhere():
    for spec in ({"model": "yeoh", "c10_pa": 1e6, "c20_pa": 1e4, "c30_pa": 1e2},
                 {"model": "ogden", "terms": [{"mu_pa": 1e6, "alpha": 2.5},
                                              {"mu_pa": 1e4, "alpha": 8.0}]}):
        mat = material_from_dict(spec)
        assert drucker_unstable(mat, 0.02, 50.0) == []
        assert all(stable_range(mat, mode) == (0.05, 20.0) for mode in MODES)


@pytest.mark.parametrize("c10, c01", [(4.72e6, -0.45e6), (1e6, -0.9e6)])
def test_stable_range_in_closed_form(c10, c01):
    """Mooney-Rivlin with C01 < 0 (r = (-C01 / C10)^(1/4)): equibiaxial stable down to r,
    uniaxial stable up to r^-2 (thesis core set: only the compression edge lies in range)."""
    r = (-c01 / c10) ** 0.25
    mat = MooneyRivlin(c10_pa=c10, c01_pa=c01)
    low, high = stable_range(mat, "equibiaxial")
    assert low == pytest.approx(r, rel=1e-7)
    assert stable_range(mat, "uniaxial")[1] == pytest.approx(min(r ** -2, 20.0), rel=1e-7)
    # limits returned as they are where stable up to them (the core set in uniaxial)
    assert stable_range(MooneyRivlin(c10_pa=4.72e6, c01_pa=-0.45e6), "uniaxial", 0.9, 1.0) == (
        0.9, 1.0)


@pytest.mark.parametrize("alpha, mu, nu", [(4.0, 1e6, -0.2), (6.0, 0.5e6, -0.3)])
def test_hyperfoam_uniaxial_edge_in_closed_form(alpha, mu, nu):
    """One-term hyperfoam: in uniaxial stress the lateral stretch is l^-nu, and the Kirchhoff
    tangent 2 mu [diag(l_i^a) + b J^(-a b) 1 1^T] is positive definite (determinant lemma) iff
    1 + b (l^(-a (1 + nu)) + 2) > 0. For b < 0 (nu < 0) that fails where
    l^(-a (1 + nu)) > -(1 + 2 b) / b: in compression (for a > 0)."""
    mat = material_from_dict({"model": "ogden_hyperfoam",
                              "terms": [{"mu_pa": mu, "alpha": alpha, "nu": nu}]})
    b = nu / (1 - 2 * nu)
    edge = (-(1 + 2 * b) / b) ** (-1.0 / (alpha * (1 + nu)))
    low, high = stable_range(mat, "uniaxial", 0.05, 20.0)
    assert low == pytest.approx(edge, rel=1e-7) and high == 20.0
    # the state: lateral stresses zero, lateral stretch l^-nu; tangent as in closed form
    lam = np.array([0.5, 1.7])
    t, d = tangent(mat, "uniaxial", lam)
    for k, l1 in enumerate(lam):
        stretches = np.array([l1, l1 ** -nu, l1 ** -nu])
        J = stretches.prod()
        d_ref = 2 * mu * (np.diag(stretches ** alpha) + b * J ** (-alpha * b))
        np.testing.assert_allclose(d[k], d_ref, rtol=1e-9)
        assert np.abs(t[k, 1:]).max() < 1e-9 * abs(t[k, 0])


def test_preset_hyperfoam_is_stable_and_linear_elastic_is_not_checked():
    ball = load_ball("cricket-3layer")
    assert drucker_unstable(ball.layers[1].material, 0.05, 20.0) == []
    elastic = LinearElastic(youngs_modulus_pa=1e7, poissons_ratio=0.3)
    assert not checked(elastic)
    with pytest.raises(InputError, match="linear_elastic: not checked"):
        drucker_unstable(elastic, 0.5, 2.0)
    with pytest.raises(InputError, match="mode = 'shear'"):
        stable_range(ball.layers[0].material, "shear")
    with pytest.raises(InputError, match="must contain 1"):
        stable_range(ball.layers[0].material, "uniaxial", 1.5, 3.0)


def test_drucker_warnings_name_every_models_constants():
    prony = [{"g": 0.5, "tau_s": 1e-4}]
    layers = [("yeoh", {**YEOH_SOFT, "prony": prony, "moduli": "instantaneous"}),
              ("ogden", {**OGDEN_MIXED, "prony": prony, "moduli": "instantaneous"}),
              ("elastic", {"model": "linear_elastic", "youngs_modulus_pa": 1e7,
                           "poissons_ratio": 0.3})]
    ball = BallModel("b", tuple(Layer(name, 0.01 * (i + 1), 1000.0, material_from_dict(spec))
                                for i, (name, spec) in enumerate(layers)))
    msgs = drucker_warnings(ball, 0.1, 10.0)
    assert msgs and all("'elastic'" not in m for m in msgs)
    assert any("(yeoh, long-term C10 = 5e+05 Pa, C20 = -5e+04 Pa, C30 = 1000 Pa)" in m for m in msgs)
    assert any("(ogden, long-term mu_1 = 3e+05 Pa, alpha_1 = 1.5, mu_2 = -1e+05 Pa, "
               "alpha_2 = -1)" in m for m in msgs)
    # the instantaneous constants (twice the long-term ones here) give the same ranges
    inst = drucker_warnings(ball.with_moduli("long_term"), 0.1, 10.0)
    assert [m.split(") is ")[1] for m in inst] == [m.split(") is ")[1] for m in msgs]
