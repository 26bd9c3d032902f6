"""The one table writer (`fileio.table_text`, `write_table`) every CSV the package writes goes
through: a unit header, one number format, non-finite values empty, text quoted where it must
be, and what it writes reads back (`fileio.read_table`, Python's csv module) to the same
numbers."""

import csv
import io
import math

import numpy as np
import pytest

from ballimpact.fileio import column_rows, read_table, table_text, write_table


def test_numbers_read_back_in_the_format_given(tmp_path):
    t = np.linspace(0.0, 1e-3, 7)
    force = 1e4 * np.sin(np.pi * t / 1e-3) + 1 / 3
    path = write_table(tmp_path / "pulse.csv", ["time_s", "force_n"], column_rows(t, force))
    _, names, _, values = read_table(tmp_path / "pulse.csv")
    assert path == str(tmp_path / "pulse.csv") and names == ["time_s", "force_n"]
    np.testing.assert_allclose(values, np.column_stack([t, force]), rtol=5e-10, atol=0)  # 10 digits
    exact = table_text(["force_n"], [[x] for x in force], number_format="")
    assert [float(line) for line in exact.split()[1:]] == force.tolist()  # round trip: the bits


def test_cells_rows_as_mappings_and_bad_rows():
    text = table_text(["name", "count", "cor", "note"],
                      [{"name": "ball, hard", "count": np.int64(3), "cor": math.nan,
                        "note": 'say "hi"'},
                       ["soft", 2, 0.512345678912, None]], number_format=".4g")
    rows = list(csv.reader(io.StringIO(text)))
    assert rows == [["name", "count", "cor", "note"], ["ball, hard", "3", "", 'say "hi"'],
                    ["soft", "2", "0.5123", ""]]
    assert text.endswith("\n") and "\r" not in text
    with pytest.raises(ValueError, match="table row 1: 2 cells for 3 columns"):
        table_text(["a_s", "b_n", "c"], [[1.0, 2.0]])
