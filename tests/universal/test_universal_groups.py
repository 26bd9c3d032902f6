"""A universal model designed in the dimensionless groups (issue 42; docs/universal.md, "A study
in the groups"): the design's points, the transforms between constants and groups, a model's
inputs that do not depend on the ball's size or speed, and a small study of the groups from the
command line to an identified ball of another size (coarse and briefly trained: the plumbing;
the built-in model's figures are in test_universal_builtin.py)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from ballimpact.balls.ball import universal_spec
from ballimpact.cli import main
from ballimpact.errors import InputError
from ballimpact.fe import SolverOptions, load_ball, simulate
from ballimpact.records.features import FEATURE_NAMES, extract_features
from ballimpact.universal import space
from ballimpact.universal.design import (GROUPS_DESIGN, param_ranges_from_groups,
                                         params_from_groups)
from ballimpact.universal.model import load_model
from ballimpact.universal.similarity import GROUPS, BallSize, groups
from ballimpact.universal.study import make_config, samples

COARSE = 4e-3  # m


def test_constants_and_groups_are_inverse_maps():
    size = BallSize(0.0369, 0.145)
    for point in ({"rho_v2_over_mu0": 3e-3, "c01_over_c10": -0.2, "g1": 0.4,
                   "tau1_v_over_r": 0.05},
                  {"rho_v2_over_mu0": 0.2, "c01_over_c10": 0.25, "g1": 0.0,
                   "tau1_v_over_r": 5e-4}):
        params = params_from_groups(point, size, 33.0)
        assert params["mu0_pa"] == pytest.approx(2 * (params["c10_pa"] + params["c01_pa"]),
                                                 rel=1e-12)
        assert groups(params, size, 33.0) == pytest.approx(point, rel=1e-12)


def test_constant_ranges_of_a_box_hold_every_point_inside_it():
    size, speed = BallSize(0.02, 0.035), 40.0
    box = {"rho_v2_over_mu0": [1e-3, 0.1], "c01_over_c10": [-0.2, 0.1], "g1": [0.1, 0.6],
           "tau1_v_over_r": [1e-3, 0.3]}
    ranges = param_ranges_from_groups(box, size, speed)
    rng = np.random.default_rng(0)
    for _ in range(200):
        point = {k: rng.uniform(*v) for k, v in box.items()}
        for key, value in params_from_groups(point, size, speed).items():
            low, high = ranges[key]
            assert low * (1 - 1e-12) <= value <= high * (1 + 1e-12) or \
                low - 1e-9 <= value <= high + 1e-9, key


def test_a_study_of_the_groups_samples_its_box_at_its_run_speeds():
    config = make_config(design="groups", runs=64)
    assert config["design_space"] == "groups" and set(config["ranges"]) == set(GROUPS)
    assert "ball-units" in config["allow"]  # its balls' moduli are the groups' at a run speed
    points = samples(config)
    t = config["template"]
    size = BallSize(t["radius_m"], t["mass_kg"])
    back = np.array([list(groups(dict(zip(space.MATERIAL_PARAMETERS, p[:4])), size, p[4])
                          .values()) for p in points])
    for j, name in enumerate(GROUPS):
        low, high = config["ranges"][name]
        assert np.all((back[:, j] >= low * (1 - 1e-9)) & (back[:, j] <= high * (1 + 1e-9)))
    assert np.allclose(points[:, 4], space.run_speed(back[:, 0]))
    assert points[:, 4].min() >= 5.0 and points[:, 4].max() <= 60.0
    # the same seed gives the same points; the log groups are spread over their decades
    assert np.array_equal(points, samples(make_config(design="groups", runs=64)))
    assert np.median(back[:, 0]) < 0.02  # log axis: the middle of 2e-4..0.25 is 7e-3


@pytest.mark.parametrize("ranges, words", [
    ({"rho_v2_over_mu0": (1e-3, 0.5)}, "rho_v2_over_mu0 HIGH = 0.5: allowed range .* crushes"),
    ({"c10_pa": (1e6, 2e6)}, "unknown in a study of the groups"),
    ({"g1": (0.5, 0.2)}, "need finite LOW < HIGH"),
])
def test_bad_group_ranges_are_named(ranges, words):
    with pytest.raises(InputError, match=words):
        make_config(design="groups", ranges=ranges)


def test_similar_impacts_give_one_input_row():
    """The model's inputs of two similar impacts (another size, density and speed, the same
    groups) are one row: nothing in them depends on the ball's size or the speed."""
    rows = []
    for size, speed in ((BallSize(0.036, 0.16), 20.0), (BallSize(0.024, 0.07), 31.0)):
        point = {"rho_v2_over_mu0": 0.02, "c01_over_c10": 0.1, "g1": 0.5,
                 "tau1_v_over_r": 0.02}
        params = params_from_groups(point, size, speed)
        spec = universal_spec(params, size.radius_m, size.density_kg_m3, "long_term", "g")
        result = simulate(load_ball(spec, allow={"ball-units"}), speed,
                          SolverOptions(element_size_m=size.radius_m / 8, precision="float64"))
        values = extract_features(result.record()).values
        rows.append(GROUPS_DESIGN.inputs(np.array([[values[k] for k in FEATURE_NAMES]]),
                                         size)[0])
    assert rows[0] == pytest.approx(rows[1], rel=1e-5)


@pytest.fixture(scope="module")
def groups_model(tmp_path_factory):
    """A 64-run coarse study of the groups, trained briefly (--force: so short a training may
    fail the held-out check)."""
    folder = tmp_path_factory.mktemp("groups")
    assert main(["universal", "run", str(folder / "s"), "--design", "groups", "--runs", "64",
                 "--batch-size", "32", "--element-size-m", str(COARSE), "--json"]) == 0
    assert main(["universal", "train", str(folder / "s"), "--out", str(folder / "m"),
                 "--steps", "200", "--width", "32", "--force", "--json"]) == 0
    return folder


def test_groups_model_file_round_trips(groups_model):
    model = load_model(groups_model / "m.json")
    assert model.design.name == "groups" and "P15" not in model.design.features
    meta = json.loads((groups_model / "m.json").read_text())
    assert meta["targets"] == list(GROUPS) and set(meta["ranges"]) == set(GROUPS)
    assert set(meta["held_out"]["inverse"]) == set(GROUPS)
    x = np.array([[meta["feature_range"][k][0] * 1.01 for k in model.design.features]])
    assert np.array_equal(model.estimate(x)["values"],
                          load_model(groups_model / "m.npz").estimate(x)["values"])


def test_groups_model_identifies_a_ball_of_another_size(groups_model, capsys, tmp_path):
    """A test of a 60 mm, 0.1 kg ball at 15 m/s: identified with the groups model (no mapping
    onto its template), the ball written at the tested size, its constants and intervals
    inside the model's box as this ball at this speed sees it."""
    size, speed = BallSize(0.03, 0.1), 15.0
    params = params_from_groups({"rho_v2_over_mu0": 0.01, "c01_over_c10": 0.0, "g1": 0.5,
                                 "tau1_v_over_r": 0.02}, size, speed)
    spec = universal_spec(params, size.radius_m, size.density_kg_m3, "long_term", "t")
    test = simulate(load_ball(spec, allow={"ball-units"}), speed,
                    SolverOptions(element_size_m=COARSE * 30 / 36)).record()
    np.savetxt(tmp_path / "t.csv", np.column_stack([test.time_s, test.force_n]), delimiter=",",
               header="time_s,force_n", comments="")
    code = main(["identify", str(tmp_path / "t.csv"), "--model", str(groups_model / "m.json"),
                 "--mass-kg", "0.1", "--ball-diameter-m", "0.06", "--impact-speed-m-s", "15",
                 "--rebound-speed-m-s", str(test.rebound_speed_m_s), "--json"])
    out, err = capsys.readouterr()
    found = json.loads(out)
    assert code in (0, 3), err
    assert found["ball"]["layers"][0]["outer_radius_m"] == pytest.approx(0.03)
    assert set(found["groups"]) == set(GROUPS)
    for name in ("c10_pa", "c01_pa", "g1", "tau1_s", "mu0_pa"):
        low, high = found["params_interval_90"][name]
        t_low, t_high = found["training_range"][name]
        assert t_low - 1e-9 * abs(t_low) <= low <= found["params"][name] <= high \
            <= t_high + 1e-9 * abs(t_high), name
    for name, (low, high) in found["group_range"].items():
        assert low <= found["groups"][name] * (1 + 1e-9) and \
            found["groups"][name] <= high * (1 + 1e-9), name


def test_refine_surrogate_is_refused_for_a_groups_model(groups_model):
    from ballimpact.universal.identify import estimate_groups

    model = load_model(groups_model / "m.json")
    values = {k: 1.0 for k in FEATURE_NAMES}
    with pytest.raises(InputError, match="groups' design"):
        estimate_groups(model, values, BallSize(0.036, 0.16), refine="surrogate")


def test_builtin_sports_ball_model_held_out_figures():
    """The built-in model of the groups (4,096 runs, 817 held out): rho v^2 / mu0 (mu0 on a given
    ball and speed) to 3% of its value at the median, and calibrated 90% intervals that
    hold 85-95% of the held-out truths for every group (issue 42, item 2)."""
    model = load_model("sports-ball-universal-model")
    assert model.design.name == "groups"
    report = model.metadata["held_out"]
    assert report["runs"] >= 800
    inverse = report["inverse"]
    assert inverse["rho_v2_over_mu0"]["range_relative_error"]["median"] < 0.002
    assert inverse["rho_v2_over_mu0"]["relative_error"]["median"] < 0.03
    for name, entry in inverse.items():
        assert 0.85 <= entry["interval_90_coverage"] <= 0.95, name
    assert model.metadata["held_out_check"]["passed"]
    assert report["forward"]["cor_absolute_error"]["p90"] < 0.005


@pytest.mark.parametrize("argv, words", [
    (["--design", "groups", "--range", "c10_pa=1e6:2e6"], "unknown in a study of the groups"),
    (["--design", "groups", "--range", "rho_v2_over_mu0=1e-3:0.5"], "crushes"),
    (["--design", "cubes"], "invalid choice"),
])
def test_cli_bad_group_study_exits_2_with_one_line(argv, words, capsys, tmp_path):
    code = main(["universal", "run", str(tmp_path / "s"), *argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert words in err[-1]
    assert not (tmp_path / "s").exists()  # refused before anything is written
