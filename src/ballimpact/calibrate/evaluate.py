"""Objectives of designs, each run through the FE engine against every test.

Per test: force NRMSE on the aligned pulses (`comparison.aligned_nrmse`, fraction of the
test's peak): the run's pulse from its first touch against the test's from its contact start as
its processing found it, at the best time shift within +/- `comparison.SHIFT_FRACTION` of the test's contact
time. The contact start of a noisy record is uncertain by a few samples (10-30 us at 100 kHz with
1% noise, which alone would be an NRMSE of several percent); and the start found in a clean pulse
at the same threshold is later than the first touch by another 30 us, so the run's own measured
start is no reference either. |COR error|, |relative contact-time error|, |relative peak-force error|. Several
tests: the mean over the tests. A design whose run fails (or whose pulse cannot be processed) gets
no objectives (NaN) and its reason.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, InputWarning
from ..comparison import aligned_nrmse, compare, measured_like
from .problem import CalibrationProblem, sub_ball

#: objective -> key of `comparison.compare`, taken in absolute value
_KEYS = {"nrmse": "force_nrmse", "cor": "cor_error", "contact_time": "contact_time_relative_error",
         "peak_force": "peak_force_relative_error", "compression": "compression_nrmse"}


@dataclass
class Evaluation:
    """Designs (unit coordinates) and what the FE made of them."""

    unit: np.ndarray          # (n, n_free)
    objectives: np.ndarray    # (n, n_objectives), NaN where failed
    per_test: list[list[dict]]  # [design][test] comparison dicts (empty where failed)
    failed: list[str | None]  # reason per design
    wall_time_s: float


def compare_run(test, fe) -> dict:
    """The comparison of an FE run with a test (`comparison.compare` keys): the force
    NRMSE of the run's pulse from its first touch, aligned with the test's; contact time, peak
    and COR of the run measured as the test was (`measured_like`). A compression test's with
    its FE curve: `compression.compare_compression`."""
    from .compression import compare_compression, is_compression

    if is_compression(test):
        return compare_compression(test, fe)
    simulated = measured_like(test, fe)
    nrmse = aligned_nrmse(test, fe.history["time_s"], fe.history["contact_force_n"])
    return compare(test.features.values, simulated.values, nrmse)


def objective_values(comparisons: list[dict], objectives) -> np.ndarray:
    """Objectives (mean over the tests they apply to: `compression` over the compression tests,
    the others over the impact tests) from one design's comparisons."""
    return np.array([np.mean([abs(c[_KEYS[o]]) for c in comparisons if _KEYS[o] in c])
                     for o in objectives])


def evaluate(problem: CalibrationProblem, unit: np.ndarray, options) -> Evaluation:
    """Run designs `unit` (n, n_free) against every test: one vmapped batch per test. A design
    whose combination of values is not a valid ball (each bound alone is, e.g. C10 + C01 <= 0 at
    a corner) fails with the reason, as a failed run does."""
    import time

    from ..fe import load_ball, simulate_batch
    from ..fe.result import FailedRun
    from .compression import is_compression

    started = time.perf_counter()
    unit = np.atleast_2d(np.asarray(unit, dtype=np.float64))
    n = len(unit)
    per_test: list[list[dict]] = [[] for _ in range(n)]
    failed: list[str | None] = [None] * n
    specs = [problem.spec(u) for u in unit]
    valid = []
    with warnings.catch_warnings():  # an allowed check warned once, for the template
        warnings.simplefilter("ignore", InputWarning)
        for i, spec in enumerate(specs):
            try:
                load_ball(spec, allow=problem.allow)
                valid.append(i)
            except InputError as error:
                failed[i] = f"not a valid ball: {error}"
        tested = [[load_ball(sub_ball(specs[i], test.layers), allow=problem.allow)
                   for i in valid] for test in problem.tests]
    for test, balls in zip(problem.tests, tested):
        if not valid:
            break
        if is_compression(test):
            _evaluate_compression(test, balls, valid, options, per_test, failed)
            continue
        # a search visits many designs: their material-stability warnings would bury the
        # output; the chosen design's runs warn again
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", InputWarning)
            runs = simulate_batch(balls, test.impact_speed_m_s, options, on_failure="return",
                                  allow=problem.allow)
        for i, fe in zip(valid, runs):
            if failed[i] is not None:
                continue
            if isinstance(fe, FailedRun):
                failed[i] = f"test {test.name}: {fe.reason}"
                continue
            try:
                per_test[i].append(compare_run(test, fe))
            except InputError as error:
                failed[i] = f"test {test.name}: the simulated pulse cannot be processed ({error})"
    objectives = np.full((n, len(problem.objectives)), np.nan)
    for i in range(n):
        if failed[i] is None:
            objectives[i] = objective_values(per_test[i], problem.objectives)
        else:
            per_test[i] = []
    return Evaluation(unit, objectives, per_test, failed, time.perf_counter() - started)


def _evaluate_compression(test, balls, valid, options, per_test, failed) -> None:
    """One quasi-static compression solve per design (no batching: each is a sequence of
    Newton solves on the host); a solve that does not converge fails its design."""
    from ..errors import SimulationError
    from .compression import compare_compression, compression_run

    for i, ball in zip(valid, balls):
        if failed[i] is not None:
            continue
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", InputWarning)
                curve = compression_run(test, ball, options)
        except (SimulationError, InputError) as error:
            failed[i] = f"test {test.name}: {error}"
            continue
        per_test[i].append(compare_compression(test, curve))
