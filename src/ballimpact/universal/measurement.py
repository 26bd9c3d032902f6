"""A held-out or training pulse turned into what a test rig records: sampled at 100 kHz with a
baseline before contact and white noise, then processed as a measured test."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputWarning
from .dataset import PULSE_RATE_HZ

#: samples of baseline before first contact (0.5 ms at 100 kHz)
LEAD_SAMPLES = 50


def noisy_record(pulse_n: np.ndarray, impact_speed_m_s: float, cor: float, mass_kg: float,
                 noise: float, rng: np.random.Generator):
    """An `ImpactRecord` of a 100 kHz pulse (from first contact) with `LEAD_SAMPLES` of baseline
    and white noise of `noise` times the peak force; impact and rebound speeds as light gates
    would give them."""
    from ..records import ImpactRecord

    time_s = np.arange(-LEAD_SAMPLES, pulse_n.size) / PULSE_RATE_HZ
    force = np.concatenate([np.zeros(LEAD_SAMPLES), pulse_n])
    force = force + rng.normal(0.0, noise * pulse_n.max(), force.size)
    return ImpactRecord(time_s, force, mass_kg=mass_kg, impact_speed_m_s=impact_speed_m_s,
                        rebound_speed_m_s=cor * impact_speed_m_s)


def noisy_features(pulse_n, impact_speed_m_s, cor, mass_kg, noise, rng, filter="none"):
    """The 19 features (dict) of the noisy record, processed as a measured test. The pulse is
    one this package generated (a study's FE run): what the measured-test checks say about it
    (e.g. "noisy record: filter it") is not about the user's data and cannot be acted on, so
    it is not passed on as a warning."""
    from ..pipeline import process

    record = noisy_record(pulse_n, impact_speed_m_s, cor, mass_kg, noise, rng)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        return process(record, filter=filter, warn_noisy=False).features.values
