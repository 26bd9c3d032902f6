"""`universal run|train|report` (and `identify --model`) against a real user's mistakes and
damaged files: each case exits 2 with one line naming the flag or file and what is wrong, before
anything is meshed, trained or written. Tampered models are copies of the built-in one; studies
are written here with synthetic rows (no FE runs)."""

import json
import os
import pickle
import shutil
from pathlib import Path

import numpy as np
import pytest

from ballimpact.cli import main
from ballimpact.fe.speed_range import FE_SPEED_RANGE_M_S as SPEEDS
from ballimpact.universal import space
from ballimpact.universal.dataset import COLUMNS, PULSE_SAMPLES, SHAPE_POINTS, batch_paths, \
    write_batch
from ballimpact.universal.model import BUILTIN, model_paths
from ballimpact.universal.study import batch_count, batch_ids, make_config, samples

COARSE = 4e-3
SAMPLE = Path(__file__).parents[2] / "src" / "ballimpact" / "data" / "sample_impact.csv"


# -- tampered copies of the built-in model ----------------------------------------------------

@pytest.fixture(scope="module")
def builtin():
    npz, meta = model_paths(BUILTIN)
    with np.load(npz) as data:
        arrays = {k: data[k] for k in data.files}
    return json.loads(meta.read_text()), arrays


def write_model(folder, name, metadata, arrays, *, json_text=None):
    """MODEL.json (the metadata, or `json_text` as it is) and MODEL.npz; returns MODEL.json."""
    (folder / f"{name}.json").write_text(json.dumps(metadata) if json_text is None else json_text)
    np.savez(folder / f"{name}.npz", **arrays)
    return folder / f"{name}.json"


def report(model, *flags):
    return ["universal", "report", model, *flags]


def test_untouched_copy_loads(builtin, tmp_path, capsys):
    """The copies below differ from a good model only in what each case breaks."""
    path = write_model(tmp_path, "copy", *builtin)
    assert main([str(a) for a in report(path, "--json")]) == 0
    capsys.readouterr()


def test_truncated_npz(builtin, tmp_path, bad_input):
    path = write_model(tmp_path, "m", *builtin)
    data = (tmp_path / "m.npz").read_bytes()
    (tmp_path / "m.npz").write_bytes(data[:len(data) // 2])
    bad_input(report(path), "m.npz", "truncated")


def test_corrupted_bytes_inside_the_npz(builtin, tmp_path, bad_input):
    path = write_model(tmp_path, "m", *builtin)
    data = bytearray((tmp_path / "m.npz").read_bytes())
    middle = len(data) // 2
    data[middle:middle + 64] = bytes(64)
    (tmp_path / "m.npz").write_bytes(bytes(data))
    bad_input(report(path), "m.npz")


def test_npz_missing_an_array(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    path = write_model(tmp_path, "m", meta, {k: v for k, v in arrays.items() if k != "inverse_003"})
    bad_input(report(path), "m.npz", "inverse_003 missing")


def test_npz_array_of_the_wrong_shape(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    path = write_model(tmp_path, "m", meta,
                       {**arrays, "inverse_003": arrays["inverse_003"][:, :12]})
    bad_input(report(path), "m.npz", "inverse_003", "(5, 12)", "expected")


def test_npz_array_of_the_wrong_dtype(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    path = write_model(tmp_path, "m", meta,
                       {**arrays, "feature_log": arrays["feature_log"].astype(float)})
    bad_input(report(path), "feature_log", "float64", "booleans")


def test_nan_weights(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    weights = arrays["forward_002"].copy()
    weights[0, 0, 0] = np.nan
    path = write_model(tmp_path, "m", meta, {**arrays, "forward_002": weights})
    bad_input(report(path), "m.npz", "forward_002", "non-finite")


def test_npz_with_a_foreign_array(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    path = write_model(tmp_path, "m", meta, {**arrays, "extra": np.zeros(3)})
    bad_input(report(path), "unexpected array extra")


class Trap:
    """Unpickling this creates a folder: the proof that a file was unpickled."""

    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        return (os.mkdir, (self.marker,))


def test_pickled_object_array_is_refused_unread(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    marker = tmp_path / "unpickled"
    trap = np.empty(1, dtype=object)
    trap[0] = Trap(marker)
    path = write_model(tmp_path, "m", meta, {**arrays, "inverse_000": trap})
    bad_input(report(path), "inverse_000", "pickle")
    assert not marker.exists()


def test_npz_that_is_a_pickle_is_refused_unread(builtin, tmp_path, bad_input):
    path = write_model(tmp_path, "m", *builtin)
    marker = tmp_path / "unpickled"
    (tmp_path / "m.npz").write_bytes(pickle.dumps(Trap(marker)))
    bad_input(report(path), "m.npz", "unpickling", "refused unread")
    assert not marker.exists()


def test_json_missing_ranges(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    path = write_model(tmp_path, "m", {k: v for k, v in meta.items() if k != "ranges"}, arrays)
    bad_input(report(path), "m.json", "'ranges' missing")


def test_json_with_a_range_that_is_not_numbers(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    path = write_model(tmp_path, "m", {**meta, "ranges": {**meta["ranges"], "g1": "0-0.9"}},
                       arrays)
    bad_input(report(path), "m.json", "ranges.g1", "low < high")


def test_json_garbage(builtin, tmp_path, bad_input):
    path = write_model(tmp_path, "m", *builtin, json_text="{not json")
    bad_input(report(path), "m.json", "not readable json")


def test_json_not_an_object(builtin, tmp_path, bad_input):
    path = write_model(tmp_path, "m", *builtin, json_text="[1, 2]")
    bad_input(report(path), "m.json", "list")


def test_json_of_another_format(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    path = write_model(tmp_path, "m", {**meta, "format": "ballimpact-universal-model/9"}, arrays)
    bad_input(report(path), "m.json", "format", "ballimpact-universal-model/1")


def test_architecture_that_disagrees_with_the_weights(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    arch = {**meta["architecture"], "inverse": {**meta["architecture"]["inverse"], "width": 64}}
    path = write_model(tmp_path, "m", {**meta, "architecture": arch}, arrays)
    bad_input(report(path), "inverse_000", "(5, 64, 19)")


def test_missing_model(tmp_path, bad_input):
    bad_input(report(tmp_path / "nothere"), "nothere.json", "not found")


def test_model_path_is_a_folder(tmp_path, bad_input):
    (tmp_path / "m.json").mkdir()
    bad_input(report(tmp_path / "m.json"), "m.json", "folder")


def test_identify_loads_models_through_the_same_checks(builtin, tmp_path, bad_input):
    meta, arrays = builtin
    path = write_model(tmp_path, "m", {k: v for k, v in meta.items() if k != "ranges"}, arrays)
    bad_input(["identify", SAMPLE, "--model", path, "--no-verify"], "m.json", "'ranges' missing")


# -- universal report's flags -------------------------------------------------------------------

@pytest.mark.parametrize("noise", ["-0.1", "1.5"])
def test_report_noise_out_of_range(noise, tmp_path, bad_input):
    fake_study(tmp_path / "s")
    bad_input(["universal", "report", "--closed-loop", tmp_path / "s", "--noise", noise],
              "--noise", "[0, 0.5)")


def test_report_noise_as_a_percentage_names_the_slip(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    bad_input(["universal", "report", "--closed-loop", tmp_path / "s", "--noise", "1"],
              "--noise = 1", "looks like a percentage: use 0.01")


def test_report_plot_suffix(tmp_path, bad_input):
    bad_input(["universal", "report", "--plot", tmp_path / "r.pdf"], "--plot", ".png")


def test_report_closed_loop_flag_without_closed_loop(bad_input):
    bad_input(["universal", "report", "--noise", "0.01"], "--noise", "--closed-loop")


def test_report_closed_loop_runs_zero(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    bad_input(["universal", "report", "--closed-loop", tmp_path / "s", "--runs", "0"],
              "--runs = 0: allowed range [1, inf)")


def test_report_unknown_filter(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    bad_input(["universal", "report", "--closed-loop", tmp_path / "s", "--noise", "0.01",
               "--filter", "smooth"], "--filter", "smooth", "loess")


def test_closed_loop_against_another_study(tmp_path, bad_input):
    fake_study(tmp_path / "other", ranges={"impact_speed_m_s": (10.0, 30.0)})
    bad_input(["universal", "report", "--closed-loop", tmp_path / "other"],
              "not the study this model was trained on", "ranges", "cricket-2048")


def test_closed_loop_study_is_a_file(tmp_path, bad_input):
    (tmp_path / "s").write_text("x")
    bad_input(["universal", "report", "--closed-loop", tmp_path / "s"], "--closed-loop",
              "is a file")


# -- studies written here, without FE runs -----------------------------------------------------

def fake_study(folder, *, runs=8, batch_size=4, features=None, **settings):
    """A study folder of `runs` finished runs whose outputs are synthetic (random, positive): the
    layout `universal run` writes, for checks that never reach the FE engine."""
    config = make_config(runs=runs, batch_size=batch_size, element_size_m=COARSE, **settings)
    folder.mkdir(parents=True)
    (folder / "study.json").write_text(json.dumps(config))
    points = samples(config)
    rng = np.random.default_rng(0)
    for batch in range(batch_count(config)):
        ids = list(batch_ids(config, batch))
        rows = []
        for i in ids:
            row = {key: float(rng.uniform(0.1, 1.0)) for key in COLUMNS}
            row.update(zip(space.PARAMETERS, map(float, points[i])))
            row.update(run_id=i, batch=batch, status="ok", reason="", warnings="",
                       mu0_pa=2 * (row["c10_pa"] + row["c01_pa"]))
            rows.append(row)
        write_batch(folder, batch, rows, {
            "run_id": np.array(ids), "force_shape": rng.uniform(0, 1, (len(ids), SHAPE_POINTS)),
            "force_n_100khz": rng.uniform(0, 1, (len(ids), PULSE_SAMPLES))})
    return config


def run(folder, *flags):
    return ["universal", "run", folder, "--element-size-m", COARSE, *flags]


@pytest.mark.parametrize("flags, fragments", [
    (["--runs", "0"], ["--runs = 0: allowed range [1, inf)"]),
    (["--runs", "-5"], ["--runs = -5"]),
    (["--workers", "0"], ["--workers = 0: allowed range [1, inf) (Dask processes)"]),
    (["--batch-size", "0"], ["--batch-size = 0"]),
    (["--group-size", "0"], ["--group-size = 0", "[1, inf)"]),
    (["--seed", "-1"], ["--seed = -1: allowed range [0, inf)"]),
    (["--range", "g1=0.5:0.2"], ["g1", "LOW < HIGH", "swapped"]),
    (["--range", "c10_pa=4e6:4e6"], ["c10_pa", "LOW < HIGH"]),
    (["--range", f"impact_speed_m_s=5:{SPEEDS[1] + 10:g}"],
     ["impact_speed_m_s HIGH", f"allowed range [{SPEEDS[0]:g}, {SPEEDS[1]:g}] m/s"]),
    (["--range", "c01_pa=-5e6:1e6"], ["c01_pa", "mu0"]),
    (["--range", "g1=0.2"], ["--range", "LOW:HIGH"]),
    (["--workers", "2", "--scheduler", "tcp://x:1"], ["--workers", "--scheduler", "give one"]),
    (["--extend", "0"], ["--extend = 0: allowed range [1, inf)"]),
    (["--extend", "10", "--runs", "100"], ["--extend", "--runs", "give one"]),
    (["--extend", "8"], ["--extend", "does not exist"]),
    (["--allow", "ballunits"], ["allow", "ballunits", "ball-units"]),
])
def test_run_flags(flags, fragments, tmp_path, bad_input):
    bad_input(run(tmp_path / "s", *flags), *fragments)
    assert not (tmp_path / "s").exists()  # refused before anything was written


def test_run_element_size_beyond_the_mesher(tmp_path, bad_input):
    bad_input(["universal", "run", tmp_path / "s", "--element-size-m", "0.03"],
              "element_size_m", "radius / 2")


def test_run_dir_is_a_file(tmp_path, bad_input):
    (tmp_path / "s").write_text("x")
    bad_input(run(tmp_path / "s"), "is a file")


def test_run_into_a_folder_holding_a_study(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    bad_input(run(tmp_path / "s"), "already holds a study", "--resume", "--extend")


def test_run_into_a_folder_holding_other_files(tmp_path, bad_input):
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "notes.txt").write_text("mine")
    bad_input(run(tmp_path / "s"), "not empty")


def test_resume_on_a_folder_without_a_study(tmp_path, bad_input):
    (tmp_path / "s").mkdir()
    bad_input(["universal", "run", tmp_path / "s", "--resume"], "--resume", "holds no study")


def test_resume_on_a_study_json_missing_ranges(tmp_path, bad_input):
    config = fake_study(tmp_path / "s")
    (tmp_path / "s" / "study.json").write_text(json.dumps(
        {k: v for k, v in config.items() if k != "ranges"}))
    bad_input(["universal", "run", tmp_path / "s", "--resume"], "study.json", "'ranges' missing")


def test_extend_an_lhs_study(tmp_path, bad_input):
    fake_study(tmp_path / "s", method="lhs")
    bad_input(["universal", "run", tmp_path / "s", "--extend", "8"], "--extend", "lhs", "sobol")


# -- universal train --------------------------------------------------------------------------

def train(folder, tmp_path, *flags):
    return ["universal", "train", folder, "--out", tmp_path / "m", *flags]


def test_train_on_a_missing_study(tmp_path, bad_input):
    bad_input(train(tmp_path / "nothere", tmp_path), "nothere", "does not exist")


def test_train_on_a_file(tmp_path, bad_input):
    (tmp_path / "s").write_text("x")
    bad_input(train(tmp_path / "s", tmp_path), "is a file")


def test_train_on_a_study_without_runs(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    shutil.rmtree(tmp_path / "s" / "runs")
    bad_input(train(tmp_path / "s", tmp_path), "no finished runs", "universal run")


def test_train_on_too_few_runs(tmp_path, bad_input):
    fake_study(tmp_path / "s", runs=8)
    bad_input(train(tmp_path / "s", tmp_path), "8 successful runs", "at least 40",
              "--extend 592")


def test_train_on_garbage_study_json(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    (tmp_path / "s" / "study.json").write_text("{")
    bad_input(train(tmp_path / "s", tmp_path), "study.json", "not readable json")


def test_train_on_a_study_json_with_a_bad_value(tmp_path, bad_input):
    config = fake_study(tmp_path / "s")
    (tmp_path / "s" / "study.json").write_text(json.dumps({**config, "batch_size": 0}))
    bad_input(train(tmp_path / "s", tmp_path), "study.json", "batch_size", ">= 1")


def test_train_on_a_truncated_batch(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    parquet = batch_paths(tmp_path / "s", 1)[0]
    parquet.write_bytes(parquet.read_bytes()[:100])
    bad_input(train(tmp_path / "s", tmp_path), "batch-00001.parquet", "resume")


def test_train_on_a_batch_missing_its_curves(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    npz = batch_paths(tmp_path / "s", 0)[1]
    np.savez(npz, run_id=np.arange(4))
    bad_input(train(tmp_path / "s", tmp_path), "batch-00000.npz", "force_shape")


def test_train_on_curves_of_the_wrong_shape(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    npz = batch_paths(tmp_path / "s", 0)[1]
    np.savez(npz, run_id=np.arange(4), force_shape=np.zeros((4, 10)),
             force_n_100khz=np.zeros((4, PULSE_SAMPLES)))
    bad_input(train(tmp_path / "s", tmp_path), "batch-00000.npz", "(4, 10)", "(4, 64)")


def test_train_on_a_batch_of_another_design(tmp_path, bad_input):
    fake_study(tmp_path / "s", runs=8, batch_size=4)
    fake_study(tmp_path / "t", runs=8, batch_size=2)
    shutil.copy(batch_paths(tmp_path / "t", 1)[0], batch_paths(tmp_path / "s", 1)[0])
    bad_input(train(tmp_path / "s", tmp_path), "batch-00001.parquet", "run ids 2..3",
              "expected 4..7")


@pytest.mark.parametrize("flags, fragments", [
    (["--steps", "10"], ["--steps = 10: allowed range [100, inf)"]),
    (["--members", "0"], ["--members = 0"]),
    (["--width", "0"], ["--width = 0", "[1, inf)"]),
    (["--seed", "-1"], ["--seed = -1", "[0, inf)"]),
    (["--noise-augment", "0.7"], ["--noise-augment", "[0, 0.5)"]),
    (["--noise-augment", "2"], ["--noise-augment = 2", "looks like a percentage: use 0.02"]),
])
def test_train_flags(flags, fragments, tmp_path, bad_input):
    fake_study(tmp_path / "s")
    bad_input(train(tmp_path / "s", tmp_path, *flags), *fragments)


def test_train_out_is_a_folder(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    (tmp_path / "m").mkdir()
    bad_input(train(tmp_path / "s", tmp_path), "--out", "a folder", "model path")


def test_train_out_in_a_missing_folder(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    bad_input(["universal", "train", tmp_path / "s", "--out", tmp_path / "no" / "m"], "--out",
              "does not exist")


def test_train_refuses_a_model_that_fails_its_held_out_check(tmp_path, capsys):
    """Outputs that are noise cannot be learned: the model is refused (exit 2, nothing written,
    the worst output and the fix named); with --force it is written, marked failed, with a
    warning, and `universal report` warns about it too. Not `bad_input`: training prints its
    progress before the refusal."""
    fake_study(tmp_path / "s", runs=48, batch_size=16)
    argv = [str(a) for a in train(tmp_path / "s", tmp_path, "--steps", "100", "--width", "8",
                                  "--members", "2", "--noise-augment", "0", "--json")]
    capsys.readouterr()
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and "Traceback" not in err
    last = err.strip().splitlines()[-1]
    assert last.startswith("error: the model fails its held-out check"), last
    for fragment in ("held-out R^2", "needs >= 0.5", "--extend 552", "--force"):
        assert fragment in last, (fragment, last)
    assert not list(tmp_path.glob("m.*"))

    assert main(argv + ["--force"]) == 0
    result = json.loads(capsys.readouterr().out)
    check = result["held_out_check"]
    assert check["passed"] is False and check["forced"] is True
    assert check["r2"][check["worst"]] == min(check["r2"].values()) < 0.5
    assert f"{check['worst']} has held-out R^2" in result["warnings"][0]
    assert json.loads((tmp_path / "m.json").read_text())["held_out_check"] == check
    assert main(["universal", "report", str(tmp_path / "m.json"), "--json"]) == 0
    warned = json.loads(capsys.readouterr().out)["warnings"]
    assert any("failed its own held-out check" in w for w in warned)


def test_resume_with_another_run_count_points_to_extend(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    bad_input(run(tmp_path / "s", "--resume", "--runs", "12"), "--resume", "differs in runs",
              "--extend N")


SOFT = ["--range", "c10_pa=1e4:2e4", "--range=c01_pa=-9e3:0"]


def test_ranges_whose_balls_are_no_sports_balls_are_refused_before_any_run(bad_input, tmp_path):
    # each range allowed alone, but the softest corner has mu0 = 2 (C10 + C01) = 2 kPa
    bad_input(["universal", "run", tmp_path / "s", "--runs", "40", *SOFT], "c10_pa",
              "outside the shear moduli of sports balls", "--allow ball-units")
    assert not (tmp_path / "s").exists()


def test_a_foam_template_and_soft_ranges_run_with_allow_ball_units(tmp_path, bad_input, capsys,
                                                                    monkeypatch):
    """A foam ball (mu0 4 kPa, below sports balls) as the template: refused, then run with
    --allow ball-units, which the study keeps for its runs' balls (the FE runs are stubbed)."""
    import ballimpact.fe
    from ballimpact.fe import FailedRun
    from ballimpact.balls.ball import universal_spec

    foam = tmp_path / "foam.json"
    foam.write_text(json.dumps(universal_spec({"c10_pa": 2e3, "c01_pa": 0.0, "g1": 0.5,
                                               "tau1_s": 1e-4}, 0.036, 900.0, name="foam")))
    argv = run(tmp_path / "s", "--template", foam, *SOFT, "--runs", "2", "--batch-size", "2",
               "--json")
    bad_input(argv, "foam", "shear modulus", "--allow ball-units")
    assert not (tmp_path / "s").exists()

    loaded = []

    def stub(balls, speeds, options, **kw):
        loaded.extend(balls)  # run_batch loaded every run's ball (soft ones included)
        return [FailedRun(b.name, float(v), "stubbed") for b, v in zip(balls, speeds)]

    monkeypatch.setattr(ballimpact.fe, "simulate_batch", stub)
    assert main([str(a) for a in argv + ["--allow", "ball-units"]]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["failed_runs"] == 2 and len(loaded) == 2
    assert any(w.startswith("ball-units:") for w in result["warnings"])
    assert json.loads((tmp_path / "s" / "study.json").read_text())["allow"] == ["ball-units"]


def test_train_on_a_truncated_batch_npz(tmp_path, bad_input):
    fake_study(tmp_path / "s")
    npz = batch_paths(tmp_path / "s", 1)[1]
    npz.write_bytes(npz.read_bytes()[:200])  # what a truncated archive raises: BadZipFile
    bad_input(train(tmp_path / "s", tmp_path), "batch-00001.npz", "truncated",
              "delete batch-00001.parquet and resume")
