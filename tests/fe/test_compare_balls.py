"""`fe.runs.compare_balls` and `fe.sweep.check_balls` (the library side of `ballimpact
compare`), called from Python; the command's own tests are in tests/fe/test_sweep.py."""

import json

import pytest

from ballimpact.fe.runs import compare_balls
from ballimpact.fe.sweep import check_balls
from ballimpact.errors import InputError
from ballimpact.fe import SolverOptions, load_ball


def test_check_balls_refuses_one_ball_and_one_ball_twice(tmp_path, monkeypatch):
    with pytest.raises(InputError, match=r"give two or more balls to compare \(got 1\)"):
        check_balls(["cricket-universal"])
    path = tmp_path / "a.json"
    path.write_text("{}")
    monkeypatch.chdir(tmp_path)
    with pytest.raises(InputError, match=r"--ball: ./a.json is given twice \(as a.json\)"):
        check_balls(["a.json", "./a.json"])
    assert check_balls(("cricket-universal", "a.json")) == ["cricket-universal", "a.json"]


def test_a_ball_against_its_copy_differs_by_nothing(tmp_path):
    spec = load_ball("cricket-universal", impact_speed_m_s=10.0).to_dict()
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    for path in (a, b):
        path.write_text(json.dumps(spec))
    comparison = compare_balls([str(a), str(b)], [10.0], SolverOptions(element_size_m=3e-3))
    assert [s.label for s in comparison.sweeps] == [str(a), str(b)]
    rows = comparison.rows
    assert [r["ball"] for r in rows] == [str(a), str(b)]
    assert 0.3 < rows[0]["cor"] < 0.9 and rows[0]["peak_force_n"] > 1e3
    assert rows[1]["cor"] == rows[0]["cor"] and rows[1]["cor_difference"] == 0.0
    assert rows[1]["peak_force_difference_percent"] == 0.0
    out = comparison.to_dict()
    assert out["balls"] == [str(a), str(b)] and out["reference_ball"] == str(a)
    assert out["speeds_m_s"] == [10.0] and out["comparison"] == rows
    # the meshed ball's mass: the 3 mm mesh's polygonal sphere, within 1% of the ball's
    assert out["sweeps"][0]["mass_kg"] == pytest.approx(load_ball(spec).mass_kg, rel=0.01)
