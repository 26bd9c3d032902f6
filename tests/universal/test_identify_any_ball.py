"""`identify --ball-diameter-m`: a test of a ball of another size and mass, made by similarity
from the cricket-ball sample (times x R / R0, forces x (m / R) / (m0 / R0) at the same speed),
is identified as the same dimensionless ball, and the ball written has the tested size and
mass (docs/universal.md, "Any solid ball")."""

from __future__ import annotations

import json
from importlib import resources

import numpy as np
import pytest

from ballimpact.cli import main

R0, M0 = 0.036, 0.16
SPEED, REBOUND = 20.8, 11.44


def _sample() -> np.ndarray:
    path = resources.files("ballimpact").joinpath("data/sample_impact.csv")
    return np.loadtxt(str(path), delimiter=",", comments="#", skiprows=5)


def _write(folder, name: str, radius_m: float, mass_kg: float):
    """The sample test of the cricket ball mapped to a ball of `radius_m`, `mass_kg`."""
    d = _sample()
    t = d[:, 0] * radius_m / R0
    f = d[:, 1] * (mass_kg / radius_m) / (M0 / R0)
    path = folder / f"{name}.csv"
    np.savetxt(path, np.column_stack([t, f]), delimiter=",", header="time_s,force_n",
               comments="")
    path.with_suffix(".json").write_text(json.dumps(
        {"mass_kg": mass_kg, "impact_speed_m_s": SPEED, "rebound_speed_m_s": REBOUND}))
    return path


#: The sample is a Hunt-Crossley pulse, not a universal ball: its FE check misses the default
#: tolerances (exit 3, issue 39); these tests are about the mapping between ball sizes.
LOOSE = ["--max-nrmse", 0.2, "--max-cor-error", 0.2, "--max-contact-time-error", 0.3,
         "--max-peak-force-error", 0.3]


def _identify(capsys, *argv) -> dict:
    capsys.readouterr()
    loose = [] if "--no-verify" in argv else LOOSE
    assert main(["identify", *map(str, argv), *map(str, loose), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("any_ball")


def test_a_similar_golf_core_is_the_same_dimensionless_ball(folder, capsys):
    cricket = _identify(capsys, _write(folder, "cricket", R0, M0))
    core = _identify(capsys, _write(folder, "core", 0.0195, 0.035), "--ball-diameter-m", 0.039)
    assert core["groups"] == pytest.approx(cricket["groups"], rel=1e-9)
    # the FE check runs the core on the study's mesh scaled to it: a similar run, so the same
    # dimensionless verification
    for key in ("force_nrmse", "cor_simulated"):
        assert core["verification"][key] == pytest.approx(cricket["verification"][key], rel=1e-6)
    ratio = core["verification"]["contact_time_simulated_s"] \
        / cricket["verification"]["contact_time_simulated_s"]
    assert ratio == pytest.approx(0.0195 / R0, rel=1e-6)  # times scale with R at one speed
    layer = core["ball"]["layers"][0]
    assert layer["outer_radius_m"] == pytest.approx(0.0195, rel=1e-12)
    volume = 4 / 3 * np.pi * 0.0195 ** 3
    assert layer["density_kg_m3"] * volume == pytest.approx(0.035, rel=1e-12)
    # moduli by the density ratio, tau1 by the radius ratio (the ball's own constants)
    density_ratio = layer["density_kg_m3"] / cricket["ball"]["layers"][0]["density_kg_m3"]
    assert core["params"]["mu0_pa"] == pytest.approx(cricket["params"]["mu0_pa"] * density_ratio,
                                                     rel=1e-9)
    assert core["params"]["tau1_s"] == pytest.approx(cricket["params"]["tau1_s"] * 0.0195 / R0,
                                                     rel=1e-9)
    assert core["ball_size"]["diameter_source"] == "given"


def test_no_diameter_for_another_mass_gives_a_note(folder, capsys):
    out = _identify(capsys, _write(folder, "light", R0, 0.14), "--no-verify")
    assert any("no ball diameter given" in w for w in out["warnings"])
    assert out["ball_size"]["mass_kg"] == pytest.approx(0.14)
    assert out["ball_size"]["diameter_m"] == pytest.approx(2 * R0)


def test_a_diameter_in_millimetres_is_refused(folder, bad_input):
    path = _write(folder, "mm", R0, M0)
    bad_input(["identify", path, "--ball-diameter-m", 72], "--ball-diameter-m",
              "looks like millimetres", "0.072")


def test_a_ball_of_no_plausible_density_is_refused(folder, bad_input):
    path = _write(folder, "hollow", 0.2, 0.16)  # 0.4 m across, 160 g: 4.8 kg/m^3
    bad_input(["identify", path, "--ball-diameter-m", 0.4], "density", "outside")
