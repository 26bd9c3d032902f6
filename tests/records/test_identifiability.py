"""`identifiability.correlation_factor`: the integrated autocorrelation time of residual series,
against its closed form for an AR(1) series, and 1 for white noise."""

import numpy as np
import pytest

from ballimpact.identifiability import correlation_factor, standard_errors


def ar1(rho, n, rng):
    x = np.empty(n)
    x[0] = rng.standard_normal()
    for i in range(1, n):
        x[i] = rho * x[i - 1] + np.sqrt(1.0 - rho * rho) * rng.standard_normal()
    return x


@pytest.mark.parametrize("rho", [0.5, 0.8])
def test_ar1_series_gives_its_integrated_autocorrelation_time(rho):
    """tau_int = 1 + 2 sum rho^k = (1 + rho) / (1 - rho) (3 and 9), within 15% on 40,000
    samples in four series (the estimate's scatter is about 5%)."""
    rng = np.random.default_rng(1)
    series = [ar1(rho, 10_000, rng) for _ in range(4)]
    assert correlation_factor(series) == pytest.approx((1 + rho) / (1 - rho), rel=0.15)


def test_white_noise_is_about_one_and_never_below():
    rng = np.random.default_rng(2)
    assert 1.0 <= correlation_factor([rng.standard_normal(5000)]) < 1.15
    assert correlation_factor([]) == 1.0
    assert correlation_factor([np.zeros(10)]) == 1.0


def test_correlation_scales_the_variances():
    rng = np.random.default_rng(3)
    jacobian, residuals = rng.standard_normal((50, 2)), rng.standard_normal(50)
    assert np.allclose(standard_errors(jacobian, residuals, correlation=4.0),
                       2.0 * standard_errors(jacobian, residuals))
