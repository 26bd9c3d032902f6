"""The CSV and plot writers of `fe.output` on known arrays: a run's histories and a compression
curve (the command line's `simulate --csv`, `compress --csv --plot`)."""

from types import SimpleNamespace

import numpy as np
import pytest

from ballimpact.fe.output import plot_curve, write_curve, write_history

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def test_history_csv_has_the_names_and_a_row_per_step(tmp_path):
    history = {"time_s": np.array([0.0, 1e-6, 2e-6]),
               "contact_force_n": np.array([0.0, 12.5, 1.0 / 3.0])}
    path = tmp_path / "h.csv"
    assert write_history(path, history) == str(path)
    lines = path.read_text().splitlines()
    assert lines[0] == "time_s,contact_force_n"
    assert lines[1:] == ["0,0", "1e-06,12.5", "2e-06,0.3333333333"]


def test_compression_curve_csv_and_plot(tmp_path):
    curve = SimpleNamespace(ball_name="rubber", rate_m_s=None,
                            deflection_m=np.array([0.0, 1e-3, 2e-3]),
                            force_n=np.array([0.0, 150.0, 420.0]))
    path = tmp_path / "c.csv"
    assert write_curve(path, curve) == str(path)
    table = np.genfromtxt(path, delimiter=",", names=True)
    assert table.dtype.names == ("deflection_m", "force_n")
    assert table["deflection_m"] == pytest.approx(curve.deflection_m, rel=1e-12)
    assert table["force_n"] == pytest.approx(curve.force_n, rel=1e-12)
    for rate in (None, 0.5):
        png = tmp_path / f"c{rate}.png"
        assert plot_curve(SimpleNamespace(**{**vars(curve), "rate_m_s": rate}), png) == png
        assert png.read_bytes().startswith(PNG_MAGIC) and png.stat().st_size > 5_000
