"""Multi-objective search of the free parameters with pymoo: NSGA-II for up to three objectives,
NSGA-III (Das-Dennis reference directions) for four. Each generation's population is one batch
of FE runs per test (`evaluate`, vmapped in groups).

Checkpoint and resume: before the first run the search writes `search.json` (what determines
its designs and their objectives: free parameters and bounds, objectives, tests, template ball,
solver options, seed, population) to the output folder, and every evaluated design is written to
`evaluations.parquet` after each generation; each file is written to a temporary file and renamed
over the old one, so an interrupt leaves the last complete version. A resumed search checks that
`search.json` matches its own options, replays the seeded algorithm from the start and takes
every design already in `evaluations.parquet` from it instead of running it again (the same seed
gives the same designs), so a stopped search loses at most the generation it was in. Nothing is
stored as a pickle.

A search whose whole first generation fails stops at once (`InputError` with the first reason):
that is bounds or options that give no runnable ball, not bad luck.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..checks import check_integer
from ..errors import InputError
from ..fileio import first_line, replacing, write_atomic, write_table
from .evaluate import evaluate
from .problem import CalibrationProblem

#: objectives of a failed design for the algorithm (it is also infeasible)
FAILED_OBJECTIVE = 1e6
EVALUATIONS_FILE = "evaluations.parquet"
MANIFEST_FILE = "search.json"
#: per-test comparison columns of `EVALUATIONS_FILE`
_PER_TEST = ("force_nrmse", "cor_error", "contact_time_relative_error",
             "peak_force_relative_error")


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
    """Multi-objective search; `out` (an existing folder) keeps the checkpoint
    (`MANIFEST_FILE`, `EVALUATIONS_FILE`) and `resume` continues the search stopped there, with
    the same options but any number of generations (`open_checkpoint`). `progress(generation,
    generations, fe_runs)` after each generation. `InputError` if the whole first generation
    fails."""
    from pymoo.core.callback import Callback
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    population, generations = check_search_options(population, generations)
    started = time.perf_counter()
    n_obj = len(problem.objectives)
    cache = open_checkpoint(problem, options, seed, population, out, resume)
    # a resume with fewer generations replays part of the checkpoint: keep the whole file
    saved_rows = _saved_rows(out) if resume else 0
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
            if state["generation"] == 0:
                _stop_if_all_failed(problem, x, [cache[xi.tobytes()][1] for xi in x])
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
            if out is not None and len(rows["unit"]) > saved_rows:
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


def check_search_options(population, generations) -> tuple[int, int]:
    """(population, generations) as ints, or `InputError` naming the flag for a population or a
    number of generations the search cannot run."""
    return (check_integer("--population", population, 4,
                          note="NSGA-II needs pairs of parents from a population of at least 4"),
            check_integer("--generations", generations, 1))


def _stop_if_all_failed(problem: CalibrationProblem, unit: np.ndarray, failed: list) -> None:
    """`InputError` when every design of the first generation failed: the bounds (or the solver
    options) give no ball that runs, and more generations of failures would only cost time."""
    if not failed or not all(failed):
        return
    values = ", ".join(f"{path}={value:g}" for path, value in problem.values(unit[0]).items())
    raise InputError(f"every design of the search's first generation failed ({len(failed)} of "
                     f"{len(failed)}), so the search stops; the first ({values}): {failed[0]}; "
                     "check the --free bounds (SI units) and the solver options")


def manifest(problem: CalibrationProblem, options, seed: int, population: int) -> dict:
    """What determines a search's designs and their objectives (`MANIFEST_FILE`): a resumed
    search must match it (the number of generations may grow)."""
    solver = dataclasses.asdict(options) if dataclasses.is_dataclass(options) else dict(options)
    return {"free": [p.to_dict() for p in problem.free],
            "objectives": list(problem.objectives),
            "tests": [{"name": t.name, "layers": t.layers, "data": _test_digest(t)}
                      for t in problem.tests],
            "template": _digest(json.dumps(problem.template, sort_keys=True).encode()),
            "solver": json.loads(json.dumps(solver)), "seed": seed, "population": population}


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()[:16]


def _test_keys(test) -> tuple[str, ...]:
    """The per-test comparison columns of a test's kind."""
    from .compression import COMPARISON_KEYS, is_compression

    return COMPARISON_KEYS if is_compression(test) else _PER_TEST


def _test_digest(test) -> str:
    """A digest of what the search compares against: the test's pulse and feature values (a
    compression test's curve, platen rate and increments)."""
    from .compression import is_compression

    if is_compression(test):
        setting = json.dumps({"rate_m_s": test.rate_m_s, "steps": test.steps})
        return _digest(np.ascontiguousarray(test.deflection_m, np.float64).tobytes()
                       + np.ascontiguousarray(test.force_n, np.float64).tobytes()
                       + setting.encode())
    t, f = test.pulse
    values = json.dumps(dict(test.features.values), sort_keys=True, default=repr)
    return _digest(np.ascontiguousarray(t, np.float64).tobytes()
                   + np.ascontiguousarray(f, np.float64).tobytes() + values.encode())


def _differences(saved: dict, now: dict) -> list[str]:
    """What differs between a saved manifest and the current one, for the user."""
    out = []
    old_free = {p["path"]: p for p in saved["free"]}
    new_free = {p["path"]: p for p in now["free"]}
    if list(old_free) != list(new_free):
        out.append(f"free parameters {', '.join(old_free)} (now {', '.join(new_free)})")
    else:
        out += [f"bounds of {path} {p['low']:g}:{p['high']:g} (now {new_free[path]['low']:g}:"
                f"{new_free[path]['high']:g})" for path, p in old_free.items()
                if p != new_free[path]]
    if saved["objectives"] != now["objectives"]:
        out.append(f"objectives {','.join(saved['objectives'])} (now "
                   f"{','.join(now['objectives'])})")
    old_tests = [(t["name"], t["layers"]) for t in saved["tests"]]
    if old_tests != [(t["name"], t["layers"]) for t in now["tests"]]:
        out.append(f"tests {', '.join(n for n, _ in old_tests)} (now "
                   f"{', '.join(t['name'] for t in now['tests'])})")
    else:
        out += [f"other data in test {a['name']} (its record or processing changed)"
                for a, b in zip(saved["tests"], now["tests"]) if a["data"] != b["data"]]
    if saved["template"] != now["template"]:
        out.append("another template ball (--ball, or the results of the stages before)")
    out += [f"solver option {key} {saved['solver'].get(key)} (now {value})"
            for key, value in now["solver"].items() if saved["solver"].get(key) != value]
    out += [f"--{key} {saved[key]} (now {now[key]})" for key in ("seed", "population")
            if saved[key] != now[key]]
    return out


def has_checkpoint(out: Path | None) -> bool:
    """Whether the folder holds a search (its manifest or its evaluations)."""
    return out is not None and ((out / MANIFEST_FILE).exists()
                                or (out / EVALUATIONS_FILE).exists())


def open_checkpoint(problem: CalibrationProblem, options, seed: int, population: int,
                    out: Path | None, resume: bool, *, write: bool = True) -> dict[bytes, Any]:
    """Check the output folder and return the designs already evaluated (by the bytes of their
    unit coordinates): none for a new search, whose manifest is written here (unless `write` is
    False: a check only). `InputError` for a folder that holds a search without `resume`, a
    resume without one, a manifest of other options, and a damaged or foreign checkpoint
    file."""
    now = manifest(problem, options, seed, population)
    if out is None:
        if resume:
            raise InputError("--resume: needs --out (the folder of the stopped search)")
        return {}
    if not resume:
        if has_checkpoint(out):
            raise InputError(f"--out {out}: holds a search already ({MANIFEST_FILE}, "
                             f"{EVALUATIONS_FILE}); add --resume to continue it, or use another "
                             "folder")
        if write:
            write_atomic(out / MANIFEST_FILE, json.dumps(now, indent=2))
        return {}
    saved = read_manifest(out)
    differences = _differences(saved, now)
    if differences:
        raise InputError(f"--resume: {out / MANIFEST_FILE} is a search with other options: "
                         f"{'; '.join(differences)}; resume with the options it was started "
                         "with, or use another --out")
    if not (out / EVALUATIONS_FILE).exists():
        return {}  # stopped in its first generation
    return _load_checkpoint(problem, out)


def read_manifest(out: Path) -> dict:
    """The manifest of the search in `out`; `InputError` naming the file if it is missing or
    not one."""
    path = out / MANIFEST_FILE
    if not path.exists():
        what = (f"{EVALUATIONS_FILE} but no {MANIFEST_FILE} (not written by this version)"
                if (out / EVALUATIONS_FILE).exists() else f"no {MANIFEST_FILE}")
        raise InputError(f"--resume: {out} holds {what}: there is no search to resume there; "
                         "run without --resume in a new folder")
    try:
        saved = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise InputError(f"--resume: {path} is damaged ({first_line(error)}); delete the "
                         "folder's search files to start afresh") from None
    wrong = _malformed(saved)
    if wrong:
        raise InputError(f"--resume: {path} is not a search manifest ({wrong}); delete the "
                         "folder's search files to start afresh")
    return saved


def _malformed(saved: Any) -> str | None:
    """What keeps a loaded manifest from being compared (`_differences`), or None."""
    if not isinstance(saved, dict):
        return "not a JSON object"
    missing = [key for key in ("free", "objectives", "tests", "template", "solver", "seed",
                               "population") if key not in saved]
    if missing:
        return f"no {', '.join(missing)}"
    entries = {"free": ("path", "low", "high"), "tests": ("name", "layers", "data")}
    for key, fields in entries.items():
        if not (isinstance(saved[key], list) and all(
                isinstance(item, dict) and all(f in item for f in fields) for item in saved[key])):
            return f"{key}: expected a list of entries with {', '.join(fields)}"
        if key == "free" and not all(isinstance(item["low"], (int, float))
                                     and isinstance(item["high"], (int, float))
                                     for item in saved[key]):
            return "free: bounds are not numbers"
    if not isinstance(saved["solver"], dict) or not isinstance(saved["objectives"], list):
        return "solver: expected an object, objectives: a list"
    return None


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
        for key in _test_keys(test):
            table[f"{test.name}:{key}"] = [c[k][key] if c else float("nan")
                                           for c in rows["per_test"]]
    table["failed"] = [reason or "" for reason in rows["failed"]]
    return table


def _write_evaluations(problem: CalibrationProblem, rows: dict, out: Path) -> None:
    """Every evaluated design so far, atomically (Parquet; CSV beside it for reading, numbers
    as the shortest text that reads back exactly, `fileio.write_table`)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    columns = _columns(problem, rows)
    with replacing(out / EVALUATIONS_FILE) as tmp:
        pq.write_table(pa.table(columns), tmp)
    write_table(out / "evaluations.csv", list(columns), zip(*columns.values()), "")


def _saved_rows(out: Path | None) -> int:
    """Designs in the checkpoint of `out` (0 if none)."""
    import pyarrow.parquet as pq

    if out is None or not (out / EVALUATIONS_FILE).exists():
        return 0
    return pq.ParquetFile(out / EVALUATIONS_FILE).metadata.num_rows


def _load_checkpoint(problem: CalibrationProblem, out: Path) -> dict[bytes, Any]:
    """Designs already evaluated (by their unit coordinates' bytes) from a stopped search;
    `InputError` naming the file and what is wrong with it."""
    import pyarrow.parquet as pq

    path = out / EVALUATIONS_FILE
    try:
        table = pq.read_table(path).to_pydict()
    except Exception as error:  # noqa: BLE001 - pyarrow's errors for a damaged file vary
        raise InputError(f"--resume: {path} cannot be read ({first_line(error)}): it is "
                         f"damaged; delete it to run this search's designs again") from None
    names = [f"u:{p.path}" for p in problem.free]
    needed = (["generation", "failed"] + names + [p.path for p in problem.free]
              + list(problem.objectives)
              + [f"{t.name}:{key}" for t in problem.tests for key in _test_keys(t)])
    missing = [name for name in needed if name not in table]
    if missing:
        raise InputError(f"--resume: {path} is not this search's checkpoint (no column "
                         f"{missing[0]!r}: other free parameters, objectives or tests)")
    try:
        unit = np.column_stack([np.asarray(table[name], np.float64) for name in names])
        objectives = np.column_stack([np.asarray(table[o], np.float64)
                                      for o in problem.objectives])
        per_test = {name: np.asarray(table[name], np.float64) for name in needed
                    if ":" in name and not name.startswith("u:")}
        failed = [str(reason) if reason else None for reason in table["failed"]]
    except (TypeError, ValueError) as error:
        raise InputError(f"--resume: {path} holds a column that is not numbers "
                         f"({first_line(error)}): it is damaged; delete it") from None
    if not np.all(np.isfinite(unit) & (unit >= 0.0) & (unit <= 1.0)):
        raise InputError(f"--resume: {path} holds unit coordinates outside [0, 1]: it is "
                         "damaged; delete it")
    for j, p in enumerate(problem.free):  # the same unit coordinates mean the same values
        if not np.allclose(p.from_unit(unit[:, j]), table[p.path], rtol=1e-12, atol=0.0):
            raise InputError(f"--resume: {path} was made with other bounds of {p.path}")
    cache: dict[bytes, Any] = {}
    for i in range(len(unit)):
        tests = [] if failed[i] else [
            {key: float(per_test[f"{t.name}:{key}"][i]) for key in _test_keys(t)}
            for t in problem.tests]
        cache[unit[i].tobytes()] = (objectives[i], failed[i], tests)
    return cache
