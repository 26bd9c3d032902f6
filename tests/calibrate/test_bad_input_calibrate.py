"""`ballimpact calibrate` on a real user's mistakes (issue 24): each case fails before anything is
meshed or run, with exit code 2 and one line that names the flag, the value and the fix.

The test record is a half-sine pulse (a 0.16 kg ball at 20 m/s, COR 0.6, 0.5 ms contact) written
as a CSV with a JSON side file: processing it takes milliseconds, so no case runs the FE solver."""

from __future__ import annotations

import importlib
import json

import numpy as np
import pytest

MAT = "layers.ball.material."


@pytest.fixture(scope="module")
def record(tmp_path_factory, half_sine_record):
    return half_sine_record(tmp_path_factory.mktemp("calibrate-bad-input"), contact_s=5e-4)


def calibrate_argv(record, *extra, free=(MAT + "c10_pa=3e6:7e6",), test=None):
    argv = ["calibrate", "--ball", "cricket-universal", "--test", test or str(record)]
    for item in free:
        argv += ["--free", item]
    return argv + list(extra)


# ---- --free: paths and bounds -------------------------------------------------------------------
FREE_CASES = [
    # the case: MPa typed for a parameter in Pa (template 4.85e6 Pa)
    ([MAT + "c10_pa=1:4"], ["--free " + MAT + "c10_pa=1:4", "4.85148e+06 Pa",
                            "looks like MPa", "use 1e+06:4e+06"]),
    ([MAT + "c10_pa=3e9:7e9"], ["1000x too large", "use 3e+06:7e+06"]),
    ([MAT + "prony.0.tau_s=20:200"], ["7e-05 s", "looks like us", "use 2e-05:0.0002"]),
    (["layers.ball.density_kg_m3=0.7:0.9"], ["looks like g/cm3", "use 700:900"]),
    ([MAT + "prony.0.g=50:90"], ["looks like percent", "use 0.5:0.9"]),
    ([MAT + "c10_pa=10:20"], ["more than 100x from the bounds", "give them in Pa",
                              "--allow unit-slip"]),
    ([MAT + "c10_pa=3e6:7e6", MAT + "c10_pa=4e6:5e6"],
     ["--free: " + MAT + "c10_pa given twice", "3e6:7e6", "4e6:5e6"]),
    ([MAT + "c11_pa=3e6:7e6"], ["unknown parameter path", "did you mean " + MAT + "c10_pa?"]),
    (["layers.bal.material.c10_pa=3e6:7e6"], ["no entry 'bal'", "did you mean " + MAT + "c10_pa?"]),
    ([MAT + "c10_pa=7e6:3e6"], ["7e+06:3e+06", "reversed"]),
    ([MAT + "c10_pa=3e6:3e6"], ["reversed or equal"]),
    ([MAT + "prony.0.g=0.5:1.5"], ["the bound 1.5", "allowed range [0, 1)"]),
    (["layers.ball.density_kg_m3=-100:900"], ["the bound -100", "density_kg_m3"]),
    ([MAT + "prony.0.tau_s=0:1e-4"], ["the bound 0", "tau_s"]),
    ([MAT + "c10_pa=nan:7e6"], ["bounds must be finite"]),
    ([MAT + "c10_pa=3e6"], ["--free: expected NAME=LOW:HIGH", "c10_pa=3e6"]),
    ([MAT + "c10_pa=3e6:5e6:7e6"], ["expected NAME=LOW:HIGH"]),
    (["layers.ball.outer_radius_m=0.03:0.04"], ["radii are fixed"]),
    ([MAT + "model=0:1"], ["not a number"]),
]


@pytest.mark.parametrize("free, fragments", FREE_CASES,
                         ids=[f"{i}-{f[0].split('=')[0].rsplit('.', 1)[-1]}"
                              for i, (f, _) in enumerate(FREE_CASES)])
def test_bad_free_parameters(bad_input, record, free, fragments):
    bad_input(calibrate_argv(record, free=free), *fragments)


def test_bounds_in_another_unit_can_be_allowed():
    """Bounds far from the template's value are the `unit-slip` check: an error that names its
    override, and with `allow` a warning, the bounds kept as given (a search far from the
    template is the user's to choose)."""
    from ballimpact.calibrate import free_parameter
    from ballimpact.errors import InputError, InputWarning
    from ballimpact.balls.ball import UNIVERSAL_DENSITY_KG_M3, universal_spec

    spec = universal_spec({"c10_pa": 4.0e6, "c01_pa": -0.4e6, "g1": 0.7, "tau1_s": 8e-5},
                          0.036, UNIVERSAL_DENSITY_KG_M3)
    path = MAT + "prony.0.tau_s"  # 20:200 typed in us for 8e-5 s
    with pytest.raises(InputError, match="looks like us.*--allow unit-slip"):
        free_parameter(spec, path, 20.0, 200.0)
    with pytest.warns(InputWarning, match="^unit-slip: --free .*looks like us; use 2e-05:0.0002"):
        parameter = free_parameter(spec, path, 20.0, 200.0, allow={"unit-slip"})
    assert (parameter.low, parameter.high) == (20.0, 200.0)


# ---- --test ------------------------------------------------------------------------------------
def test_test_speed_not_a_number(bad_input, record):
    bad_input(calibrate_argv(record, test=f"{record}:fast"), "the speed 'fast' is not a number")


def test_test_speed_negative(bad_input, record):
    bad_input(calibrate_argv(record, test=f"{record}:-3"),
              "speed = -3: allowed range (0, inf) m/s")


def test_test_speed_nan(bad_input, record):
    bad_input(calibrate_argv(record, test=f"{record}:nan"),
              "speed = nan: expected a finite number")


def test_test_speed_outside_the_fe_range(bad_input, record, tmp_path):
    fast = tmp_path / "fast.csv"  # the record's pulse at 90 m/s (its impulse scaled with it)
    t, f = np.loadtxt(record, delimiter=",", skiprows=1, unpack=True)
    np.savetxt(fast, np.column_stack([t, 4.5 * f]), delimiter=",", header="time_s,force_n",
               comments="")
    fast.with_suffix(".json").write_text(json.dumps({"mass_kg": 0.16, "impact_speed_m_s": 90}))
    bad_input(calibrate_argv(record, test=str(fast)), "--test fast:", "90 m/s is outside",
              "--allow speed-range")


def test_test_layer_unknown(bad_input, record):
    bad_input(calibrate_argv(record, test=f"{record}:20:kernel"), "layers = 'kernel'",
              "have: ball")


def test_test_file_missing(bad_input, record):
    bad_input(calibrate_argv(record, test=str(record.parent / "nope.csv")), "nope.csv")


# ---- search and stage options ------------------------------------------------------------------
@pytest.mark.parametrize("extra, fragments", [
    (["--population", "0"], ["--population = 0: allowed range [4, inf)"]),
    (["--population", "3"], ["--population = 3: allowed range [4, inf) (NSGA-II needs pairs"]),
    (["--generations", "0"], ["--generations = 0: allowed range [1, inf)"]),
    (["--generations", "-2"], ["--generations = -2"]),
    (["--method", "nsga3"], ["--method", "invalid choice: 'nsga3'"]),
    (["--objectives", "nrmse,speed"], ["--objectives", "nrmse,speed"]),
    (["--weights", "1,a"], ["--weights", "comma-separated numbers"]),
    (["--weights", "1,-1"], ["--weights 1,-1", ">= 0"]),
    (["--stage", "frees=*c10_pa"], ["--stage", "keys free, tests, objectives, name"]),
    (["--stage", "tests=core"], ["--stage stage1: tests='core' is not a test", "have: ball"]),
    (["--stage", "free=layers.cover.*"], ["matches none of the --free paths"]),
    (["--stage", "name=a", "--stage", "name=a"], ["--stage name=a", "unique"]),
    (["--method", "gradient", "--max-evaluations", "0"],
     ["--max-evaluations = 0: allowed range [1, inf)"]),
    (["--method", "gradient", "--precision", "float32"], ["--precision float32", "float64"]),
], ids=lambda v: "_".join(v) if isinstance(v, list) and v and v[0].startswith("--") else None)
def test_bad_search_and_stage_options(bad_input, record, extra, fragments):
    bad_input(calibrate_argv(record, *extra), *fragments)


# ---- --out and --resume ------------------------------------------------------------------------
def test_out_is_a_file(bad_input, record, tmp_path):
    path = tmp_path / "result.json"
    path.write_text("{}")
    bad_input(calibrate_argv(record, "--out", path), f"--out {path}: is a file")


def test_out_in_a_missing_folder(bad_input, record, tmp_path):
    bad_input(calibrate_argv(record, "--out", tmp_path / "no" / "cal"), "--out",
              "does not exist")


def test_resume_without_out(bad_input, record):
    bad_input(calibrate_argv(record, "--resume"), "--resume: needs --out")


def test_resume_without_a_checkpoint(bad_input, record, tmp_path):
    bad_input(calibrate_argv(record, "--out", tmp_path, "--resume"),
              "--resume: no search to resume", "search.json")


def test_resume_of_a_gradient_refinement(bad_input, record, tmp_path):
    bad_input(calibrate_argv(record, "--out", tmp_path, "--resume", "--method", "gradient"),
              "--method gradient keeps no checkpoint")


def test_out_holding_a_search_needs_resume(bad_input, record, tmp_path):
    (tmp_path / "calibration").mkdir()
    (tmp_path / "calibration" / "search.json").write_text("{}")
    bad_input(calibrate_argv(record, "--out", tmp_path), "holds a search already",
              "add --resume")


@pytest.mark.parametrize("text, fragments", [
    ('{"free": [{"path": "x", "lo', ["search.json is damaged", "delete"]),
    ("[1, 2]", ["not a search manifest", "not a JSON object"]),
    ('{"free": []}', ["not a search manifest", "no objectives"]),
    ('{"free": 3, "objectives": [], "tests": [], "template": "", "solver": {}, "seed": 0, '
     '"population": 6}', ["not a search manifest", "free: expected a list"]),
])
def test_a_damaged_manifest_is_named(bad_input, record, tmp_path, text, fragments):
    (tmp_path / "calibration").mkdir()
    manifest = tmp_path / "calibration" / "search.json"
    manifest.write_bytes(text.encode())
    bad_input(calibrate_argv(record, "--out", tmp_path, "--resume"), str(manifest), *fragments)


# ---- --resume on a search started with other options, or a damaged checkpoint -------------------
SEARCH = ("--population", "4", "--generations", "2", "--seed", "2", "--element-size-m", "4e-3")


@pytest.fixture
def started(record, tmp_path, monkeypatch, capsys):
    """A search stopped (Ctrl-C) before its first FE run: its manifest is written, nothing run.
    Returns (out folder, the argv that started it)."""
    from ballimpact.cli import main

    # the module (the package's `search` is the function of the same name)
    search_module = importlib.import_module("ballimpact.calibrate.search")

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    out = tmp_path / "cal"
    argv = calibrate_argv(record, "--out", out, *SEARCH)
    with monkeypatch.context() as patch:
        patch.setattr(search_module, "evaluate", interrupted)
        assert main([str(a) for a in argv]) == 130
    capsys.readouterr()
    assert (out / "calibration" / "search.json").exists()
    return out, argv


@pytest.mark.parametrize("change, fragments", [
    (("--seed", "3"), ["search.json is a search with other options", "--seed 2 (now 3)"]),
    (("--population", "6"), ["--population 4 (now 6)"]),
    (("--element-size-m", "5e-3"), ["solver option element_size_m 0.004 (now 0.005)"]),
    (("--objectives", "nrmse,cor"), ["objectives nrmse,cor,contact_time (now nrmse,cor)"]),
])
def test_resume_with_other_options(bad_input, started, change, fragments):
    out, argv = started
    argv = list(argv)
    flag, value = change
    if flag in argv:
        argv[argv.index(flag) + 1] = value
    else:
        argv += [flag, value]
    bad_input(argv + ["--resume"], *fragments, "resume with the options it was started with")


def test_resume_with_other_bounds(bad_input, started, record):
    _, argv = started
    argv = [MAT + "c10_pa=3e6:6e6" if a == MAT + "c10_pa=3e6:7e6" else a for a in argv]
    bad_input(argv + ["--resume"], f"bounds of {MAT}c10_pa 3e+06:7e+06 (now 3e+06:6e+06)")


def test_resume_with_another_test_record(bad_input, started, record, tmp_path):
    _, argv = started
    other = tmp_path / "ball.csv"  # the same name, a different pulse
    t, f = np.loadtxt(record, delimiter=",", skiprows=1, unpack=True)
    np.savetxt(other, np.column_stack([t, 1.1 * f]), delimiter=",", header="time_s,force_n",
               comments="")
    (tmp_path / "ball.json").write_text((record.parent / "ball.json").read_text())
    argv = [str(other) if a == str(record) else a for a in argv]
    bad_input(argv + ["--resume", "--impulse-tolerance", "0.2"],
              "other data in test ball (its record or processing changed)")


def _write_parquet(path, columns):
    import pyarrow as pa
    import pyarrow.parquet as pq

    pq.write_table(pa.table(columns), path)


def _checkpoint_columns(u=0.5, generation=0):
    columns = {"generation": [generation], f"u:{MAT}c10_pa": [u],
               f"{MAT}c10_pa": [3e6 + u * 4e6], "nrmse": [0.1], "cor": [0.01],
               "contact_time": [0.02], "failed": [""]}
    for key in ("force_nrmse", "cor_error", "contact_time_relative_error",
                "peak_force_relative_error"):
        columns[f"ball:{key}"] = [0.1]
    return columns


@pytest.mark.parametrize("write, fragments", [
    (lambda path: path.write_bytes(b"PAR1\x00\x01 truncated"), ["cannot be read", "damaged"]),
    (lambda path: path.write_text("generation,failed\n0,\n"), ["cannot be read"]),
    (lambda path: _write_parquet(path, {"x": [1.0]}),
     ["not this search's checkpoint", "no column 'generation'"]),
    (lambda path: _write_parquet(path, {**_checkpoint_columns(), "nrmse": ["low"]}),
     ["a column that is not numbers"]),
    (lambda path: _write_parquet(path, _checkpoint_columns(u=1.5)),
     ["unit coordinates outside [0, 1]"]),
    (lambda path: _write_parquet(path, {**_checkpoint_columns(), f"{MAT}c10_pa": [1.0]}),
     ["other bounds of " + MAT + "c10_pa"]),
], ids=["truncated", "csv", "wrong-columns", "words", "unit-range", "values"])
def test_a_damaged_checkpoint_is_named(bad_input, started, write, fragments):
    out, argv = started
    path = out / "calibration" / "evaluations.parquet"
    write(path)
    bad_input(argv + ["--resume"], f"--resume: {path}", *fragments)
