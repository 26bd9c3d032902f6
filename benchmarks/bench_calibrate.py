"""Calibration costs on this machine, printed as JSON.

1. Gradients through the explicit solver (universal ball, 20 m/s, four parameters C10, C01, g1,
   tau1): wall time of one standard FE run, one fixed-increment misfit evaluation, the forward-mode
   Jacobian (jax.jacfwd, four tangents plus the time shift) and the reverse-mode gradient
   (jax.grad with checkpointed chunks), as ratios to the misfit evaluation measured in the same
   run; and their largest relative difference from central differences.
2. NSGA-II against the gradient refinement on the recovery problem: a two-layer ball (core
   Mooney-Rivlin + Prony, cover Mooney-Rivlin; six free constants) against synthetic tests at 10
   and 25 m/s with 1% noise. NSGA-II (population 24, 8 generations) with a knee decision, and the
   Levenberg-Marquardt refinement from the template alone: FE runs, wall times, objectives.

    python benchmarks/bench_calibrate.py [--element-size-m 1.5e-3]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

import jax
import numpy as np

from ballimpact.calibrate import (
    CalibrationProblem,
    free_parameter,
    refine,
    search,
    smooth_misfits,
    standard_runs,
)
from ballimpact.calibrate.decision import decide
from ballimpact.calibrate.gradient import CHUNK_STEPS, central_differences
from ballimpact.calibrate.evaluate import compare_run, objective_values
from ballimpact.calibrate.problem import get_value
from ballimpact.calibrate.synthetic import TWO_LAYER_TRUTH, synthetic_test, two_layer_recovery
from ballimpact.fe import SolverOptions
from ballimpact.balls.ball import UNIVERSAL_DENSITY_KG_M3, universal_spec

def _timed(fn, repeat: int = 3) -> float:
    fn()  # compile
    started = time.perf_counter()
    for _ in range(repeat):
        fn()
    return (time.perf_counter() - started) / repeat


def gradient_costs(options) -> dict:
    truth = universal_spec({"c10_pa": 4.0e6, "c01_pa": -0.4e6, "g1": 0.7, "tau1_s": 8e-5},
                           0.036, UNIVERSAL_DENSITY_KG_M3)
    test = synthetic_test("20m/s", truth, 20.0, options, 0.0, np.random.default_rng(0))
    template = universal_spec({"c10_pa": 4.5e6, "c01_pa": -0.3e6, "g1": 0.6, "tau1_s": 1e-4},
                              0.036, UNIVERSAL_DENSITY_KG_M3)
    m = "layers.ball.material."
    bounds = {m + "c10_pa": (3e6, 7e6), m + "c01_pa": (-1e6, 0.5e6), m + "prony.0.g": (0.3, 0.9),
              m + "prony.0.tau_s": (2e-5, 5e-4)}
    problem = CalibrationProblem(template, [test], [free_parameter(template, p, *b)
                                                    for p, b in bounds.items()])
    u = problem.start_unit()
    runs = standard_runs(problem, u, options)
    misfit = smooth_misfits(problem, options, runs)[0]
    standard = _timed(lambda: standard_runs(problem, u, options))
    value = _timed(lambda: misfit.evaluate(u))
    jacobian = _timed(lambda: misfit.evaluate(u, "jacobian"))
    reverse = _timed(lambda: misfit.evaluate(u, "grad"))
    r, jac = misfit.evaluate(u, "jacobian")
    forward_grad = 2 * jac[:, :-1].T @ r
    reverse_grad = misfit.evaluate(u, "grad")[1][:-1]
    central = central_differences(misfit, u)
    return {"parameters": list(bounds), "steps": misfit.n_chunks * CHUNK_STEPS,
            "elements": runs[0].elements,
            "standard_run_s": standard, "misfit_evaluation_s": value,
            "jacobian_forward_mode_s": jacobian, "gradient_reverse_mode_s": reverse,
            "jacobian_over_misfit": jacobian / value, "gradient_over_misfit": reverse / value,
            "forward_vs_central_max_relative_difference":
                float(np.max(np.abs(forward_grad / central - 1))),
            "reverse_vs_central_max_relative_difference":
                float(np.max(np.abs(reverse_grad / central - 1)))}


def nsga_against_gradient(options, population: int, generations: int) -> dict:
    problem = two_layer_recovery(options)
    started = time.perf_counter()
    found = search(problem, options, population=population, generations=generations, seed=0)
    front = found.pareto()
    chosen = decide(found.objectives[front]).index
    nsga = {"fe_runs": found.fe_runs, "wall_time_s": time.perf_counter() - started,
            "knee_objectives": dict(zip(problem.objectives,
                                        found.objectives[front[chosen]].tolist())),
            "best_nrmse_on_front": float(found.objectives[front, 0].min()),
            "front_size": int(len(front))}
    refined = refine(problem, options)
    comparisons = [compare_run(t, fe) for t, fe in zip(problem.tests, refined.runs)]
    recovered = {p: {"value": refined.values[p], "truth": get_value(TWO_LAYER_TRUTH, p),
                     "standard_error": refined.standard_error[p]} for p in refined.values}
    gradient = {"fe_runs": refined.fe_runs,
                "misfit_evaluations": refined.residual_evaluations,
                "jacobian_evaluations": refined.jacobian_evaluations,
                "wall_time_s": refined.wall_time_s,
                "objectives": dict(zip(problem.objectives,
                                       objective_values(comparisons,
                                                        problem.objectives).tolist())),
                "per_test_nrmse": [c["force_nrmse"] for c in comparisons],
                "per_test_cor_error": [c["cor_error"] for c in comparisons],
                "recovered": recovered}
    return {"nsga2": nsga, "gradient_from_template": gradient}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--element-size-m", type=float, default=1.5e-3)
    parser.add_argument("--population", type=int, default=24)
    parser.add_argument("--generations", type=int, default=8)
    args = parser.parse_args()
    options = SolverOptions(element_size_m=args.element_size_m)
    out = {"machine": {"platform": platform.platform(), "processor": platform.machine(),
                       "cpu_count": os.cpu_count(), "python": platform.python_version()},
           "jax": jax.__version__, "backend": jax.default_backend(),
           "element_size_m": args.element_size_m}
    out["gradients"] = gradient_costs(options)
    out["recovery"] = nsga_against_gradient(options, args.population, args.generations)
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
