"""Drucker stability of incompressible Mooney-Rivlin sets (ABAQUS's material check)."""

import numpy as np
import pytest

from ballimpact.errors import InputError
from ballimpact.fe.ball import TABLE_7_3, BallModel, Layer, load_ball
from ballimpact.fe.materials import MooneyRivlin, NeoHookean
from ballimpact.fe.materials.stability import (
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
