"""The report's table of repeats: per model and speed group, the mean and SD of the parameters
of the per-test fits (docs/report.md)."""

from types import SimpleNamespace

import numpy as np
import pytest

from ballimpact.report.tables import repeats_table


def _run(model, speed, k, lam):
    return SimpleNamespace(model=model, impact_speed_m_s=speed, parameters={"k": k, "lambda": lam},
                           units={"k": "N/m^n", "lambda": "s/m"})


def test_repeats_are_grouped_by_speed_and_summarised():
    ks = [1.0e7, 1.2e7, 1.1e7]
    runs = [_run("hunt_crossley", s, k, 0.1 * i) for i, (s, k) in
            enumerate(zip((20.1, 19.9, 20.0), ks))]
    runs.append(_run("hunt_crossley", 10.0, 9e6, 0.5))  # alone at its speed: no row
    runs.append(_run("universal", 20.0, 1.0, 1.0))       # one test of this model: no row
    table = repeats_table(runs)
    rows = {row[3]: row for row in table.rows}
    assert set(rows) == {"k [N/m^n]", "lambda [s/m]"}
    model, speed, count, _, mean, sd = rows["k [N/m^n]"]
    assert (model, count) == ("hunt_crossley", 3)
    assert speed == pytest.approx(20.0)
    assert mean == pytest.approx(np.mean(ks), rel=1e-12)
    assert sd == pytest.approx(np.std(ks, ddof=1), rel=1e-12)


def test_no_repeats_no_table():
    assert repeats_table([_run("m", 10.0, 1.0, 1.0), _run("m", 20.0, 1.0, 1.0)]) is None
