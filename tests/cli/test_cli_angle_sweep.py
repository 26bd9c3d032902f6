"""The angle sweep of the 3D solver (issue 27): `ballimpact simulate --solver 3d --angle-deg
10,30,60`. One batched run equals the single runs, the normalised figures follow their
definitions, the elastic-sphere reference comes with a one-layer elastic ball (and not with a
viscoelastic or layered one), the files are written, and bad input is refused in one line.

The sweep runs once per module on a coarse mesh (8 divisions: about 35 s with its compilation
on 2 CPU cores, and about 16 s more for the single runs it is compared with)."""

import contextlib
import io
import json
import math

import numpy as np
import pytest

from ballimpact.cli import main
from ballimpact.oblique.sweep import parse_angles
from ballimpact.errors import InputError
from ballimpact.fe import Hexahedral, ImpactCondition, Options3D, load_ball, simulate
from ballimpact.oblique.elastic_reference import normalised_curves
from ballimpact.oblique.plots import rigid_gripping_lines
from ballimpact.oblique.sweep import ROW_FIELDS

R, RHO, E, NU = 0.036, 800.0, 1e8, 0.3
ELASTIC = {"model": "linear_elastic", "youngs_modulus_pa": E, "poissons_ratio": NU}
SPEED, FRICTION, ANGLES, DIVISIONS = 3.0, 0.3, (10.0, 30.0, 60.0), 8
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _ball_file(folder, material=ELASTIC):
    spec = {"name": "elastic-sphere", "layers": [{"name": "sphere", "outer_radius_m": R,
                                                   "density_kg_m3": RHO, "material": material}]}
    path = folder / "elastic-sphere.json"
    path.write_text(json.dumps(spec))
    return path


def _run(argv) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    """The JSON, table and plot of one sweep of the elastic ball (angles given unordered)."""
    folder = tmp_path_factory.mktemp("angle_sweep")
    ball = _ball_file(folder)
    table, plot = folder / "sweep.csv", folder / "sweep.png"
    code, out, err = _run(["simulate", "--solver", "3d", "--ball", ball, "--speed-m-s", SPEED,
                           "--angle-deg", "60,10,30", "--friction", FRICTION, "--divisions",
                           DIVISIONS, "--json", "--table", table, "--plot", plot])
    assert code == 0, err
    assert "3 angles (10, 30, 60 deg) in one batched run" in err
    return {"json": json.loads(out), "ball": ball, "table": table, "plot": plot}


def _normal_and_tangential(angle_deg):
    theta = math.radians(angle_deg)
    return SPEED * math.cos(theta), SPEED * math.sin(theta)


# ---- one batch equals the single runs ----------------------------------------------------------
@pytest.mark.filterwarnings("ignore:contact not resolved")  # the coarse mesh is the sweep's own
def test_sweep_rows_equal_single_runs(sweep):
    runs = sweep["json"]["runs"]
    assert [r["angle_deg"] for r in runs] == list(ANGLES)  # ascending
    ball = load_ball(sweep["ball"], impact_speed_m_s=SPEED)
    # the batch's mesh and penalty, chosen for its slowest normal speed (60 degrees)
    batch = Hexahedral(Options3D(divisions=DIVISIONS)).checked(
        ball, [ImpactCondition(SPEED, a, 0.0, FRICTION) for a in ANGLES], None)
    assert sweep["json"]["penalty_scale"] == batch.settings.penalty_scale
    assert sweep["json"]["pole_grading"] == pytest.approx(batch.settings.pole_grading, rel=1e-12)
    for row in runs:
        single = simulate(ball, ImpactCondition(SPEED, row["angle_deg"], 0.0, FRICTION),
                          geometry=Hexahedral(batch.settings))
        # vmapped and single runs do the same arithmetic: equal to round-off
        assert row["normal_cor"] == pytest.approx(single.normal_cor, rel=1e-9, abs=1e-12)
        assert row["tangential_cor"] == pytest.approx(single.tangential_cor, rel=1e-9, abs=1e-12)
        assert row["rebound_spin_rad_s"] == pytest.approx(single.rebound_spin_rad_s, rel=1e-9,
                                                          abs=1e-9)
        assert row["contact_point_tangential_cor"] == pytest.approx(
            single.contact_point_tangential_cor, rel=1e-9, abs=1e-12)
        assert row["steps"] == single.steps
    out = sweep["json"]
    assert out["elements"] == single.elements and out["half_model"] is True
    assert out["target"] == "rigid plane" and out["speed_m_s"] == SPEED
    assert out["friction"] == FRICTION and out["spin_rad_s"] == 0.0 and out["wall_time_s"] > 0


# ---- the normalised figures ---------------------------------------------------------------------
def test_normalised_figures_follow_their_definitions(sweep):
    """Psi = 2 v_x / (mu (1 + e_n) v_n), Omega = w' R / (mu (1 + e_n) v_n) from the run's
    velocities, and the exact kinematic identity e_cp = -e_t + 2 Omega / Psi (no initial spin);
    k^2 of a homogeneous sphere is 2/5."""
    out = sweep["json"]
    assert out["k2"] == pytest.approx(0.4, rel=1e-12)
    for row in out["runs"]:
        v_n, v_x = _normal_and_tangential(row["angle_deg"])
        scale = FRICTION * (1.0 + row["normal_cor"]) * v_n
        assert row["psi"] == pytest.approx(2.0 * v_x / scale, rel=1e-12)
        assert row["normalised_spin"] == pytest.approx(row["rebound_spin_rad_s"] * R / scale,
                                                       rel=1e-12)
        assert row["contact_point_tangential_cor"] == pytest.approx(
            -row["tangential_cor"] + 2.0 * row["normalised_spin"] / row["psi"], abs=1e-9)
        # the rebound angle from the CORs: tan(theta') = e_t v_x / (e_n v_n)
        assert math.tan(math.radians(row["rebound_angle_deg"])) == pytest.approx(
            row["tangential_cor"] * v_x / (row["normal_cor"] * v_n), rel=1e-9)
        assert row["energy_balance_error"] < 0.01 and row["peak_force_n"] > 0
        assert row["contact_time_s"] > 0


def test_reference_for_a_one_layer_elastic_ball(sweep):
    """nu from the small-strain moduli is the ball file's 0.3; the curves are
    `normalised_curves` on the stated grid, and in gross sliding the rigid-body limits
    Omega = 1 / k^2 = 2.5 and e_t = 1 - 2 / Psi."""
    out = sweep["json"]
    reference = out["reference"]
    assert reference is not None and "Maw" in reference["note"]
    assert reference["poissons_ratio"] == pytest.approx(NU, abs=1e-9)
    curves = {k: np.array(v) for k, v in reference["curves"].items()}
    top = max(12.0, 1.1 * max(r["psi"] for r in out["runs"]))
    grid = np.linspace(0.05, top, 200)
    assert curves["psi"] == pytest.approx(grid, rel=1e-6)  # e_n of the reference: 1 to round-off
    picks = [0, 90, 199]
    again = normalised_curves(grid[picks], NU)
    for key in ("normalised_spin", "tangential_cor", "contact_point_cor"):
        assert curves[key][picks] == pytest.approx(again[key], rel=1e-9, abs=1e-12)
    sliding = curves["psi"] > 8.0
    assert curves["normalised_spin"][sliding] == pytest.approx(2.5, abs=1e-6)
    assert curves["tangential_cor"][sliding] == pytest.approx(1 - 2 / curves["psi"][sliding],
                                                              abs=1e-6)


def test_plot_and_table_files(sweep):
    out = sweep["json"]
    assert out["plot"] == str(sweep["plot"])
    assert sweep["plot"].read_bytes()[:8] == PNG_MAGIC and sweep["plot"].stat().st_size > 20_000
    table = np.genfromtxt(sweep["table"], delimiter=",", names=True)
    assert list(table.dtype.names) == list(ROW_FIELDS)
    assert len(table) == len(ANGLES)
    for row, json_row in zip(table, out["runs"]):
        for name in ("angle_deg", "psi", "tangential_cor", "rebound_spin_rad_s", "peak_force_n"):
            assert row[name] == pytest.approx(json_row[name], rel=1e-9)  # 10 digits written


# ---- pure parts ----------------------------------------------------------------------------------
def test_rigid_gripping_lines_are_the_rigid_body_closed_forms():
    """Rolling: e_t = 1 / (1 + k^2) (Daish's 5/7), e_cp = 0; sliding: e_t = 1 - 2 / Psi,
    e_cp = -1 + 2 (1 + k^2) / (k^2 Psi); both meet at Psi = 2 (1 + k^2) / k^2."""
    for k2 in (0.4, 2.0 / 3.0):
        transition = 2 * (1 + k2) / k2
        rolling = np.linspace(0.1, transition * 0.99, 7)
        sliding = np.linspace(transition * 1.01, 30.0, 7)
        lines = rigid_gripping_lines(np.concatenate([rolling, sliding]), k2)
        n = len(rolling)
        assert lines["tangential_cor"][:n] == pytest.approx(1 / (1 + k2), rel=1e-12)
        assert lines["contact_point_cor"][:n] == pytest.approx(0.0, abs=1e-12)
        assert lines["normalised_spin"][:n] == pytest.approx(rolling / (2 * (1 + k2)), rel=1e-12)
        assert lines["tangential_cor"][n:] == pytest.approx(1 - 2 / sliding, rel=1e-12)
        assert lines["contact_point_cor"][n:] == pytest.approx(
            -1 + 2 * (1 + k2) / (k2 * sliding), rel=1e-12)


def test_parse_angles_keeps_order_and_names_the_range():
    assert parse_angles("5,10,20.5") == (5.0, 10.0, 20.5)
    assert parse_angles(" 0, 89") == (0.0, 89.0)
    for text, fragment in (("5,,10", "empty"), ("5,ten", "'ten' is not a number"),
                           ("10,10", "given twice"), ("10,95", "95"), ("-1,10", "-1"),
                           ("10,nan", "nan")):
        with pytest.raises(InputError, match=r"\[0, 89\] deg") as caught:
            parse_angles(text)
        assert fragment in str(caught.value)


# ---- bad input ------------------------------------------------------------------------------------
BASE = ("simulate", "--ball", "cricket-universal", "--speed-m-s", "10", "--solver", "3d",
        "--friction", "0.3")


@pytest.mark.parametrize("angles, fragment", [
    ("5,,10", "empty"), ("5,ten", "ten"), ("10,20,10", "given twice"), ("10,95", "95"),
    ("-5,10", "-5"), ("10,", "empty")])
def test_malformed_angle_lists_are_refused(bad_input, angles, fragment):
    bad_input([*BASE, f"--angle-deg={angles}"], "--angle-deg", "[0, 89]", fragment)


def test_sweep_refusals(bad_input, tmp_path):
    sweep = ("--angle-deg", "10,30")
    bad_input(["simulate", "--ball", "cricket-universal", "--speed-m-s", "10", *sweep],
              "--angle-deg", "needs --solver 3d")
    bad_input(["simulate", "--ball", "cricket-universal", "--speed-m-s", "5,10", "--solver", "3d",
               *sweep], "--speed-m-s", "one speed")
    bad_input([*BASE, *sweep, "--vtk", tmp_path / "run.pvd"], "--vtk", "one run", "--table")
    bad_input([*BASE, *sweep, "--animate", tmp_path / "run.gif"], "--animate", "one run")
    bad_input([*BASE, *sweep, "--csv", tmp_path / "run.csv"], "--csv", "one run")
    bad_input([*BASE, *sweep, "--table", tmp_path / "missing" / "t.csv"], "--table",
              "does not exist")
    bad_input([*BASE, *sweep, "--plot", tmp_path / "p.pdf"], "--plot", ".png")
    bad_input(["simulate", "--ball", "cricket-universal", "--speed-m-s", "10", "--solver", "3d",
               *sweep, "--plot", tmp_path / "p.png"], "--plot", "--friction")
    bad_input([*BASE, *sweep, "--element-size-m", "0.002"], "--element-size-m")
    bad_input([*BASE, *sweep, "--divisions", "7"], "divisions")


def test_single_angles_are_unchanged(bad_input):
    """One angle is still the run of one impact: its range is the solver's (`angle_deg`), and
    without --solver 3d it is refused as before."""
    bad_input([*BASE, "--angle-deg", "95"], "angle_deg")
    bad_input(["simulate", "--ball", "cricket-universal", "--speed-m-s", "10", "--angle-deg", "30"],
              "--angle-deg", "--solver 3d")
    bad_input([*BASE, "--angle-deg", "ten"], "--angle-deg", "not a number")


# ---- a ball without the reference (slow: its own compilation) ------------------------------------
@pytest.mark.slow
def test_universal_ball_sweep_has_no_reference():
    argv = ["simulate", "--solver", "3d", "--ball", "cricket-universal", "--speed-m-s", 10,
            "--angle-deg", "20,50", "--friction", 0.3, "--divisions", 6]
    code, out, err = _run([*argv, "--json"])
    assert code == 0, err
    result = json.loads(out)
    assert result["reference"] is None and "no elastic-sphere reference" in result[
        "reference_note"]
    assert [r["angle_deg"] for r in result["runs"]] == [20.0, 50.0]
    radius = load_ball("cricket-universal", 10.0).outer_radius_m
    for row in result["runs"]:
        v_n = 10 * math.cos(math.radians(row["angle_deg"]))
        scale = 0.3 * (1 + row["normal_cor"]) * v_n
        assert row["normalised_spin"] == pytest.approx(
            row["rebound_spin_rad_s"] * radius / scale, rel=1e-12)
    code, text, err = _run(argv)  # the text output says why there is no reference
    assert code == 0, err
    assert "no elastic-sphere reference: " in text and "Psi" in text
    assert len([line for line in text.splitlines() if line.strip()[:2] in ("20", "50")]) == 2
