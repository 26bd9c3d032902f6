"""`video.check_mass` and `video.write_side_file` (issue 40 item 2: the `video` command's mass
check and side file in the library), called from Python."""

import json
import math

import pytest

from ballimpact.errors import InputError
from ballimpact.records.loaders import read_side_file
from ballimpact.video import check_mass, write_side_file

#: a measurement's summary: 20 m/s at 30 degrees in, 12 m/s at 40 degrees out
SUMMARY = {"impact_speed_m_s": 20.0, "rebound_speed_m_s": 12.0,
           "impact_speed_normal_m_s": 20.0 * math.cos(math.radians(30)),
           "impact_speed_tangential_m_s": 20.0 * math.sin(math.radians(30)),
           "rebound_speed_normal_m_s": 12.0 * math.cos(math.radians(40)),
           "rebound_speed_tangential_m_s": 12.0 * math.sin(math.radians(40))}


def test_check_mass_takes_ball_masses_and_names_grams():
    assert check_mass(0.16) == 0.16
    with pytest.raises(InputError, match=r"--mass-kg 160 kg is outside .* looks like grams; "
                                         r"use 0\.16"):
        check_mass(160.0)
    for bad in (0.0, -0.1, math.nan):
        with pytest.raises(InputError, match=r"--mass-kg = .*(allowed range|expected a finite "
                                             r"number in) \(0, inf\) kg"):
            check_mass(bad)


def test_write_side_file_gives_the_normal_speeds_and_the_mass(tmp_path):
    path = write_side_file(tmp_path / "test1.json", SUMMARY, 0.16, source="ballimpact video v.mp4")
    assert path == str(tmp_path / "test1.json")
    side = json.loads((tmp_path / "test1.json").read_text())
    assert side["source"] == "ballimpact video v.mp4" and side["mass_kg"] == 0.16
    assert side["impact_speed_m_s"] == pytest.approx(17.3205081, rel=1e-8)
    assert side["rebound_speed_m_s"] == pytest.approx(9.19253332, rel=1e-8)
    assert side["impact_angle_deg"] == pytest.approx(30.0, abs=1e-12)
    assert side["rebound_angle_deg"] == pytest.approx(40.0, abs=1e-12)
    assert side["impact_speed_total_m_s"] == 20.0
    assert (tmp_path / "test1.json").read_text().endswith("}\n")
    assert read_side_file(tmp_path / "test1.json")["impact_speed_m_s"] == pytest.approx(17.3205081)
