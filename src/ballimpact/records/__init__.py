"""Measured impact records, from the file to the features (thesis chapter 3), one straight path:
`loaders` (CSV, WAV, side files, built-in `datasets`) -> `record` (ImpactRecord, baseline,
contact window, resampling) -> `plausibility` (polarity, clipping, one pulse, momentum) ->
`ringing` (the load cell's resonance divided out) -> `filters` -> `edges` and `reconstruct` (the
pulse with fitted ends, the uncertainty) -> `features` (the 19 values); `pipeline.process` runs
them in that order. `repeats` groups repeated tests, `pulses` makes analytic records."""

from .record import (
    ContactWindow as ContactWindow,
    ImpactRecord as ImpactRecord,
    baseline_noise_rms as baseline_noise_rms,
    contact_window as contact_window,
    remove_baseline as remove_baseline,
    resample as resample,
    rms as rms,
    sample_rate_hz as sample_rate_hz,
)

__all__ = ["ContactWindow", "ImpactRecord", "baseline_noise_rms", "contact_window",
           "remove_baseline", "resample", "rms", "sample_rate_hz"]
