"""A study survives Ctrl-C and grows: `universal run` interrupted (exit 130, one line saying how
to resume), interrupted again in the middle of writing a batch, resumed, and extended with
`--extend` must each end with the dataset of one uninterrupted run (tiny coarse studies)."""

import numpy as np
import pytest

from ballimpact.cli import main
from ballimpact import fileio
from ballimpact.universal import study
from ballimpact.universal.study import load_dataset

COARSE = 4e-3  # m: a coarse mesh keeps these studies to seconds
SMALL = ["--batch-size", "3", "--element-size-m", COARSE, "--json"]


def universal_run(folder, *flags):
    try:
        return main([str(a) for a in ("universal", "run", folder, *flags)])
    except KeyboardInterrupt:  # would end the whole test session
        pytest.fail("Ctrl-C escaped the command line: exit 130 and one line expected")


def assert_same_dataset(a_folder, b_folder):
    """Every column and curve equal (floats to 1e-12 relative), the runs' wall times aside."""
    (a, curves_a), (b, curves_b) = load_dataset(a_folder), load_dataset(b_folder)
    assert set(a) == set(b)
    for key in a:
        if key == "wall_time_s":
            continue
        if a[key].dtype.kind == "f":
            np.testing.assert_allclose(a[key], b[key], rtol=1e-12, atol=0, err_msg=key)
        else:
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    for key in ("run_id", "force_shape", "force_n_100khz"):
        np.testing.assert_allclose(curves_a[key], curves_b[key], rtol=1e-12, atol=0, err_msg=key)


def stderr_lines(err):
    """stderr without the progress bar's lines."""
    return [line for line in err.replace("\r", "\n").splitlines()
            if line.strip() and not line.lstrip().startswith("[")]


@pytest.fixture(scope="module")
def whole(tmp_path_factory):
    """The uninterrupted 6-run study (two batches of 3)."""
    folder = tmp_path_factory.mktemp("resume") / "whole"
    assert universal_run(folder, "--runs", 6, *SMALL) == 0
    return folder


def test_ctrl_c_exits_130_with_a_resume_line_and_resume_completes_the_study(
        whole, tmp_path, capsys, monkeypatch):
    folder = tmp_path / "cut"
    real = study.run_batch
    started = []

    def ctrl_c_after_first_batch(config, batch):
        if started:
            raise KeyboardInterrupt
        started.append(batch)
        return real(config, batch)

    monkeypatch.setattr(study, "run_batch", ctrl_c_after_first_batch)
    capsys.readouterr()
    code = universal_run(folder, "--runs", 6, *SMALL)
    out, err = capsys.readouterr()
    assert code == 130, err
    lines = stderr_lines(err)
    assert len(lines) == 1 and "Traceback" not in err, err
    assert f"ballimpact universal run {folder} --resume" in lines[0]
    assert out == ""
    # the first batch is on disk, whole; nothing half-written
    assert sorted(p.name for p in (folder / "runs").iterdir()) == [
        "batch-00000.npz", "batch-00000.parquet"]

    # Ctrl-C again while the second batch is being written: between its NPZ and its Parquet
    monkeypatch.setattr(study, "run_batch", real)
    real_replace = fileio.os.replace

    def ctrl_c_before_parquet(src, dst):
        if str(dst).endswith("batch-00001.parquet"):
            raise KeyboardInterrupt
        return real_replace(src, dst)

    monkeypatch.setattr(fileio.os, "replace", ctrl_c_before_parquet)
    assert universal_run(folder, "--resume", "--json") == 130
    assert study.done_batches(folder) == {0}  # the half-written batch does not count
    assert not list((folder / "runs").glob("*.tmp.*"))  # the interrupted write removed its own
    monkeypatch.setattr(fileio.os, "replace", real_replace)
    # a killed process removes nothing: what it left is cleared by the resume
    (folder / "runs" / "batch-00001.tmp.parquet").write_bytes(b"PAR1 half a file")

    capsys.readouterr()
    assert universal_run(folder, "--resume", "--json") == 0
    assert not list((folder / "runs").glob("*.tmp.*"))  # what the interrupt left is cleared
    assert_same_dataset(whole, folder)


def test_extend_grows_a_study_to_the_one_run_with_the_total(whole, tmp_path, capsys):
    folder = tmp_path / "grown"
    assert universal_run(folder, "--runs", 4, *SMALL) == 0   # batches [0 1 2] [3]
    assert load_dataset(folder)[0]["run_id"].tolist() == [0, 1, 2, 3]
    assert universal_run(folder, "--extend", 2, "--json") == 0  # [3] rerun as [3 4 5]
    assert study.load_config(folder)["runs"] == 6
    assert_same_dataset(whole, folder)


def test_group_size_is_stored_and_gives_the_same_dataset(whole, tmp_path):
    """`--group-size` (groups of 2 balls rather than 4) is kept in study.json and changes no
    run beyond float32 round-off (the study's precision; about 1e-5 relative, seen): a vmapped
    group is the same runs side by side."""
    folder = tmp_path / "grouped"
    assert universal_run(folder, "--runs", 6, "--group-size", 2, *SMALL) == 0
    assert study.load_config(folder)["group_size"] == 2
    (a, _), (b, _) = load_dataset(whole), load_dataset(folder)
    for key in ("c10_pa", "peak_force_n", "cor"):
        np.testing.assert_allclose(a[key], b[key], rtol=1e-4, err_msg=key)
