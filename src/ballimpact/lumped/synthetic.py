"""Synthetic impact tests with known answers: records of lumped models of known parameters
(`SINGLE`, `THREE`: a 0.16 kg ball at 20 m/s sampled at 200 kHz), clean or with white noise,
for the identification tests (tests/conftest.py's fixtures) and benchmarks/bench_lumped.py."""

import numpy as np

from .simulate import simulate

MASS_KG, SPEED_M_S, RATE_HZ = 0.16, 20.0, 200e3
SINGLE = {"k": 2e7, "alpha": 1.3, "c": 80.0}
THREE = {"k1": 2e7, "alpha1": 1.3, "c1": 40.0, "k2": 5e6, "alpha2": 1.1, "c2": 60.0,
         "k3": 4e7, "alpha3": 1.45, "c3": 20.0, "m1": 0.06, "m2": 0.04, "m3": 0.06}


def clean(model, params, speed=SPEED_M_S, rate_hz=RATE_HZ):
    """The model's pulse sampled at `rate_hz`, the grid shifted by 0.37 of a sample from the
    contact start; the measured rebound speed is the exact one."""
    record = simulate(model, params, impact_speed_m_s=speed, mass_kg=MASS_KG, rate_hz=rate_hz)
    return record.replace(time_s=record.time_s + 0.37 / rate_hz, velocity_m_s=None)


def noisy(record, fraction, seed):
    """White noise of RMS `fraction` of the peak force added to every sample."""
    rng = np.random.default_rng(seed)
    noise = fraction * record.force_n.max() * rng.standard_normal(record.force_n.size)
    return record.replace(force_n=record.force_n + noise)
