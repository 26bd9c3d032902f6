"""The thesis' path for the core end to end on synthetic data with a known answer
(examples/thesis_core_path.py): material test -> `material fit` -> `simulate` -> the Prony term
calibrated from one impact."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))


@pytest.mark.slow
def test_thesis_core_path(tmp_path):
    import thesis_core_path as path

    result = path.run(tmp_path)
    fit, truth = result["material_fit"], path.TRUE_MATERIAL
    for key in ("c10_pa", "c01_pa"):  # measured 1.0 and 1.2 standard errors
        assert abs(fit[key] - truth[key]) <= 2.0 * fit["standard_errors"][key]
    assert fit["r2"]["overall"] > 0.999
    # the elastic constants of a slow test miss the impact's energy loss (thesis figure 5-8)
    assert result["elastic_prediction"]["cor"] > 0.95
    assert result["measured_impact"]["cor"] == pytest.approx(0.75, abs=0.02)
    for run in (result["prony_calibration"], result["prony_calibration_from_true_constants"]):
        g = run["layers.core.material.prony.0.g"]
        tau = run["layers.core.material.prony.0.tau_s"]
        assert g["error_in_standard_errors"] <= 1.0           # measured 0.11 and 0.04
        # tau: 6% high in both, 2.2-2.3 standard errors: the systematic misfit of the explicit
        # run's ringing contact force is not in the standard errors (the example's docstring)
        assert tau["calibrated"] == pytest.approx(tau["truth"], rel=0.1)
        assert tau["error_in_standard_errors"] <= 3.0
