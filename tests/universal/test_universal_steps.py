"""The library calls behind `ballimpact identify` and `ballimpact universal run|train|report`
(issue 40 item 2): `by_speed.speed_groups` and `identify_tests`, and `steps.design_config`,
`run_design`, `train_model` and `held_out`, called from Python."""

import json
from importlib import resources

import numpy as np
import pytest

from ballimpact import load_record, process
from ballimpact.errors import InputError
from ballimpact.universal import steps
from ballimpact.universal.by_speed import identify_tests, speed_groups
from ballimpact.universal.study import load_dataset
from ballimpact.universal.model import load_model

COARSE = 4e-3  # m: a coarse mesh keeps the study to seconds
KEYS = ("c10_pa", "c01_pa", "g1", "tau1_s", "mu0_pa")


def repeat(folder, name, seed, mass_kg=None):
    """The built-in sample test (20.8 m/s) with 1% white noise of its peak, seeded, processed."""
    data = resources.files("ballimpact").joinpath("data")
    d = np.loadtxt(str(data / "sample_impact.csv"), delimiter=",", comments="#", skiprows=5)
    force = d[:, 1] + np.random.default_rng(seed).normal(0.0, 0.01 * d[:, 1].max(), len(d))
    path = folder / f"{name}.csv"
    np.savetxt(path, np.column_stack([d[:, 0], force]), delimiter=",", header="time_s,force_n",
               comments="")
    side = json.loads((data / "sample_impact.json").read_text())
    path.with_suffix(".json").write_text(json.dumps(side))
    return path, process(load_record(path, mass_kg=mass_kg))


def test_identify_tests_groups_repeats_and_gives_the_speed_table(tmp_path):
    (a, pa), (b, pb) = repeat(tmp_path, "a", 1), repeat(tmp_path, "b", 2)
    assert speed_groups([pa, pb], [a, b]) == [pytest.approx(20.8)] * 2
    assert speed_groups([pa, pb], [a, b], [20.0]) == [20.0, 20.0]
    seen = []
    found = identify_tests([pa, pb], [a, b], load_model(), verify=False,
                           each=lambda path, f: seen.append(path))
    assert seen == [a, b] and found.groups == [pytest.approx(20.8)] * 2
    params = np.array([[f.params[k] for k in KEYS] for _, _, f in found.results])
    (group,) = found.repeats
    assert group["count"] == 2 and group["files"] == [str(a), str(b)]
    for j, key in enumerate(KEYS):
        assert group["params_mean"][key] == pytest.approx(params[:, j].mean(), rel=1e-12)
        assert group["params_sd"][key] == pytest.approx(params[:, j].std(ddof=1), rel=1e-9)
    out = found.to_dict()
    assert [f["file"] for f in out["identifications"]] == [str(a), str(b)]
    (row,) = out["table"]
    assert row["c10_pa"] == pytest.approx(params[:, 0].mean(), rel=1e-12)
    assert found.ball["speed_table"]["rows"] == out["table"]
    one = identify_tests([pa], [a], load_model(), verify=False)
    assert one.to_dict()["file"] == str(a) and "table" not in one.to_dict()
    assert one.ball == one.results[0][2].ball


def test_tests_of_one_command_are_of_one_ball(tmp_path):
    (a, pa), (b, pb) = repeat(tmp_path, "a", 1), repeat(tmp_path, "b", 2, mass_kg=0.145)
    with pytest.raises(InputError, match=r"mixed masses among the tests of one command"):
        speed_groups([pa, pb], [a, b])
    with pytest.raises(InputError, match="is not within 5% of any nominal speed"):
        speed_groups([pa], [a], [10.0])


def test_design_config_new_and_stored():
    config = steps.design_config(runs=4, seed=2, batch_size=2, element_size_m=COARSE,
                                 method=None)
    assert (config["runs"], config["seed"], config["batch_size"]) == (4, 2, 2)
    assert config["method"] == "sobol" and config["element_size_m"] == COARSE
    assert steps.design_config(stored=True, runs=None) is None  # nothing given: the stored one
    assert steps.design_config(stored=True, seed=3, runs=None) == {"seed": 3}
    ranged = steps.design_config(stored=True, ranges={"g1": (0.1, 0.5)})
    assert list(ranged) == ["ranges"] and ranged["ranges"]["g1"] == [0.1, 0.5]


def test_run_design_summarises_the_study_and_held_out_checks_the_study(tmp_path):
    summary = steps.run_design(tmp_path / "s", runs=2, batch_size=2, element_size_m=COARSE)
    assert (summary["runs"], summary["finished_runs"], summary["new_runs"]) == (2, 2, 2)
    columns, _ = load_dataset(tmp_path / "s")
    assert summary["failed_runs"] == int(np.sum(columns["status"] != "ok"))
    assert summary["failures"] == [] or summary["failures"][0]["reason"]
    assert summary["runs_per_s"] == pytest.approx(2 / summary["wall_time_s"])
    model, out = steps.held_out()
    assert out["model"] == "built-in" and out["held_out"] is model.metadata["held_out"]
    assert out["runs"] == model.metadata["runs"] and out["study"] == model.metadata["study"]
    assert out["held_out_check"] == model.metadata.get("held_out_check")  # None: an older model
    with pytest.raises(InputError, match="--closed-loop: .* is not the study this model was "
                                         "trained on"):
        steps.held_out(None, tmp_path / "s")


def test_train_model_saves_the_model_and_returns_its_figures(tmp_path, monkeypatch):
    builtin = load_model()  # a fresh instance: its metadata is this test's
    check = {"passed": True, "min_r2": 0.5, "forced": False}
    builtin.metadata["held_out_check"] = check  # as `training.train` records it
    given = {}

    def train(study, **settings):  # the training itself is tested in test_universal.py
        given.update(settings, study=study)
        return builtin, builtin.metadata["held_out"]

    monkeypatch.setattr(steps, "train", train)
    monkeypatch.setattr(steps, "load_config", lambda study: {})  # no study on disk
    out = steps.train_model(tmp_path / "study", tmp_path / "m", seed=1, steps=100, force=True)
    assert given == {"study": tmp_path / "study", "seed": 1, "steps": 100, "width": 128,
                     "members": 5, "noise_augment": 0.02, "force": True}
    assert out["model_json"].endswith("m.json") and out["model_npz"].endswith("m.npz")
    saved = load_model(tmp_path / "m")
    assert saved.metadata["held_out"] == json.loads(json.dumps(out["held_out"]))
    assert out["held_out_check"] == check == saved.metadata["held_out_check"]
    assert out["runs"] == builtin.metadata["runs"]
    assert out["wall_time_s"] == builtin.metadata["training"]["wall_time_s"]
