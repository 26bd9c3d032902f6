"""Multi-objective search of the free parameters with pymoo: NSGA-II for up to three objectives,
NSGA-III (Das-Dennis reference directions) for four. Each generation's population is one batch
of FE runs per test (`evaluate`, vmapped in groups).

Checkpoint and resume: every evaluated design is appended to `evaluations.parquet` in the output
folder after each generation. A resumed search replays the seeded algorithm from the start and
takes every design already in that file from it instead of running it again (the same seed gives
the same designs), so a stopped search loses at most the generation it was in, and nothing is
stored as a pickle.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from .evaluate import evaluate
from .problem import CalibrationProblem

#: objectives of a failed design for the algorithm (it is also infeasible)
FAILED_OBJECTIVE = 1e6
EVALUATIONS_FILE = "evaluations.parquet"


@dataclass
class SearchResult:
    """Every evaluated design in order, with the generation it was made in."""

    problem: CalibrationProblem
    unit: np.ndarray            # (n, n_free)
    objectives: np.ndarray      # (n, n_obj), NaN where failed
    generation: np.ndarray      # (n,)
    failed: list
    per_test: list
    fe_runs: int                # runs made in this call (not taken from the checkpoint)
    wall_time_s: float
    algorithm: str

    def pareto(self) -> np.ndarray:
        """Indices of the non-dominated feasible designs (duplicates dropped)."""
        from pymoo.util.nds.non_dominated_sorting import NonDominatedSorting

        ok = np.flatnonzero(np.all(np.isfinite(self.objectives), axis=1))
        if ok.size == 0:
            return ok
        _, first = np.unique(self.objectives[ok], axis=0, return_index=True)
        ok = ok[np.sort(first)]
        front = NonDominatedSorting().do(self.objectives[ok], only_non_dominated_front=True)
        return ok[np.sort(front)]

    def convergence(self) -> dict[str, np.ndarray]:
        """Per generation: the best value so far of each objective and the hypervolume so far of
        the front, normalised between the ideal point and the worst feasible values of the first
        generation (reference point 1.1 in every normalised objective)."""
        from pymoo.indicators.hv import HV

        gens = np.unique(self.generation)
        feasible = np.all(np.isfinite(self.objectives), axis=1)
        first = self.objectives[(self.generation == gens[0]) & feasible]
        ideal = np.nanmin(self.objectives, axis=0)
        worst = first.max(axis=0) if len(first) else np.nanmax(self.objectives, axis=0)
        span = np.where(worst > ideal, worst - ideal, 1.0)
        indicator = HV(ref_point=np.full(self.objectives.shape[1], 1.1))
        best, volume = [], []
        for g in gens:
            sofar = self.objectives[(self.generation <= g) & feasible]
            best.append(sofar.min(axis=0) if len(sofar) else np.full(sofar.shape[1], np.nan))
            volume.append(float(indicator((sofar - ideal) / span)) if len(sofar) else 0.0)
        return {"generation": gens, "best": np.array(best), "hypervolume": np.array(volume)}


def _algorithm(n_objectives: int, population: int):
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.algorithms.moo.nsga3 import NSGA3
    from pymoo.util.ref_dirs import get_reference_directions

    if n_objectives <= 3:
        return "nsga2", NSGA2(pop_size=population, eliminate_duplicates=True)
    partitions = 1
    while _count_directions(n_objectives, partitions + 1) <= population:
        partitions += 1
    directions = get_reference_directions("das-dennis", n_objectives, n_partitions=partitions)
    return "nsga3", NSGA3(ref_dirs=directions, pop_size=population, eliminate_duplicates=True)


def _count_directions(m: int, p: int) -> int:
    from math import comb

    return comb(m + p - 1, p)


def search(problem: CalibrationProblem, options, *, population: int = 24, generations: int = 8,
           seed: int = 0, out: Path | None = None, resume: bool = False,
           progress=None) -> SearchResult:
    """Multi-objective search; `out` (a folder) keeps the checkpoint (`EVALUATIONS_FILE`).
    `progress(generation, generations, fe_runs)` after each generation."""
    from pymoo.core.callback import Callback
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    if not (isinstance(population, int) and population >= 4):
        raise InputError(f"--population {population}: must be an integer >= 4")
    if not (isinstance(generations, int) and generations >= 1):
        raise InputError(f"--generations {generations}: must be an integer >= 1")
    started = time.perf_counter()
    n_obj = len(problem.objectives)
    cache = _load_checkpoint(problem, out) if resume else {}
    if out is not None and not resume and (out / EVALUATIONS_FILE).exists():
        raise InputError(f"--out {out}: holds a search already ({EVALUATIONS_FILE}); use "
                         "--resume to continue it or another folder")
    rows: dict[str, list] = {"unit": [], "objectives": [], "generation": [], "failed": [],
                             "per_test": []}
    state = {"generation": 0, "fe_runs": 0}

    class FEProblem(Problem):
        def __init__(self):
            super().__init__(n_var=len(problem.free), n_obj=n_obj, n_ieq_constr=1, xl=0.0,
                             xu=1.0)

        def _evaluate(self, x, out_, *args, **kwargs):
            x = np.asarray(x, np.float64)
            missing = [i for i, xi in enumerate(x) if xi.tobytes() not in cache]
            if missing:
                done = evaluate(problem, x[missing], options)
                state["fe_runs"] += len(missing) * len(problem.tests)
                for j, i in enumerate(missing):
                    cache[x[i].tobytes()] = (done.objectives[j], done.failed[j], done.per_test[j])
            f = np.empty((len(x), n_obj))
            g = np.empty((len(x), 1))
            for i, xi in enumerate(x):
                objectives, failed, per_test = cache[xi.tobytes()]
                f[i] = FAILED_OBJECTIVE if failed else objectives
                g[i] = 1.0 if failed else -1.0
                rows["unit"].append(xi)
                rows["objectives"].append(objectives)
                rows["generation"].append(state["generation"])
                rows["failed"].append(failed)
                rows["per_test"].append(per_test)
            out_["F"], out_["G"] = f, g

    class Checkpoint(Callback):
        def notify(self, algorithm):
            if out is not None:
                _write_evaluations(problem, rows, out)
            state["generation"] += 1
            if progress is not None:
                progress(state["generation"], generations, state["fe_runs"])

    name, algorithm = _algorithm(n_obj, population)
    minimize(FEProblem(), algorithm, ("n_gen", generations), seed=seed, callback=Checkpoint(),
             verbose=False)
    return SearchResult(problem, np.array(rows["unit"]), np.array(rows["objectives"]),
                        np.array(rows["generation"]), rows["failed"], rows["per_test"],
                        state["fe_runs"], time.perf_counter() - started, name)


def _columns(problem: CalibrationProblem, rows: dict) -> dict[str, list]:
    unit = np.array(rows["unit"])
    objectives = np.array(rows["objectives"])
    table: dict[str, list] = {"generation": list(map(int, rows["generation"]))}
    for j, p in enumerate(problem.free):
        table[f"u:{p.path}"] = unit[:, j].tolist()
        table[p.path] = [float(p.from_unit(x)) for x in unit[:, j]]
    for j, name in enumerate(problem.objectives):
        table[name] = objectives[:, j].tolist()
    for k, test in enumerate(problem.tests):
        for key in ("force_nrmse", "cor_error", "contact_time_relative_error",
                    "peak_force_relative_error"):
            table[f"{test.name}:{key}"] = [c[k][key] if c else float("nan")
                                           for c in rows["per_test"]]
    table["failed"] = [reason or "" for reason in rows["failed"]]
    return table


def _write_evaluations(problem: CalibrationProblem, rows: dict, out: Path) -> None:
    """Every evaluated design so far, atomically (Parquet; CSV beside it for reading)."""
    import pyarrow as pa
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    table = pa.table(_columns(problem, rows))
    tmp = out / (EVALUATIONS_FILE + ".tmp")
    pq.write_table(table, tmp)
    os.replace(tmp, out / EVALUATIONS_FILE)
    pacsv.write_csv(table, out / "evaluations.csv")


def _load_checkpoint(problem: CalibrationProblem, out: Path | None) -> dict[bytes, Any]:
    """Designs already evaluated (by their unit coordinates' bytes) from a stopped search."""
    import pyarrow.parquet as pq

    if out is None or not (out / EVALUATIONS_FILE).exists():
        if out is not None:
            print(f"resume: no {EVALUATIONS_FILE} in {out}; starting afresh", file=sys.stderr)
        return {}
    table = pq.read_table(out / EVALUATIONS_FILE).to_pydict()
    names = [f"u:{p.path}" for p in problem.free]
    tests = [f"{t.name}:force_nrmse" for t in problem.tests]
    if any(name not in table for name in names + list(problem.objectives) + tests):
        raise InputError(f"--resume: {out / EVALUATIONS_FILE} is from a calibration with other "
                         "free parameters, objectives or tests")
    unit = np.column_stack([np.asarray(table[name], np.float64) for name in names])
    for j, p in enumerate(problem.free):  # the same unit coordinates mean the same values
        if not np.allclose(p.from_unit(unit[:, j]), table[p.path], rtol=1e-12, atol=0.0):
            raise InputError(f"--resume: {out / EVALUATIONS_FILE} was made with other bounds "
                             f"of {p.path}")
    objectives = np.column_stack([np.asarray(table[o], np.float64) for o in problem.objectives])
    cache: dict[bytes, Any] = {}
    for i in range(len(unit)):
        failed = table["failed"][i] or None
        per_test = [] if failed else [
            {key: table[f"{t.name}:{key}"][i] for key in
             ("force_nrmse", "cor_error", "contact_time_relative_error",
              "peak_force_relative_error")} for t in problem.tests]
        cache[unit[i].tobytes()] = (objectives[i], failed, per_test)
    return cache
