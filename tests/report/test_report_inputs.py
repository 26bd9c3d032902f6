"""The `report` command's checks and messages built in the library (issue 40 item 2):
`report.inputs.check_test_record`, `builtin_note`, `report.build.best_miss` and
`raise_if_unmatched`, called from Python."""

from pathlib import Path

import numpy as np
import pytest

from ballimpact.errors import CheckFailed, InputError
from ballimpact.records.record import ImpactRecord
from ballimpact.report.build import best_miss, raise_if_unmatched
from ballimpact.report.inputs import builtin_ball, builtin_note, check_test_record


def record(**scalars) -> ImpactRecord:
    t = np.linspace(0.0, 1e-3, 101)
    return ImpactRecord(t, 1e3 * np.sin(np.pi * t / 1e-3), **scalars)


def test_a_test_record_needs_its_speed_and_mass():
    full = record(mass_kg=0.16, impact_speed_m_s=20.0)
    assert check_test_record(full, Path("t.csv")) is full
    with pytest.raises(InputError) as caught:
        check_test_record(record(mass_kg=0.16), Path("lab/t1.csv"))
    assert str(caught.value) == (
        'lab/t1.csv: no impact_speed_m_s; a report compares tests at their speeds: give them in '
        'the side file t1.json (e.g. {"mass_kg": 0.16, "impact_speed_m_s": 25}) or '
        '--impact-speed-m-s')
    with pytest.raises(InputError) as caught:  # several tests: the side file only
        check_test_record(record(), Path("t2.csv"), count=3)
    assert str(caught.value).startswith("t2.csv: no impact_speed_m_s and no mass_kg;")
    assert str(caught.value).endswith('"impact_speed_m_s": 25})')


def test_builtin_note_names_the_synthetic_set_and_the_generating_ball():
    assert builtin_note("sample") == ("SYNTHETIC tests (the built-in set 'sample', see "
                                      "docs/report.md), not measurements.")
    ball = builtin_ball("speeds")
    note = builtin_note("speeds", ball)
    assert "the built-in set 'speeds'" in note
    assert "The model 'FE synthetic-3layer' is the ball that generated them" in note


def result_of(checks):
    """A `build_report` result with runs (test, model, force NRMSE, missed criteria)."""
    runs = [{"test": t, "model": m, "comparison": {"force_nrmse": e},
             "check": {"passed": not missed, "missed": missed}} for t, m, e, missed in checks]
    tests = list(dict.fromkeys(t for t, *_ in checks))
    unmatched = [t for t in tests if not any(r["check"]["passed"] for r in runs
                                             if r["test"] == t)]
    return {"runs": runs, "tests": [{"test": t} for t in tests], "unmatched_tests": unmatched,
            "report_html": "out/report.html"}


def test_best_miss_and_the_failed_check():
    result = result_of([("10 m/s", "single", 0.08, ["COR"]), ("10 m/s", "three", 0.03,
                                                               ["peak force", "COR"]),
                        ("20 m/s", "single", 0.02, [])])
    assert best_miss(result, "10 m/s") == "10 m/s: best three missed peak force, COR"
    with pytest.raises(CheckFailed) as caught:
        raise_if_unmatched(result)
    assert str(caught.value) == ("no model passes its check on 1 of 2 tests (10 m/s): 10 m/s: "
                                 "best three missed peak force, COR; see out/report.html")
    assert caught.value.exit_code == 3 and caught.value.result is result
    raise_if_unmatched(result_of([("20 m/s", "single", 0.02, [])]))  # every test matched


def test_the_command_help_names_the_library_default_models():
    from ballimpact.cli import report as cli_report
    from ballimpact.report.build import DEFAULT_MODELS

    assert cli_report.DEFAULT_MODELS == DEFAULT_MODELS
