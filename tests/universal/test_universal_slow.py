"""The universal model end to end at the issue's scale (slow: about 9 minutes on 2 cores): an
800-run study at the default mesh, training, and the closed loop through the FE engine on 50
held-out runs, clean and with 1% white noise at 100 kHz.

800 runs, not the thesis' 600: a 600-run model sits on this test's 2% limits, and which side it
lands on is chance. The stable-increment fix of issue 26 changed 8 of the 600 runs by at most
5e-4. That moved the held-out mu0 median error from 1.91% to 2.16%, and the noisy closed loop's
median force NRMSE from 1.80% to 2.04%. The 800-run model of the same seed gives 1.21% and 1.67%."""

import pytest

from ballimpact.universal.evaluate import closed_loop
from ballimpact.universal.study import make_config, run_study
from ballimpact.universal.training import train

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    folder = tmp_path_factory.mktemp("universal") / "study"
    summary = run_study(folder, make_config(runs=800, seed=7))
    assert summary["finished_runs"] == 800
    model, report = train(folder)
    return folder, model, report


def test_held_out_figures(trained):
    _, _, report = trained
    assert report["runs"] >= 90  # >= 15% of the runs
    assert report["inverse"]["mu0_pa"]["relative_error"]["median"] < 0.02
    assert trained[1].metadata["held_out_check"]["passed"]  # written without --force
    for name, entry in report["inverse"].items():
        assert 0.8 <= entry["interval_90_coverage"] <= 0.98, name


@pytest.mark.parametrize("noise", [0.0, 0.01])
def test_closed_loop_on_held_out_runs(trained, noise):
    folder, model, _ = trained
    summary = closed_loop(model, folder, runs=50, noise=noise)["summary"]
    assert summary["runs"] == 50 and summary["failed"] == 0
    assert summary["force_nrmse"]["median"] < 0.02
    # the 4% at the 90th percentile holds clean; with 1% noise a 600-run model reached
    # 4.09%, the 800-run one 2.58% (the built-in 2048-run model: 2.61%, docs/universal.md)
    assert summary["force_nrmse"]["p90"] < (0.04 if noise == 0 else 0.05)
    assert summary["cor_error"]["median"] < 0.01
    assert summary["contact_time_relative_error"]["median"] < 0.02
