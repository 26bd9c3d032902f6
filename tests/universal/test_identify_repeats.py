"""`identify` with repeats at one speed: one identification per repeat, their mean and standard
deviation (the scatter carried into the parameters), the mean pulse's identification, and one
row per speed in the table and the ball (docs/universal.md, "Repeated tests")."""

from __future__ import annotations

import json
from importlib import resources

import numpy as np
import pytest

from ballimpact.cli import main

KEYS = ("c10_pa", "c01_pa", "g1", "tau1_s", "mu0_pa")


def _repeat(folder, name: str, seed: int) -> str:
    """The built-in sample test with 1% more white noise (of its peak), seeded."""
    path = resources.files("ballimpact").joinpath("data/sample_impact.csv")
    d = np.loadtxt(str(path), delimiter=",", comments="#", skiprows=5)
    rng = np.random.default_rng(seed)
    force = d[:, 1] + rng.normal(0.0, 0.01 * d[:, 1].max(), d[:, 0].size)
    out = folder / f"{name}.csv"
    np.savetxt(out, np.column_stack([d[:, 0], force]), delimiter=",", header="time_s,force_n",
               comments="")
    side = json.loads(resources.files("ballimpact").joinpath("data/sample_impact.json")
                      .read_text())
    out.with_suffix(".json").write_text(json.dumps(side))
    return str(out)


def test_repeats_give_mean_sd_and_the_mean_pulse(tmp_path, capsys):
    files = [_repeat(tmp_path, f"r{i}", seed) for i, seed in enumerate((1, 2, 3))]
    ball = tmp_path / "ball.json"
    capsys.readouterr()
    assert main(["identify", *files, "--no-verify", "--json", "--ball-out", str(ball)]) == 0
    out = json.loads(capsys.readouterr().out)
    each = np.array([[f["params"][k] for k in KEYS] for f in out["identifications"]])
    (group,) = out["repeats"]
    assert group["count"] == 3 and group["files"] == files
    assert group["speed_m_s"] == pytest.approx(20.8)
    for j, key in enumerate(KEYS):  # against an independent mean and SD of the three
        assert group["params_mean"][key] == pytest.approx(each[:, j].mean(), rel=1e-12)
        assert group["params_sd"][key] == pytest.approx(each[:, j].std(ddof=1), rel=1e-9)
    assert np.all(each.std(axis=0) > 0)  # the noise moved every parameter: a real scatter
    pulse = group["mean_pulse"]
    for key in KEYS:
        low, high = pulse["params_interval_90"][key]
        assert low <= pulse["params"][key] <= high
    # the mean pulse is less noisy than any repeat: its mu0 lies within the repeats' spread
    mu0 = each[:, -1]
    assert mu0.min() - 2 * mu0.std(ddof=1) <= pulse["params"]["mu0_pa"] \
        <= mu0.max() + 2 * mu0.std(ddof=1)
    # the table and the speed-table ball hold one row for the speed: the repeats' mean
    (row,) = out["table"]
    assert row["c10_pa"] == pytest.approx(group["params_mean"]["c10_pa"], rel=1e-12)
    written = json.loads(ball.read_text())
    assert len(written["speed_table"]["rows"]) == 1
