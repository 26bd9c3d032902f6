"""Benchmark: feature extraction and filters on a 1 ms half-sine pulse (cricket-ball scale).

Prints one JSON object. Times are medians of repeated calls; `ratio_to_reference` compares each
with a reference measured in the same run: the thesis' appendix `PARA` procedure (sample-based, no
interpolation) written in NumPy, on the same samples, with the contact-time and peak-time errors of both
against the closed form.

Run: python benchmarks/bench_features.py
"""

import json
import os
import platform
import time

import numpy as np

from ballimpact import apply_filter, extract_features
from ballimpact.records.pulses import half_sine

DURATION_S, PEAK_N = 1e-3, 1e4


def para_reference(t, f, v_in, mass):
    """The appendix PARA procedure: window = samples > eps; spans from first/last sample above
    each level; moments and integrals as sample sums."""
    inside = np.flatnonzero(f > np.finfo(float).eps)
    t, f = t[inside[0] : inside[-1] + 1], f[inside[0] : inside[-1] + 1]
    velocity = v_in - np.concatenate([[0], np.cumsum((f[1:] + f[:-1]) / 2 * np.diff(t))]) / mass
    peak = f.max()
    spans = []
    for level in (0.1, 0.5, 0.9):
        above = np.flatnonzero(f >= level * peak)
        spans.append(t[above[-1]] - t[above[0]])
    d = f - f.mean()
    kurtosis = np.mean(d**4) / np.mean(d**2) ** 2
    skewness = np.mean(d**3) / np.mean(d**2) ** 1.5
    tp = t[f == peak].mean()
    return [t[-1] - t[0], *spans, tp - t[0], peak, kurtosis, skewness,
            f[t > tp].sum() / f[t <= tp].sum(), velocity[0], -velocity[-1]]


def median_time(call, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def main():
    results = {}
    for rate in (20e3, 1e6):
        record = half_sine(PEAK_N, DURATION_S, rate, phase=0.37, mass_kg=0.16, impact_speed_m_s=25.0)
        reference = median_time(lambda: para_reference(record.time_s, record.force_n, 25.0, 0.16), 50)
        ours = median_time(lambda: extract_features(record), 50)
        para = para_reference(record.time_s, record.force_n, 25.0, 0.16)
        features = extract_features(record).values
        entry = {
            "samples": record.sample_count,
            "contact_time_error_reference": para[0] / DURATION_S - 1,
            "contact_time_error_ours": features["P1"] / DURATION_S - 1,
            "peak_time_error_reference": para[4] / (DURATION_S / 2) - 1,
            "peak_time_error_ours": features["P5"] / (DURATION_S / 2) - 1,
            "reference_para_s": reference,
            "extract_features_s": ours,
            "ratio_to_reference": ours / reference,
        }
        for name in ("cfc10000", "savgol", "loess"):
            if rate < 100e3 and name != "savgol":
                continue
            entry[f"filter_{name}_s"] = median_time(lambda: apply_filter(record, name), 10)
        results[f"{rate:.0f}_hz"] = entry
    print(json.dumps({
        "benchmark": "features",
        "pulse": "half-sine 1 ms, 10 kN, sampling phase 0.37",
        "machine": {"platform": platform.platform(), "processor": platform.processor(),
                    "cpus": os.cpu_count(), "python": platform.python_version()},
        "results": results,
    }, indent=2))


if __name__ == "__main__":
    main()
