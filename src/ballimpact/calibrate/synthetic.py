"""Synthetic tests with known answers: a ball specification simulated by the FE engine, sampled
at 100 kHz with a baseline and white noise as a test rig records it (`comparison.noisy_record`)."""

from __future__ import annotations

import numpy as np

from ..comparison import PULSE_RATE_HZ, noisy_record
from .problem import CalibrationProblem, CalibrationTest, free_parameter, sub_ball, with_values


def synthetic_record(spec: dict, speed_m_s: float, options, noise: float,
                     rng: np.random.Generator, layers: str | None = None):
    """An `ImpactRecord` of the ball (up to layer `layers`) at `speed_m_s` (m/s), with white
    noise of `noise` times the peak force, and its FE run."""
    from ..fe import load_ball, simulate

    fe = simulate(load_ball(sub_ball(spec, layers)), speed_m_s, options)
    t = np.arange(0.0, fe.history["time_s"][-1], 1.0 / PULSE_RATE_HZ)
    force = np.interp(t, fe.history["time_s"], fe.history["contact_force_n"])
    return noisy_record(force, speed_m_s, fe.cor, fe.mass_kg, noise, rng), fe


def synthetic_test(name: str, spec: dict, speed_m_s: float, options, noise: float,
                   rng: np.random.Generator, layers: str | None = None) -> CalibrationTest:
    """A processed synthetic test (see `synthetic_record`)."""
    from ..records.pipeline import process

    record, _ = synthetic_record(spec, speed_m_s, options, noise, rng, layers)
    return CalibrationTest(name, process(record, warn_noisy=False).features, layers)


# ---- the recovery problem (tests/calibrate/test_calibrate_slow.py, benchmarks/bench_calibrate.py) ------
#: a two-layer ball: core Mooney-Rivlin with one Prony term, cover Mooney-Rivlin
TWO_LAYER_TRUTH = {
    "name": "two-layer", "layers": [
        {"name": "core", "outer_radius_m": 0.026, "density_kg_m3": 900.0,
         "material": {"model": "mooney_rivlin", "c10_pa": 4.0e6, "c01_pa": -0.4e6,
                      "prony": [{"g": 0.6, "tau_s": 8e-5}]}},
        {"name": "cover", "outer_radius_m": 0.036, "density_kg_m3": 1000.0,
         "material": {"model": "mooney_rivlin", "c10_pa": 6.0e6, "c01_pa": -0.5e6}}]}
TWO_LAYER_START = {"layers.core.material.c10_pa": 5e6, "layers.core.material.c01_pa": -0.2e6,
                   "layers.core.material.prony.0.g": 0.5,
                   "layers.core.material.prony.0.tau_s": 1.2e-4,
                   "layers.cover.material.c10_pa": 5e6, "layers.cover.material.c01_pa": -0.3e6}
TWO_LAYER_BOUNDS = {"layers.core.material.c10_pa": (3e6, 7e6),
                    "layers.core.material.c01_pa": (-1e6, 0.5e6),
                    "layers.core.material.prony.0.g": (0.3, 0.8),
                    "layers.core.material.prony.0.tau_s": (2e-5, 5e-4),
                    "layers.cover.material.c10_pa": (3e6, 8e6),
                    "layers.cover.material.c01_pa": (-1e6, 0.5e6)}


def two_layer_recovery(options, seed: int = 1) -> CalibrationProblem:
    """The recovery problem: tests of the true ball at 10 and 25 m/s (1% noise), the template
    at `TWO_LAYER_START`."""
    rng = np.random.default_rng(seed)
    tests = [synthetic_test(f"{v:g}m/s", TWO_LAYER_TRUTH, v, options, 0.01, rng)
             for v in (10.0, 25.0)]
    template = with_values(TWO_LAYER_TRUTH, TWO_LAYER_START)
    return CalibrationProblem(template, tests, [free_parameter(template, p, *b)
                                                for p, b in TWO_LAYER_BOUNDS.items()])
