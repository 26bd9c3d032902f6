"""Benchmark: lumped-model identification (issue: single-element fit; thesis < 2 s, goal < 0.5 s).

Prints one JSON object. The test is a synthetic single-element impact (k = 2e7 N/m^1.3,
alpha = 1.3, c = 80 N s/m, 160 g at 20 m/s) with 2% white noise, sampled at 200 kHz.

- `single_element_fit_s`: median wall time of `lumped.fit` (GA, defaults) over 5 seeds, after
  the first call; `first_fit_s`: the first call of the process, which includes JAX compilation.
- `three_element_fit_s`: the same for the three-element model (104 generations by default).
- `batch_simulations_per_s`: 64 single-element parameter sets, 500 RK4 steps each, per second.
- Reference measured in the same run: the thesis' appendix procedure (GAOPT + Sim1 + FIT,
  200 generations as the thesis' text says, population 20) transcribed to NumPy with the
  simulation batched per generation, on the same record resampled to its 2e-5 s step.

Run: python benchmarks/bench_lumped.py
"""

import json
import os
import platform
import time

import numpy as np

from ballimpact.lumped import MODELS, fit
from ballimpact.lumped.synthetic import SINGLE, THREE, clean, noisy
from ballimpact.lumped.thesis import THESIS_STEP_S, sim1


def thesis_gaopt(time_s, force_n, speed, mass, generations=200, population=20, pm=0.1, seed=0):
    """Appendix GAOPT with its bounds (k 4e6..8e6, a 1..1.5, c 3000..100), arithmetic crossover
    of neighbours in a random order, tournament cloning, one-gene mutation sparing the best."""
    rng = np.random.default_rng(seed)
    grid = np.arange(0.0, time_s[-1], THESIS_STEP_S)
    measured = np.interp(grid, time_s, force_n)
    low, high = np.array([4e6, 1.0, 3000.0]), np.array([8e6, 1.5, 100.0])

    def fitness(farm):
        pulses, *_ = sim1(farm[:, 0], farm[:, 1], farm[:, 2], np.full(len(farm), mass), speed)
        out = []
        for pulse in pulses:
            n = pulse.size
            ref = measured[:n] if n <= measured.size else np.r_[measured, np.zeros(n - measured.size)]
            out.append(np.sqrt(np.sum((pulse - ref) ** 2) / n))
        return np.array(out)

    farm = low + (high - low) * rng.random((population, 3))
    best, best_fit = None, np.inf
    for _ in range(generations):
        order = rng.permutation(population)
        pairs = np.c_[order, np.roll(order, -1)]
        w = rng.random((population, 1))
        children = np.vstack([w * farm[pairs[:, 0]] + (1 - w) * farm[pairs[:, 1]],
                              (1 - w) * farm[pairs[:, 0]] + w * farm[pairs[:, 1]]])
        everyone = np.vstack([farm, children])
        scores = fitness(everyone)
        duel = rng.permutation(2 * population).reshape(population, 2)
        winners = np.where(scores[duel[:, 0]] <= scores[duel[:, 1]], duel[:, 0], duel[:, 1])
        farm, farm_fit = everyone[winners], scores[winners]
        if farm_fit.min() < best_fit:
            best, best_fit = farm[np.argmin(farm_fit)].copy(), farm_fit.min()
        spare = np.argmin(farm_fit)
        for i in np.flatnonzero(rng.random(population) < pm):
            if i != spare:
                gene = rng.integers(3)
                farm[i, gene] = low[gene] + (high[gene] - low[gene]) * rng.random()
    return best, best_fit


def timed(call):
    start = time.perf_counter()
    value = call()
    return time.perf_counter() - start, value


def main():
    truth = clean("single_element", SINGLE)
    records = [noisy(truth, 0.02, seed) for seed in range(6)]
    first_s, _ = timed(lambda: fit(records[0], "single_element", seed=0))
    runs = [timed(lambda r=r, s=s: fit(r, "single_element", seed=s))
            for s, r in enumerate(records[1:], 1)]
    single_s = float(np.median([t for t, _ in runs]))
    alpha_errors = [abs(r.params["alpha"] / SINGLE["alpha"] - 1) for _, r in runs]

    three_truth = clean("three_element", THREE)
    timed(lambda: fit(noisy(three_truth, 0.02, 0), "three_element", generations=2))  # compile
    three = [timed(lambda s=s: fit(noisy(three_truth, 0.02, s), "three_element", seed=s))
             for s in range(3)]

    model = MODELS["single_element"]
    params = np.tile([SINGLE["k"], SINGLE["alpha"], SINGLE["c"]], (64, 1))
    params[:, 0] *= np.linspace(0.5, 2.0, 64)
    model.run_batch(params, 0.16, 20.0, 2.5e-6, 500)
    batch_s = min(timed(lambda: model.run_batch(params, 0.16, 20.0, 2.5e-6, 500))[0]
                  for _ in range(5))

    thesis_s, (thesis_best, thesis_rmse) = timed(
        lambda: thesis_gaopt(records[1].time_s - records[1].time_s[0], records[1].force_n, 20.0,
                             0.16))

    print(json.dumps({
        "machine": {"platform": platform.platform(), "processor": platform.machine(),
                    "cpu_count": os.cpu_count(), "python": platform.python_version()},
        "record": "single element k=2e7 N/m^1.3, alpha=1.3, c=80 N s/m, 0.16 kg, 20 m/s, "
                  "2% noise, 200 kHz",
        "single_element_fit_s": single_s,
        "first_fit_s": first_s,
        "single_element_evaluations": runs[0][1].evaluations,
        "single_element_alpha_error_max": max(alpha_errors),
        "single_element_nrmse_median": float(np.median([r.nrmse for _, r in runs])),
        "three_element_fit_s": float(np.median([t for t, _ in three])),
        "three_element_nrmse_median": float(np.median([r.nrmse for _, r in three])),
        "batch_simulations_per_s": 64 / batch_s,
        "thesis_procedure_s": thesis_s,
        "thesis_procedure_rmse_n": float(thesis_rmse),
        "thesis_procedure_params": dict(zip(("k", "alpha", "c"), map(float, thesis_best))),
        "ratio_single_element_fit_to_thesis_procedure": single_s / thesis_s,
        "thesis_reported_fit_s": 2.0,
        "goal_fit_s": 0.5,
    }, indent=2))


if __name__ == "__main__":
    main()
