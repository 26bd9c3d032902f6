"""Compare a simulated pulse with a measured (or held-out) one: force NRMSE on the aligned
pulse, COR, contact time and peak force."""

from __future__ import annotations

import numpy as np


def pulse_nrmse(t_a: np.ndarray, f_a: np.ndarray, t_b: np.ndarray, f_b: np.ndarray) -> float:
    """RMS difference of two pulses, both with t = 0 at first contact, over the span where
    either touches, divided by the peak of `f_a` (the reference)."""
    end = max(t_a[f_a > 0].max(initial=0.0), t_b[f_b > 0].max(initial=0.0))
    t = np.linspace(0.0, end, 512)
    a = np.interp(t, t_a, f_a, left=0.0, right=0.0)
    b = np.interp(t, t_b, f_b, left=0.0, right=0.0)
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.max(f_a))


def compare(measured: dict[str, float], simulated: dict[str, float], nrmse: float) -> dict:
    """Scalar comparison; `measured`/`simulated` hold P1 (contact time), P6 (peak), P17 (COR)."""
    return {"force_nrmse": nrmse,
            "cor_measured": measured["P17"], "cor_simulated": simulated["P17"],
            "cor_error": simulated["P17"] - measured["P17"],
            "contact_time_measured_s": measured["P1"], "contact_time_simulated_s": simulated["P1"],
            "contact_time_relative_error": simulated["P1"] / measured["P1"] - 1.0,
            "peak_force_measured_n": measured["P6"], "peak_force_simulated_n": simulated["P6"],
            "peak_force_relative_error": simulated["P6"] / measured["P6"] - 1.0}


def features_pulse(features) -> tuple[np.ndarray, np.ndarray]:
    """The contact pulse of `ImpactFeatures` (its times already count from contact start)."""
    return features.time_s, features.force_n
