"""Benchmark: where the contact time's error comes from on a ringing load cell (issue 39).

A load cell is a lightly damped oscillator: its inertia delays the record's onset behind the
force's, over about one period of its resonance, whether or not its ringing stands above the
noise. Divided out (`process` with the resonance found in the record, or given as
`--load-cell-hz`) the delay goes; left in, the fitted contact start is late. This script measures
the contact start and end, in units of the exact contact time, of three exact pulses (a 1 ms
half-sine, the sample's Hertz ball, Hunt-Crossley COR 0.45) through an ideal cell and cells
ringing at 8, 14 and 25 kHz (damping ratio 0.03), sampled at 200 kHz, nearly noise-free (0.01%
of the peak) and at 1% noise, no offset, `records` records each (seed 3), processed three ways:
the raw record (`ringing=False`), the default (the resonance sought in the record) and the
resonance given. It prints, per case, the mean start and end error with its standard error, and
how often the default found a resonance.

Run: python benchmarks/bench_load_cell_onset.py [--records N]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import bench_feature_accuracy as accuracy  # noqa: E402

from ballimpact import process  # noqa: E402

RATE_HZ = 200e3
CELLS_HZ = (None, 8e3, 14e3, 25e3)
NOISE = (1e-4, 0.01)
#: raw: the cell left in; default: its resonance sought in the record; given: as --load-cell-hz
WAYS = ("raw", "default", "given")


def edges(shape, cell_hz, noise, way, records):
    """Mean start and end error (fractions of the contact time) and their standard errors, and
    the share of records in which a resonance was divided out."""
    _, pulse, duration, rebound, mass, speed = shape
    rng = np.random.default_rng(3)
    start, end, found = [], [], []
    for _ in range(records):
        record = accuracy.measured(pulse, duration, rebound, mass, speed, rng=rng, rate_hz=RATE_HZ,
                                   noise=noise, ringing_hz=cell_hz, offset=0.0)
        given = cell_hz if way == "given" else None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            processed = process(record, warn_noisy=False, uncertainty=False,
                                damping_ratio=accuracy.DAMPING_RATIO, resonance_hz=given,
                                ringing=way != "raw")
        window = processed.features.window
        start.append(window.start_s / duration)
        end.append(window.end_s / duration - 1)
        found.append(processed.filtered.metadata.get("load_cell_resonance") is not None)
    se = lambda x: float(np.std(x) / np.sqrt(len(x)))  # noqa: E731
    return {"start_error": float(np.mean(start)), "start_standard_error": se(start),
            "end_error": float(np.mean(end)), "end_standard_error": se(end),
            "resonance_divided_out": float(np.mean(found))}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", type=int, default=12, help="records per case (default 12)")
    args = parser.parse_args(argv)
    started = time.perf_counter()
    shapes = [s for s in accuracy.shapes(False) if s[0] in ("half-sine", "hertz",
                                                             "hunt-crossley-0.45")]
    cases = []
    for shape in shapes:
        for cell in CELLS_HZ:
            for noise in NOISE:
                for way in (("raw",) if cell is None else WAYS):
                    cases.append({"pulse": shape[0], "cell_hz": cell, "noise": noise, "way": way,
                                  **edges(shape, cell, noise, way, args.records)})
        print(f"{shape[0]} done", file=sys.stderr)
    print(json.dumps({"machine": f"{platform.machine()}, {os.cpu_count()} cores",
                      "rate_hz": RATE_HZ, "records_per_case": args.records,
                      "seconds": round(time.perf_counter() - started, 1), "cases": cases},
                     indent=1))


if __name__ == "__main__":
    main()
