"""`standards.table_rows`, `write_result_table` and `stats_text` (issue 40 item 2: the `standard`
command's table and text built in the library), called from Python on results made by
`standards.summarise` from known shots; the means and SDs checked against numpy."""

import csv
import math

import numpy as np
import pytest

from ballimpact.standards import (get_method, stats_text, summarise, table_rows,
                                  write_result_table)

SHOTS = [("ballA", "ballA_1.csv", 0.50, 26.7), ("ballA", "ballA_2.csv", 0.52, 26.9),
         ("ballB", "ballB_1.csv", 0.55, 26.8)]


@pytest.fixture
def records_result():
    method = get_method("cor")
    shots = [{"ball": b, "file": f, "cor": c, "impact_speed_m_s": v} for b, f, c, v in SHOTS]
    return {**method.to_dict(), "source": "records", "shots": shots, **summarise(method, shots)}


def test_table_rows_of_records_give_shots_balls_and_all(records_result):
    header, rows = table_rows(records_result)
    assert header == ["kind", "ball", "file", "count", "cor", "cor_sd", "impact_speed_m_s",
                      "impact_speed_m_s_sd"]
    assert [row[:4] for row in rows] == [["shot", "ballA", "ballA_1.csv", 1],
                                         ["shot", "ballA", "ballA_2.csv", 1],
                                         ["shot", "ballB", "ballB_1.csv", 1],
                                         ["ball", "ballA", "", 2], ["ball", "ballB", "", 1],
                                         ["all", "", "", 2]]
    assert rows[0][4:] == [0.50, None, 26.7, None]
    assert rows[3][4] == pytest.approx(0.51) and rows[3][5] == pytest.approx(np.std([.5, .52],
                                                                                   ddof=1))
    assert math.isnan(rows[4][5])  # one shot: no SD
    means = [0.51, 0.55]
    assert rows[5][4] == pytest.approx(np.mean(means))
    assert rows[5][5] == pytest.approx(np.std(means, ddof=1))


def test_table_rows_of_a_model_is_one_row():
    result = {**get_method("compression").to_dict(), "source": "model", "ball": "tennis",
              "result": {"deflection_m": 0.00635, "force_at_6_35_mm_n": 400.0,
                         "force_at_6_35_mm_lbf": 89.92}}
    header, rows = table_rows(result)
    assert header[4:] == ["force_at_6_35_mm_n", "force_at_6_35_mm_n_sd", "force_at_6_35_mm_lbf",
                          "force_at_6_35_mm_lbf_sd"]
    assert rows == [["model", "tennis", "", 1, 400.0, None, 89.92, None]]


def test_write_result_table_and_stats_text(records_result, tmp_path):
    path = write_result_table(tmp_path / "cor.csv", records_result)
    with open(path, newline="") as handle:
        read = list(csv.reader(handle))
    assert read[0][:5] == ["kind", "ball", "file", "count", "cor"] and len(read) == 7
    assert read[1][4:] == ["0.5", "", "26.7", ""]          # 12 significant digits, None empty
    assert float(read[4][5]) == pytest.approx(np.std([.5, .52], ddof=1), rel=1e-11)
    ball_a = records_result["balls"][0]
    assert stats_text(ball_a["cor"]) == "0.51 +- 0.0141"
    assert stats_text(records_result["balls"][1]["impact_speed_m_s"], "m/s") == "26.8 +- n/a m/s"
