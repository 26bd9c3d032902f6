"""`ballimpact bat` (docs/equipment.md, "Ball on bat"): JSON keys, the sweep and its plot, the
printed lines, bad input in one line naming the flag. A direct Hunt-Crossley law (no FE run)."""

import json

import pytest

from ballimpact.cli import main

BALL = "hc:0.145188:2.009e7:0.019749"  # the FE baseball's law at 61 m/s before its
# recalibration (now about hc:0.145188:2.114e7:0.019646); any such law serves these tests
BASE = ["bat", "--bat", "baseball-wood-34in", "--ball", BALL, "--speed-m-s", "61"]


def _json(capsys, argv):
    assert main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_one_point_json(capsys):
    out = _json(capsys, BASE + ["--impact-m", "0.70", "--grip", "2e4:20", "--modes", "8"])
    for key in ("collision_efficiency", "batted_ball_speed_m_s", "bat_mass_kg",
                "mode_frequencies_hz", "ball_energy_lost_j", "bat_vibration_energy_j",
                "bat_rigid_energy_j", "energy_balance_error", "max_bending_stress_pa",
                "max_bending_stress_x_m", "warnings"):
        assert key in out, key
    assert set(out["bat_moment_of_inertia_kg_m2"]) == {"knob", "centre_of_mass"}
    assert set(out["contact_force"]) == {"time_s", "force_n"}
    assert set(out["hands_force"]) == {"time_s", "force_n", "velocity_m_s"}
    assert len(out["mode_frequencies_hz"]) == 8
    assert 0.1 < out["collision_efficiency"] < 0.3
    assert 0.0 < out["max_contact_rotation_rad"] < 0.1


def test_sweep_json_plot_and_printed_lines(capsys, tmp_path):
    png = tmp_path / "sweet.png"
    argv = BASE + ["--impact-m", "0.70:0.74:0.02", "--bat-speed-m-s", "10", "--pivot-m", "0.15",
                   "--modes", "6"]
    out = _json(capsys, argv + ["--plot", str(png)])
    assert [round(p["impact_m"], 6) for p in out["points"]] == [0.70, 0.72, 0.74]
    assert set(out["sweet_spot"]) >= {"max_efficiency_m", "least_vibration_m"}
    assert out["plot"] == str(png) and png.stat().st_size > 0
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "sweet spot: largest e_A" in text and "least vibration at" in text


@pytest.mark.parametrize("extra, fragments", [
    (["--impact-m", "0.95"], ["--impact-m", "off the bat"]),
    (["--impact-m", "0.7", "--pivot-m", "1.2"], ["--pivot-m", "beyond the bat"]),
    (["--impact-m", "0.74:0.70:0.01"], ["--impact-m", "STOP"]),
    (["--impact-m", "0.7:0.8"], ["--impact-m", "3 numbers"]),
    (["--impact-m", "0.7", "--bat-speed-m-s", "-3"],
     ["--bat-speed-m-s = -3: allowed range [0, inf) m/s"]),
    (["--impact-m", "0.7", "--support", "pivot"], ["--pivot-m"]),
])
def test_bad_input_is_one_line_naming_the_flag(bad_input, extra, fragments):
    bad_input(BASE + extra, *fragments)


def test_a_negative_speed_and_a_bad_law_are_refused(bad_input):
    argv = ["bat", "--bat", "baseball-wood-34in", "--ball", BALL, "--impact-m", "0.7"]
    bad_input(argv + ["--speed-m-s", "-5"], "--speed-m-s = -5: allowed range (0, inf) m/s")
    bad_input(["bat", "--bat", "baseball-wood-34in", "--ball", "hc:0.145:-1:0.02",
               "--speed-m-s", "61", "--impact-m", "0.7"], "--ball", "stiffness")


def test_unit_slips_are_named(bad_input):
    """A ball mass in grams and positions on the bat in millimetres: exit 2, one line naming the
    flag and the slip."""
    ball = ["bat", "--bat", "baseball-wood-34in", "--speed-m-s", "40"]
    bad_input(ball + ["--ball", "hc:145:2e7:0.02", "--impact-m", "0.7"],
              "--ball", "grams given as kg", "0.145")
    law = ball + ["--ball", "hc:0.145:2e7:0.02"]
    bad_input(law + ["--impact-m", "700"], "--impact-m", "off the bat", "millimetres", "0.7")
    bad_input(law + ["--impact-m", "0.7", "--pivot-m", "152"], "--pivot-m", "millimetres",
              "0.152")
    # just past the barrel's end (the 34 in bat is 0.864 m): off the bat, no millimetre hint
    line = bad_input(law + ["--impact-m", "0.95"], "--impact-m", "off the bat")
    assert "millimetres" not in line


@pytest.mark.parametrize("kwargs, fragments", [
    ({"modes": 1}, ["--modes", "[2, 200]"]),
    ({"grip": (2e4, -1.0)}, ["--grip damping = -1: allowed range [0, inf)"]),
    ({"pivot_m": -0.1}, ["--pivot-m", "beyond the bat"]),
])
def test_the_library_run_refuses_what_the_flags_would(kwargs, fragments):
    """`bats.ball_on_bat`, the command's one call, checks its plain arguments itself."""
    from ballimpact.bats import HuntCrossleyBall, ball_on_bat
    from ballimpact.errors import InputError

    with pytest.raises(InputError) as error:
        ball_on_bat("baseball-wood-34in", HuntCrossleyBall(0.145, 2e7, 0.02), 61.0, [0.7],
                    **kwargs)
    assert all(f in str(error.value) for f in fragments), str(error.value)
