"""The `features` command's library calls (issue 40 item 2): `repeats.record_files`,
`summarise_repeats`, `record_summary`, `record_group`, `write_speed_table` and
`plotting.plot_repeats`, called from Python on the built-in synthetic speed set."""

import csv
import math
import shutil
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from ballimpact import load_record, process
from ballimpact.records import repeats
from ballimpact.errors import InputError, InputWarning

SPEED_SET = Path(str(resources.files("ballimpact") / "data" / "speed_set"))


def copy_test(folder: Path, speed: str, name: str) -> Path:
    """The built-in synthetic test at `speed` (e.g. "10.0") with its side file, as `name`."""
    for suffix in (".csv", ".json"):
        shutil.copy(SPEED_SET / f"synthetic_{speed}_m_s{suffix}", folder / f"{name}{suffix}")
    return folder / f"{name}.csv"


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    """Two identical repeats at 10 m/s and one test at 20.8 m/s: (files, processed)."""
    folder = tmp_path_factory.mktemp("lab")
    files = [copy_test(folder, "10.0", "a_10"), copy_test(folder, "10.0", "b_10"),
             copy_test(folder, "20.8", "c_20")]
    return files, [process(load_record(path)) for path in files]


def test_record_files_leave_out_the_table_and_refuse_to_overwrite_a_record(lab, tmp_path):
    files, _ = lab
    folder = files[0].parent
    table = folder / "table.csv"
    table.write_text("file\n")
    try:
        assert repeats.record_files([folder], table) == files  # the earlier table left out
        assert table in repeats.record_files([folder])
        with pytest.raises(InputError, match="one of the records given"):
            repeats.record_files([files[0]], files[0])
    finally:
        table.unlink()
    only = tmp_path / "only.csv"
    only.write_text("file\n")
    with pytest.raises(InputError, match="no test records besides the --table output"):
        repeats.record_files([tmp_path], only)


def test_summarise_repeats_groups_means_and_sds(lab):
    files, processed = lab
    result = repeats.summarise_repeats(processed, files, [10.0, 20.8], 0.05)
    assert result["grouping"] == {"rule": "nominal", "nominal_speeds_m_s": [10.0, 20.8],
                                  "speed_tolerance": 0.05}
    slow, fast = result["groups"]
    assert (slow["speed_m_s"], slow["count"], fast["speed_m_s"], fast["count"]) == (10, 2, 20.8, 1)
    assert slow["files"] == [str(files[0]), str(files[1])]
    peak = processed[0].features.values["P6"]
    assert peak == pytest.approx(3764.39, rel=1e-4)
    assert slow["mean"]["peak_force_n"] == pytest.approx(peak, rel=1e-12)
    assert slow["sd"]["peak_force_n"] == 0.0             # identical repeats
    assert math.isnan(fast["sd"]["cor"])                 # one record: no SD
    assert fast["mean"]["impact_speed_m_s"] == pytest.approx(20.8)
    assert [row["group_speed_m_s"] for row in result["records"]] == [10.0, 10.0, 20.8]
    clustered = repeats.summarise_repeats(processed, files)
    assert clustered["grouping"]["rule"] == "clustered"
    assert [g["speed_m_s"] for g in clustered["groups"]] == pytest.approx([10.0, 20.8])
    with pytest.warns(InputWarning, match="nominal speed 40 m/s: no record"):
        repeats.summarise_repeats(processed, files, [10.0, 20.8, 40.0], 0.05)


def test_one_record_summary_group_and_table(lab, tmp_path):
    files, processed = lab
    summary = repeats.record_summary(processed[2])
    assert summary["filter"] == "none" and summary["load_cell_resonance"] is None
    assert summary["baseline_offset_n"] == pytest.approx(4.786476, rel=1e-6)
    assert summary["features"]["P15"] == pytest.approx(20.8)
    assert repeats.record_group(processed[2], files[2]) == pytest.approx(20.8)
    assert repeats.record_group(processed[2], files[2], [10.0, 20.0], 0.05) == 20.0
    with pytest.raises(InputError, match="c_20.csv: impact speed 20.8 m/s is not within 5%"):
        repeats.record_group(processed[2], files[2], [10.0], 0.05)
    rows = [repeats.record_row(p, f, 10.0) for p, f in zip(processed[:2], files[:2])]
    path = repeats.write_speed_table(tmp_path / "t.csv", rows)
    with open(path, newline="") as handle:
        read = list(csv.DictReader(handle))
    assert list(read[0]) == list(repeats.TABLE_COLUMNS)
    assert [r["file"] for r in read] == [str(f) for f in files[:2]]
    assert float(read[0]["peak_force_n"]) == rows[0]["peak_force_n"]  # round-trips exactly


def test_plot_repeats_writes_the_band_png(lab, tmp_path):
    from ballimpact.plotting import plot_repeats

    files, processed = lab
    path = plot_repeats(processed, [10.0, 10.0, 20.8], tmp_path / "band.png")
    assert path == tmp_path / "band.png"
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 10_000
    bands = repeats.pulse_bands(processed, np.array([10.0, 10.0, 20.8]))
    assert [b.count for b in bands] == [2, 1]
