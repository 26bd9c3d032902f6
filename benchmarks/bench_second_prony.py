"""Does a second Prony term earn its place in the universal model? (issue 42, item 1)

The universal ball has one Prony term (g1, tau1). A real ball's relaxation spreads over more
than one time. If the one-term model, identified from a test of a ball with two terms, gives
that test back as well as it gives back one-term balls, a second term would add two groups to
learn and nothing the impact shows.

For each material family (`data/ball_families.json`) this draws the family's 12 balls
(`families.family_box_tests`, the seeds of examples/identify_ball_families.py), and makes of
each a two-term twin: the same long-term C10, C01 and total g (g1 + g2 = the one-term g1,
split at a fraction drawn in 0.3-0.7) with the
two relaxation times a factor k apart around the one-term tau1 (tau1 / sqrt(k) and
tau1 sqrt(k), k log-uniform in 10-100: one to two decades). Both sets go through the families'
closed loop (`families.family_closed_loop`: FE test at 100 kHz with 1% noise, identified with
the model, the identified ball's FE run against the clean test). It prints per family and set
the median and 90th percentile of the force NRMSE, |COR error| and contact-time error.

    python benchmarks/bench_second_prony.py [--model sports-ball-universal-model]
        [--families cricket,softball,...] [--runs 12]

About 20 s a family and set on 2 CPU cores.
"""

from __future__ import annotations

import argparse
import json
import platform
import time

import numpy as np

from ballimpact.universal import load_model
from ballimpact.universal.families import MATERIAL_FAMILIES, family_box_tests, family_closed_loop


def two_term_twins(params: list[dict], seed: int) -> list[dict]:
    """Each ball's two-term twin (see the module)."""
    rng = np.random.default_rng(seed)
    twins = []
    for p in params:
        share, k = rng.uniform(0.3, 0.7), 10.0 ** rng.uniform(1.0, 2.0)
        g, tau = p["g1"], p["tau1_s"]
        twins.append({**p, "prony": [{"g": g * share, "k": 0.0, "tau_s": tau / np.sqrt(k)},
                                     {"g": g * (1 - share), "k": 0.0,
                                      "tau_s": tau * np.sqrt(k)}]})
    return twins


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--model", default="sports-ball-universal-model")
    parser.add_argument("--families", default=",".join(MATERIAL_FAMILIES))
    parser.add_argument("--runs", type=int, default=12)
    args = parser.parse_args(argv)
    model = load_model(args.model)
    out = {"model": args.model, "runs_per_family": args.runs, "noise_of_peak": 0.01,
           "machine": f"{platform.machine()}, Python {platform.python_version()}",
           "families": {}}
    started = time.perf_counter()
    names = args.families.split(",")
    unknown = [name for name in names if name not in MATERIAL_FAMILIES]
    if unknown:
        parser.error(f"--families: unknown {', '.join(unknown)}; the families are "
                     f"{', '.join(MATERIAL_FAMILIES)}")
    for name in names:
        seed = MATERIAL_FAMILIES.index(name)  # examples/identify_ball_families.py's draws
        size, params, speeds = family_box_tests(name, args.runs, seed)
        rows = {}
        for label, tests in (("one_term", params), ("two_terms", two_term_twins(params, 1))):
            loop = family_closed_loop(model, size, tests=(tests, speeds), seed=seed,
                                      label=f"{name} {label}")["summary"]
            rows[label] = {key: loop[key] for key in ("force_nrmse", "cor_error",
                                                      "contact_time_relative_error", "failed")}
        out["families"][name] = rows
    out["wall_time_s"] = time.perf_counter() - started
    print(json.dumps(out, indent=2))
    return out


if __name__ == "__main__":
    main()
