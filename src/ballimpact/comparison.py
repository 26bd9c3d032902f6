"""Compare a model's force pulse with a test's, and turn a model's pulse into what a test rig
records. Used wherever a model meets a test: calibration, the universal model, the report.

- `pulse_nrmse`: force RMS difference over the span where either pulse touches (a fraction of
  the reference's peak); `best_alignment` / `aligned_nrmse`: the same at the best time shift
  within +/- `SHIFT_FRACTION` of the test's contact time.
- `measured_like`: a model's features measured as the test's were (its rate, its threshold).
- `compare`: the scalar comparison (NRMSE, COR, contact time, peak force).
- `noisy_record` / `noisy_features`: a pulse sampled at `PULSE_RATE_HZ` (100 kHz) with a baseline
  and white noise, processed as a measured test.

A "test" here is anything with `features` (`ImpactFeatures`) and `pulse` (time s, force N from
its contact start), e.g. `calibrate.CalibrationTest`.
"""

from __future__ import annotations

import warnings

import numpy as np

from .errors import InputWarning

#: the sampling rate (Hz) of stored and synthetic pulses
PULSE_RATE_HZ = 100e3
#: samples of baseline before first contact in `noisy_record` (0.5 ms at 100 kHz)
LEAD_SAMPLES = 50
#: the largest time shift between the pulses when aligning them, as a fraction of contact time
SHIFT_FRACTION = 0.05


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
    """The contact pulse of `ImpactFeatures` as measured (times from contact start): its
    samples, noise and all (`samples_time_s`, `samples_force_n`) when the values came from a
    fitted pulse, else its curve."""
    if getattr(features, "samples_time_s", None) is not None:
        return features.samples_time_s, features.samples_force_n
    return features.time_s, features.force_n


def max_shift_s(test) -> float:
    """How far (s) the pulses may be shifted against each other to align them."""
    return SHIFT_FRACTION * float(test.features.values["P1"])


def aligned_nrmse(test, t_model: np.ndarray, f_model: np.ndarray) -> float:
    """Force NRMSE (`pulse_nrmse`) at the best time shift of the model pulse within
    +/- `max_shift_s`."""
    return best_alignment(test, t_model, f_model)[0]


def best_alignment(test, t_model: np.ndarray, f_model: np.ndarray) -> tuple[float, float]:
    """(NRMSE, shift in s) of `aligned_nrmse`: the model pulse's times plus the shift line up
    with the test's."""
    from scipy.optimize import minimize_scalar

    limit = max_shift_s(test)
    t_test, f_test = test.pulse

    def misfit(shift):
        return pulse_nrmse(t_test, f_test, t_model + shift, f_model)

    best = minimize_scalar(misfit, bounds=(-limit, limit), method="bounded",
                           options={"xatol": 1e-3 * limit})
    unshifted = misfit(0.0)
    return (float(best.fun), float(best.x)) if best.fun < unshifted else (float(unshifted), 0.0)


def measured_like(test, run):
    """The features of a model's pulse measured as the test's was: resampled at the test's
    rate, windowed at the test's threshold (a fraction of the peak) and, for a test described by
    its fitted pulse, described the same way at the test's noise level. A noisy test's window
    starts and ends where its pulse crosses a threshold above the noise (5 x its RMS, 5% of the
    peak at 1% noise), extrapolated to zero; the clean FE pulse measured at 1e-3 of its peak would
    differ in contact time by the pulse's tails alone (5% on the thesis' ball). `run`: an FE run
    or any model's `ImpactRecord`. Resampled by LINEAR interpolation: a clean model pulse ends
    in exact zeros after a kink (separation), and the ringing of a cubic spline there once left
    the resampled tail all positive, so that the contact never ended and a report aborted with
    "force_n: no sample at or below zero force where the record ends" (a three-element fit to a
    50 kHz test: spacing 20 us, 8.01 steps of 2.5 us; `records.resample`)."""
    from .records.features import extract_features
    from .records.record import ImpactRecord, resample

    features = test.features
    spacing = features.sample_interval_s or float(np.median(np.diff(features.time_s)))
    # a test described by its fitted pulse (the default since issue 39): the model's pulse is
    # described the same way, as a record of the test's noise would be (its threshold from that
    # noise, the same smoothing)
    fitted = {"method": "fit", "noise_rms_n": features.window.noise_rms_n,
              "smoothing": features.smoothing} if features.method == "fit" else {}
    fraction = 1e-3 if fitted else max(1e-3, features.window.threshold_n / features.values["P6"])
    record = run if isinstance(run, ImpactRecord) else run.record()
    resampled = resample(record, 1.0 / spacing, method="linear")
    # notes on the model's own pulse (its impulse over the test's window) are nothing the user
    # can act on: warnings are for the user's data
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        return extract_features(resampled, threshold_fraction=fraction, **fitted)


def noisy_record(pulse_n: np.ndarray, impact_speed_m_s: float, cor: float, mass_kg: float,
                 noise: float, rng: np.random.Generator):
    """An `ImpactRecord` of a 100 kHz pulse (from first contact) with `LEAD_SAMPLES` of baseline
    and white noise of `noise` times the peak force; impact and rebound speeds as light gates
    would give them."""
    from .records.record import ImpactRecord

    time_s = np.arange(-LEAD_SAMPLES, pulse_n.size) / PULSE_RATE_HZ
    force = np.concatenate([np.zeros(LEAD_SAMPLES), pulse_n])
    force = force + rng.normal(0.0, noise * pulse_n.max(), force.size)
    return ImpactRecord(time_s, force, mass_kg=mass_kg, impact_speed_m_s=impact_speed_m_s,
                        rebound_speed_m_s=cor * impact_speed_m_s)


def noisy_features(pulse_n, impact_speed_m_s, cor, mass_kg, noise, rng, filter="none",
                   method="fit"):
    """The 19 features (dict) of the noisy record, processed as a measured test (with the pulse
    description `method`, `extract_features`; no uncertainty, which nothing here uses). The pulse is
    one this package generated (a study's FE run): what the measured-test checks say about it
    (e.g. "noisy record: filter it") is not about the user's data and cannot be acted on, so
    it is not passed on as a warning."""
    from .records.pipeline import process

    record = noisy_record(pulse_n, impact_speed_m_s, cor, mass_kg, noise, rng)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        return process(record, filter=filter, warn_noisy=False, method=method,
                       uncertainty=False).features.values
