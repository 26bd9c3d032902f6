"""Quasi-static compression between two platens (`fe.compress`, `ballimpact compress`): Hertz for
a sphere between two plates, the impact's maximum approach from the work of the quasi-static
curve, the rate dependence of a viscoelastic ball and its two elastic limits, the CLI and its
bad input."""

import json
import math
import warnings

import numpy as np
import pytest

from ballimpact.fe import Hexahedral, Options3D, SolverOptions, compress, load_ball, simulate

R_M, DENSITY = 0.036, 1000.0
C10_PA = 1.0e6
MU_PA = 2.0 * C10_PA


def neo_hookean(nu=None, c10=C10_PA, prony=None, name="nh"):
    """A homogeneous neo-Hookean ball; nu sets D1 = 2 / K (None: D1 = 0, K = 20 mu)."""
    material = {"model": "neo_hookean", "c10_pa": c10}
    if nu is not None:
        mu = 2.0 * C10_PA  # D1 from the reference shear modulus, the same for every variant
        material["d1_per_pa"] = 2.0 / (2.0 * mu * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu)))
    if prony is not None:
        material["prony"] = prony
    return load_ball({"name": name, "layers": [{"outer_radius_m": R_M, "density_kg_m3": DENSITY,
                                                "material": material}]})


def hertz_force_n(deflection_m, nu):
    """Sphere between two plates: each contact approaches by D/2,
    F = 4/3 E* sqrt(R) (D/2)^(3/2), E* = E / (1 - nu^2), E = 2 mu (1 + nu)."""
    e_star = 2.0 * MU_PA * (1.0 + nu) / (1.0 - nu * nu)
    return 4.0 / 3.0 * e_star * math.sqrt(R_M) * (0.5 * np.asarray(deflection_m)) ** 1.5


#: 0.75 mm elements (5928): the contact radius sqrt(R D/2) spans 6-7 elements at D/2R = 1.5-2%.
#: Measured (reduced integration; full integration within 0.2% of it): nu 0.3 at D/2R = 1, 1.5,
#: 2, 2.5, 3%: -2.7%, -0.6%, +1.1%, +2.6%, +3.7% (below 1% the patch spans < 5 elements and the
#: penalty contact reads soft; above, Hertz's small-strain, half-space assumptions weaken).
#: K = 20 mu (nu 0.475): +2.2%, +3.4%, +4.3% at 1, 1.5, 2% (jagged by +-1% as surface nodes
#: enter the contact one by one): 3% holds for nu 0.3 only, 5% is asked of K = 20 mu
HERTZ_OPTIONS = SolverOptions(element_size_m=0.75e-3)
HERTZ_TOLERANCE = {0.3: 0.03, None: 0.05}


@pytest.mark.slow
@pytest.mark.parametrize("nu", [0.3, None])
def test_small_deflection_follows_hertz(nu):
    ball = neo_hookean(nu)
    # D = 2R x (1.25%, 1.5%, 1.75%, 2%) in 4 increments from 1% (the first increment's guess)
    result = compress(ball, 0.02 * 2 * R_M, steps=8, options=HERTZ_OPTIONS)
    poisson = 0.3 if nu is not None else (3 * 20 - 2) / (2 * (3 * 20 + 1))  # K = 20 mu
    d = result.deflection_m
    check = (d >= 0.0125 * 2 * R_M * (1 - 1e-9))
    errors = result.force_n[check] / hertz_force_n(d[check], poisson) - 1.0
    assert np.all(np.abs(errors) < HERTZ_TOLERANCE[nu]), errors
    assert result.max_force_imbalance < 1e-6  # both platens carry the same force
    assert np.all(np.diff(result.force_n) > 0)


def test_default_mesh_from_the_contact():
    """`compression_options`: both poles refined to 5-7 elements across the Hertz contact radius
    sqrt(R D / 2), pole sizes on a ladder (nearby deflections share a mesh), the stiff platen
    penalty; a contact wider than 5 coarse elements needs no refinement."""
    from ballimpact.fe.compression import CONTACT_ELEMENTS, compression_options
    from ballimpact.fe.options import COMPRESSION_PENALTY_SCALE

    ball = neo_hookean(0.3)
    d = 0.01 * 2 * R_M
    radius = math.sqrt(R_M * d / 2)
    options = compression_options(ball, d)
    assert options.both_poles and options.penalty_scale == COMPRESSION_PENALTY_SCALE
    assert radius / CONTACT_ELEMENTS / math.sqrt(2) < options.pole_element_size_m \
        <= radius / CONTACT_ELEMENTS
    assert compression_options(ball, 1.05 * d) == options
    wide = compression_options(ball, 0.05 * 2 * R_M)
    assert wide.pole_element_size_m is None and wide.element_size_m == SolverOptions().element_size_m


def test_user_mesh_that_leaves_the_contact_unresolved_is_warned():
    from ballimpact.errors import InputWarning

    with pytest.warns(InputWarning, match="contact not resolved.*spans 0.63 elements of 3 mm"):
        compress(neo_hookean(0.3), 0.0002, steps=1, options=SolverOptions(element_size_m=3e-3))


#: the reference: 20 elements across the contact radius at both poles, penalty 100 (10 elements
#: and penalty 30 move it by at most 0.3%, benchmarks/bench_compress_hertz.py)
def reference_options(deflection_m):
    radius = math.sqrt(R_M * deflection_m / 2)
    return SolverOptions(pole_element_size_m=radius / 20, both_poles=True, penalty_scale=100.0,
                         pole_zone_deg=max(math.degrees(2.5 * radius / R_M), 5.0))


@pytest.mark.slow
@pytest.mark.parametrize("nu", [0.3, 0.49])
def test_default_compression_resolves_the_contact(nu):
    """With no options, `compress` reads an elastic sphere within 1.5% of a converged reference
    at D / 2R = 1 and 2% (each a run of its own, as a user runs it; measured -1.3% to +0.5%),
    and within 2.5% of Hertz at 0.25%, where the sphere's finite size (which makes the
    converged solution stiffer than Hertz's half-space by about 0.4 sqrt(D / 2R)) is small
    (measured +2.0%)."""
    ball = neo_hookean(nu)
    for fraction in (0.01, 0.02):
        d = fraction * 2 * R_M
        default = compress(ball, d, steps=4).force_n[-1]
        reference = compress(ball, d, steps=4, options=reference_options(d)).force_n[-1]
        assert default == pytest.approx(reference, rel=0.015), fraction
    d = 0.0025 * 2 * R_M
    assert compress(ball, d, steps=4).force_n[-1] == pytest.approx(hertz_force_n(d, nu), rel=0.025)


#: the 3D geometry (hexahedra, a half model unless told): D / 2R = 5% of the nu 0.3 sphere
HEX_FRACTION = 0.05


def hex_curve(divisions, fraction=HEX_FRACTION, **settings):
    return compress(neo_hookean(0.3), fraction * 2 * R_M, steps=5,
                    geometry=Hexahedral(Options3D(divisions=divisions, **settings)))


def test_3d_geometry_for_the_platens():
    """`compression_geometry` on `Hexahedral`: the pole grading left None puts 3 elements across
    the platens' Hertz radius sqrt(R D / 2) (both poles: the O-grid grades every face alike),
    the platen penalty, float64 and no bulk viscosity, the half model; a grading given is kept,
    and one that leaves the contact unresolved is warned about."""
    from ballimpact.errors import InputWarning
    from ballimpact.fe.compression import compression_geometry
    from ballimpact.fe.hex.mesh import pole_spacing_m
    from ballimpact.fe.options import COMPRESSION_PENALTY_SCALE

    ball, d = neo_hookean(0.3), 0.02 * 2 * R_M
    radius = math.sqrt(R_M * d / 2)
    chosen = compression_geometry(ball, d, Hexahedral(Options3D(divisions=16)))
    o = chosen.options
    assert chosen.half and o.penalty_scale == COMPRESSION_PENALTY_SCALE
    assert o.precision == "float64" and o.bulk_viscosity_linear == 0.0
    spacing = pole_spacing_m(R_M, 16, o.pole_grading)
    assert radius / 3 * 0.99 < spacing <= radius / 3
    assert chosen.platen_element_m(ball) == pytest.approx(spacing)
    same = compression_geometry(ball, d, options=Options3D(divisions=16, pole_grading=5.0))
    assert same.options.pole_grading == 5.0
    with pytest.warns(InputWarning, match="contact not resolved"):
        compression_geometry(ball, d, Hexahedral(Options3D(divisions=8, pole_grading=1.0)))


def test_3d_compression_agrees_with_the_axisymmetric():
    """The same elastic sphere (nu 0.3) at D / 2R = 5% on the 3D half model of 10 divisions
    (2600 hexahedra, pole grading chosen for the platens): within 3% of the axisymmetric curve's
    end force on its default mesh (measured +1.7%; 8 divisions read +7.5%, docs/materials.md),
    both platens carrying the same force, the force rising."""
    d = HEX_FRACTION * 2 * R_M
    axisymmetric = compress(neo_hookean(0.3), d, steps=5)
    hexahedral = hex_curve(10)
    assert hexahedral.geometry == "3d" and axisymmetric.geometry == "axisymmetric"
    assert hexahedral.force_n[-1] == pytest.approx(axisymmetric.force_n[-1], rel=0.03)
    assert hexahedral.max_force_imbalance < 1e-9
    assert np.all(np.diff(hexahedral.force_n) > 0)


@pytest.mark.slow
def test_3d_half_model_equals_the_full_model():
    """The full 3D model, held only on the problem's mirror planes x = 0 and y = 0, gives the
    half model's curve (forces doubled) to 1e-9 (measured 1e-14)."""
    half = hex_curve(8)
    full = hex_curve(8, half=False)
    assert full.elements == 2 * half.elements
    np.testing.assert_allclose(full.force_n, half.force_n, rtol=1e-9)


@pytest.mark.slow
def test_3d_compression_converges_to_the_reference():
    """16 divisions at D / 2R = 2% (8192 hexahedra): within 2% of the converged axisymmetric
    reference (measured -1.2%; 12 divisions +1.9%)."""
    d = 0.02 * 2 * R_M
    reference = compress(neo_hookean(0.3), d, steps=4, options=reference_options(d))
    curve = compress(neo_hookean(0.3), d, steps=4,
                     geometry=Hexahedral(Options3D(divisions=16)))
    assert curve.force_n[-1] == pytest.approx(reference.force_n[-1], rel=0.02)


#: a 1.5 mm mesh (1482 elements): at 0.5 m/s the contact radius is 6.3 mm (4.2 elements)
IMPACT_OPTIONS = SolverOptions(element_size_m=1.5e-3, bulk_viscosity_linear=0.0,
                               bulk_viscosity_quadratic=0.0)


@pytest.mark.slow
def test_impact_approach_from_quasi_static_work():
    """An elastic ball as stiff as a cricket ball's long-term core (C10 4 MPa) at 1 m/s: the
    centre's largest approach in the explicit impact equals the
    one-platen approach a* at which the work of the quasi-static curve, int_0^a* F_c(2a) da,
    equals the kinetic energy (a = D/2: each platen of the two-platen test approaches the
    centre by half the deflection)."""
    c10, nu = 4.0e6, 0.3
    bulk = 2.0 * c10 * 2.0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu))
    ball = load_ball({"name": "stiff", "layers": [{
        "outer_radius_m": R_M, "density_kg_m3": DENSITY,
        "material": {"model": "neo_hookean", "c10_pa": c10, "d1_per_pa": 2.0 / bulk}}]})
    speed = 1.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        impact = simulate(ball, speed, IMPACT_OPTIONS)
    z = impact.history["centre_z_m"]
    approach = z[0] - z.min()
    curve = compress(ball, 2.6 * approach, steps=26, options=IMPACT_OPTIONS)
    # work over one platen's approach a = D/2: int F(2a) da = 1/2 int F(D) dD (trapezoidal)
    d, f = curve.deflection_m, curve.force_n
    work = 0.5 * np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(d))])
    energy = 0.5 * impact.mass_kg * speed ** 2
    assert work[-1] > energy
    a_star = 0.5 * np.interp(energy, work, d)
    # measured: a* / approach = 1.025 (a* 1.138 mm against 1.111 mm; peak 227 N in the
    # impact, 219 N on the curve at D = 2 a*). A softer ball (C10 1 MPa) at 1 m/s reads 1.035:
    # under inertial loading the far side is not indented as a second platen indents it, a
    # difference that grows with the deflection (1.9 mm there)
    assert a_star == pytest.approx(approach, rel=0.03)


#: a coarse 3 mm mesh (the curves are compared with each other on it); the penalty x100: the
#: impact solver's springs scale with each ball's instantaneous wave speed, so at scale 1 the
#: long-term elastic ball's softer springs alone moved its curve by up to 4% at this mesh
#: and the hourglass springs x0.2: they follow the instantaneous shear modulus, so at the
#: default 0.05 they kept a slowly loaded g = 0.5 ball 3% stiffer than its long-term limit
VISCO_OPTIONS = SolverOptions(element_size_m=3e-3, penalty_scale=100.0, hourglass_scale=0.01)
TAU_S, G = 1.0, 0.5  # a 1 s relaxation: the three rates are lab rates (2e-7 to 20 m/s)
VISCO_DEFLECTION_M = 2e-3


@pytest.fixture(scope="module")
def visco_curves():
    """The viscoelastic ball at three platen speeds (loading times 1e4, 1, 1e-4 tau) and its
    elastic limits: C10 (long-term, as given) and C10 / (1 - g) (instantaneous)."""
    ball = neo_hookean(0.45, prony=[{"g": G, "k": 0.0, "tau_s": TAU_S}], name="visco")
    rates = VISCO_DEFLECTION_M / (TAU_S * np.array([1e4, 1.0, 1e-4]))
    curves = [compress(ball, VISCO_DEFLECTION_M, rate_m_s=r, steps=6, options=VISCO_OPTIONS)
              for r in rates]
    long_term = compress(neo_hookean(0.45, name="lt"), VISCO_DEFLECTION_M, steps=6,
                         options=VISCO_OPTIONS)
    instantaneous = compress(neo_hookean(0.45, c10=C10_PA / (1 - G), name="inst"),
                             VISCO_DEFLECTION_M, steps=6, options=VISCO_OPTIONS)
    relaxed = compress(ball, VISCO_DEFLECTION_M, steps=6, options=VISCO_OPTIONS)
    return curves, long_term, instantaneous, relaxed


def test_viscoelastic_curve_between_its_limits(visco_curves):
    curves, long_term, instantaneous, relaxed = visco_curves
    ends = np.array([c.force_n[-1] for c in curves])
    assert np.all(np.diff(ends) > 0), ends  # stiffer at every higher rate
    assert ends[-1] / ends[0] > 1.3  # and markedly so (g = 0.5)
    mid = slice(2, None)  # from 1/3 of the deflection (the forces near 0 are tiny)
    np.testing.assert_allclose(curves[0].force_at(long_term.deflection_m[mid]), long_term.force_n[mid], rtol=0.02)
    np.testing.assert_allclose(curves[-1].force_at(instantaneous.deflection_m[mid]),
                               instantaneous.force_n[mid], rtol=0.02)
    # without a rate: the long-term curve itself (the contact springs follow the instantaneous
    # wave speed, as in the impact solver: 0.5% apart at penalty x100)
    np.testing.assert_allclose(relaxed.force_at(long_term.deflection_m[mid]), long_term.force_n[mid], rtol=0.005)


def test_result_output(visco_curves):
    result = visco_curves[0][2]
    out = result.to_dict()
    assert out["deflection_m"][-1] == pytest.approx(VISCO_DEFLECTION_M)
    assert len(out["force_n"]) == len(out["deflection_m"]) == 7
    assert out["time_s"][-1] == pytest.approx(VISCO_DEFLECTION_M / result.rate_m_s)
    summary = result.summary()
    assert summary["peak_force_n"] == pytest.approx(max(out["force_n"]))
    f, d = out["force_n"], out["deflection_m"]
    assert summary["end_stiffness_n_m"] == pytest.approx((f[-1] - f[-2]) / (d[-1] - d[-2]))
    json.dumps(summary)


def test_cli_json_csv_plot(tmp_path, capsys):
    from ballimpact.cli import main

    ball = tmp_path / "ball.json"
    ball.write_text(json.dumps({"name": "nh", "layers": [{
        "outer_radius_m": R_M, "density_kg_m3": DENSITY,
        "material": {"model": "neo_hookean", "c10_pa": C10_PA}}]}))
    csv, png = tmp_path / "c.csv", tmp_path / "c.png"
    code = main(["compress", "--ball", str(ball), "--deflection-m", "0.002", "--steps", "4",
                 "--element-size-m", "0.003", "--json", "--csv", str(csv), "--plot", str(png)])
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    assert len(out["force_n"]) == len(out["deflection_m"]) == 5
    assert out["deflection_m"][-1] == pytest.approx(0.002)
    assert out["peak_force_n"] == pytest.approx(out["force_n"][-1])
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert csv.read_text().splitlines()[0] == "deflection_m,force_n"
    np.testing.assert_allclose(data[:, 1], out["force_n"], rtol=1e-9)
    assert png.stat().st_size > 1000


def test_cli_3d(tmp_path, capsys):
    from ballimpact.cli import main

    code = main(["compress", "--ball", "cricket-3layer", "--deflection-m", "0.004", "--steps",
                 "2", "--solver", "3d", "--divisions", "4", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["geometry"] == "3d"
    assert out["force_n"][-1] > out["force_n"][1] > 0


@pytest.mark.parametrize("argv, fragments", [
    (["--deflection-m", "0"], ["deflection_m = 0: allowed range (0, 0.036] m"]),
    (["--deflection-m", "-0.001"], ["deflection_m", "allowed range (0, 0.036] m"]),
    (["--deflection-m", "5"], ["deflection_m", "millimetres given as metres", "0.005 m"]),
    (["--deflection-m", "0.05"], ["deflection_m", "above the ball's radius"]),
    (["--deflection-m", "0.08"], ["deflection_m", "diameter"]),
    (["--deflection-m", "0.002", "--rate-m-s", "0"], ["rate_m_s = 0: allowed range (0, 80] m/s"]),
    (["--deflection-m", "0.002", "--rate-m-s", "500"], ["rate_m_s = 500", "mm/s given as m/s"]),
    (["--deflection-m", "0.002", "--steps", "0"], ["steps = 0: allowed range [1, inf)"]),
    (["--deflection-m", "0.002", "--csv", "/nonexistent/x.csv"], ["--csv", "does not exist"]),
    (["--deflection-m", "0.002", "--divisions", "8"], ["--divisions", "--solver 3d"]),
    (["--deflection-m", "0.002", "--solver", "3d", "--element-size-m", "0.002"],
     ["--element-size-m", "--divisions"]),
    (["--deflection-m", "0.002", "--solver", "3d", "--divisions", "5"], ["divisions = 5"]),
    (["--deflection-m", "0.002", "--solver", "3d", "--pole-grading", "100"],
     ["pole_grading = 100", "allowed range [1, 40]"]),
    (["--deflection-m", "0.002", "--full-model"], ["--full-model", "--solver 3d"]),
])
def test_bad_input(bad_input, argv, fragments):
    bad_input(["compress", "--ball", "cricket-3layer", *argv], *fragments)
