"""A calibration from start to end: stages in order, each a search and/or a gradient refinement
and a decision, earlier stages' results frozen into the template of the next (thesis 5.2-5.3:
the core on the core's test, then the midsole on the core + midsole test, then the cover on the
ball's test; and within a component the hyperelastic constants before the Prony terms).

A stage names its free parameters (paths or shell-style patterns matched against the `--free`
paths), its tests (names) and optionally its objectives; one stage with everything is the
default.
"""

from __future__ import annotations

import fnmatch
import re
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..progress import progress_line
from .compression import is_compression, refine_compression
from .decision import decide
from .evaluate import compare_run, objective_values
from .gradient import refine, standard_runs
from .problem import (
    OBJECTIVES,
    CalibrationProblem,
    check_objectives_apply,
    default_objectives,
    free_parameter,
)

METHODS = ("nsga2", "gradient", "nsga2+gradient")


@dataclass(frozen=True)
class Stage:
    name: str
    free: tuple[str, ...] = ("*",)          # patterns of --free paths
    tests: tuple[str, ...] | None = None    # test names; None: all
    objectives: tuple[str, ...] | None = None  # None: the calibration's


def parse_stage(text: str, index: int) -> Stage:
    """`free=PATTERN,...;tests=NAME,...;objectives=nrmse,cor;name=TEXT` (all parts optional)."""
    fields: dict[str, Any] = {"name": f"stage{index + 1}"}
    for part in filter(None, (p.strip() for p in text.split(";"))):
        key, sep, value = part.partition("=")
        key = key.strip()
        if not sep or key not in ("free", "tests", "objectives", "name"):
            raise InputError(f"--stage {text!r}: expected KEY=VALUE parts separated by ';' with "
                             "keys free, tests, objectives, name")
        items = tuple(v.strip() for v in value.split(",") if v.strip())
        fields[key] = value.strip() if key == "name" else items
    return Stage(**fields)


@dataclass
class StageResult:
    stage: Stage
    problem: CalibrationProblem
    unit: np.ndarray
    values: dict[str, float]
    objectives: dict[str, float]
    per_test: list[dict]
    search: Any = None
    decision: Any = None
    refinement: Any = None
    fe_runs: int = 0
    wall_time_s: float = 0.0
    runs: list = field(default_factory=list, repr=False)  # FE runs of the chosen design

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "name": self.stage.name, "free": [p.to_dict() for p in self.problem.free],
            "tests": [t.name for t in self.problem.tests],
            "objectives": list(self.problem.objectives),
            "chosen": {"parameters": self.values, "objectives": self.objectives,
                       "per_test": self.per_test},
            "fe_runs": self.fe_runs, "wall_time_s": self.wall_time_s}
        if self.search is not None:
            front = self.search.pareto()
            out["search"] = {"algorithm": self.search.algorithm,
                             "designs": int(len(self.search.unit)),
                             "fe_runs": self.search.fe_runs,
                             "wall_time_s": self.search.wall_time_s}
            out["pareto"] = [{"parameters": self.problem.values(self.search.unit[i]),
                              "objectives": dict(zip(self.problem.objectives,
                                                     self.search.objectives[i].tolist()))}
                             for i in front]
            out["decision"] = {"method": self.decision.method, "reason": self.decision.reason}
        if self.refinement is not None:
            out["refinement"] = self.refinement.to_dict()
        return out


def run_stage(problem: CalibrationProblem, stage: Stage, options, *, method: str,
              population: int, generations: int, seed: int, decision: str, weights,
              out: Path | None, resume: bool, max_evaluations: int,
              verbose: bool = True) -> StageResult:
    from .search import search

    started = time.perf_counter()
    u = problem.start_unit()
    result = StageResult(stage, problem, u, {}, {}, [])
    fe_runs = 0
    if method in ("nsga2", "nsga2+gradient"):
        def progress(g, total, runs):
            if verbose:
                progress_line(f"  {stage.name}: generation {g}/{total}, {runs} FE runs, "
                     f"{time.perf_counter() - started:.0f} s")
        found = search(problem, options, population=population, generations=generations,
                       seed=seed, out=out, resume=resume, progress=progress)
        front = found.pareto()
        result.search = found
        result.decision = decide(found.objectives[front], decision, weights)
        u = found.unit[front[result.decision.index]]
        fe_runs += found.fe_runs
        if verbose:
            progress_line(f"  {stage.name}: chose by {result.decision.reason}")
    if method in ("gradient", "nsga2+gradient"):
        def progress(i, misfit):
            if verbose:
                progress_line(f"  {stage.name}: gradient refinement, misfit evaluation {i}: "
                     f"{misfit:.4g} ({time.perf_counter() - started:.0f} s)")
        if all(is_compression(t) for t in problem.tests):
            result.refinement = refine_compression(problem, options, start=u,
                                                   max_evaluations=max_evaluations,
                                                   progress=progress)
        else:  # `_check` refused a stage that mixes them
            result.refinement = refine(problem, options, start=u,
                                       max_evaluations=max_evaluations, progress=progress)
        u = result.refinement.unit
        fe_runs += result.refinement.fe_runs
    runs = result.refinement.runs if result.refinement is not None else \
        standard_runs(problem, u, options)
    fe_runs += 0 if result.refinement is not None else len(problem.tests)
    comparisons = [compare_run(t, fe) for t, fe in zip(problem.tests, runs)]
    result.unit, result.values = u, problem.values(u)
    result.objectives = dict(zip(problem.objectives,
                                 objective_values(comparisons, problem.objectives).tolist()))
    result.per_test = [{"test": t.name, **c} for t, c in zip(problem.tests, comparisons)]
    result.runs = runs
    result.fe_runs, result.wall_time_s = fe_runs, time.perf_counter() - started
    if out is not None:
        _stage_files(result, out)
    return result


def _stage_files(result: StageResult, out: Path) -> None:
    """The stage's pictures, and its Pareto front as `pareto.csv` (parameters, objectives;
    numbers as the shortest text that reads back exactly)."""
    from ..fileio import write_table
    from .plots import plot_convergence, plot_pareto, plot_pulses

    if result.search is not None:
        front = result.search.pareto()
        rows = result.to_dict()["pareto"]
        columns = {**{p: [r["parameters"][p] for r in rows] for p in result.problem.names},
                   **{o: [r["objectives"][o] for r in rows] for o in result.problem.objectives}}
        write_table(out / "pareto.csv", list(columns), zip(*columns.values()), "")
        plot_pareto(result.search, int(front[result.decision.index]), out / "pareto.png",
                    f"{result.stage.name}: {result.search.algorithm}, "
                    f"{len(result.search.unit)} designs")
        plot_convergence(result.search, out / "convergence.png", result.stage.name)
    plot_pulses(result.problem.tests, result.runs, out / "pulses.png",
                f"{result.stage.name}: calibrated")


def _check(template, tests, bounds, options, objectives, method, stages, decision, weights,
           max_evaluations, population, generations, allow) -> None:
    """Everything that can be checked before the first FE run (errors name the flag)."""
    from ..fe import load_ball
    from ..checks import check_allow, check_integer
    from ..fe.speed_range import check_fe_speed
    from .compression import check_against_ball
    from .problem import sub_ball
    from .search import check_search_options

    if method not in METHODS:
        raise InputError(f"--method {method!r}: allowed {', '.join(METHODS)}")
    if "nsga2" in method:
        check_search_options(population, generations)
    allow = check_allow(allow)
    for flag, chosen in ([("--objectives", objectives)] if objectives is not None else []) + [
            (f"--stage {s.name}: objectives", s.objectives) for s in stages if s.objectives]:
        if not chosen or any(o not in OBJECTIVES for o in chosen):
            raise InputError(f"{flag}={','.join(chosen)}: allowed any of {', '.join(OBJECTIVES)}")
    if "gradient" in method and options.precision != "float64":
        raise InputError(f"--precision {options.precision}: the gradient refinement needs "
                         "float64 (in float32 round-off over thousands of steps dominates the "
                         "derivatives)")
    if "gradient" in method:
        check_integer("--max-evaluations", max_evaluations, 1)
    for path, (low, high) in bounds.items():
        free_parameter(template, path, low, high, allow)
    for test in tests:
        if is_compression(test):
            try:
                ball = load_ball(sub_ball(template, test.layers), allow=allow)
            except InputError as error:
                raise InputError(f"--compression {test.source or test.name}: {error}") from None
            check_against_ball(test, ball)
            continue
        try:
            sub_ball(template, test.layers)
            check_fe_speed(test.impact_speed_m_s, allow)
        except InputError as error:
            raise InputError(f"--test {test.name}: {error}") from None
    names = [s.name for s in stages]
    for stage in stages:
        if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9._-]*", stage.name or ""):
            raise InputError(f"--stage name={stage.name!r}: letters, digits, '.', '_' and '-' "
                             "only (it names the stage's folder)")
        if names.count(stage.name) > 1:
            raise InputError(f"--stage name={stage.name}: stage names must be unique")
        select_free(stage, bounds)
        chosen_tests = select_tests(stage, tests)
        stage_objectives = stage_objectives_of(stage, objectives, chosen_tests)
        check_objectives_apply(stage_objectives, chosen_tests,
                               f"--stage {stage.name}" if stage.objectives or len(stages) > 1
                               else "--objectives")
        kinds = {is_compression(t) for t in chosen_tests}
        if "gradient" in method and len(kinds) > 1:
            raise InputError(f"--stage {stage.name}: --method {method} cannot refine against "
                             "compression and impact tests in one stage (the compression "
                             "curve's Jacobian is by finite differences, the impact runs' by "
                             "JAX); give them separate stages (tests=...)")
        n_objectives = len(stage_objectives)
        if (weights is not None and "nsga2" in method and decision in ("pseudo-weights", "asf")
                and len(weights) != n_objectives):
            raise InputError(f"--weights: {len(weights)} given, stage {stage.name} has "
                             f"{n_objectives} objectives")


def stage_objectives_of(stage: Stage, objectives, tests) -> tuple[str, ...]:
    """A stage's objectives: its own, else the calibration's, else those of its tests' kinds
    (`problem.default_objectives`: nrmse, cor, contact_time and/or compression)."""
    return tuple(stage.objectives or objectives or default_objectives(tests))


def stage_folder(out: Path, stage: Stage) -> Path:
    """The folder of a stage's files in `out`."""
    return out / stage.name.replace("/", "-").replace(" ", "-")


def _check_resume(out: Path | None, stages: list[Stage], method: str, resume: bool) -> None:
    """Before the first run, what `search.open_checkpoint` (which checks each stage's folder as
    the stage starts) does not: that a resume is of a search, and that some stage's folder holds
    one to continue."""
    from .search import MANIFEST_FILE

    if not resume:
        return
    if "nsga2" not in method:
        raise InputError(f"--resume: --method {method} keeps no checkpoint (only a search, "
                         "nsga2 or nsga2+gradient, can be resumed)")
    if out is not None and not any((stage_folder(out, s) / MANIFEST_FILE).exists()
                                   for s in stages):
        raise InputError(f"--resume: no search to resume in {out} (no stage folder holds "
                         f"{MANIFEST_FILE}); run without --resume")


def select_free(stage: Stage, bounds: dict[str, tuple[float, float]]) -> list[str]:
    paths = [p for p in bounds if any(fnmatch.fnmatchcase(p, pat) for pat in stage.free)]
    if not paths:
        raise InputError(f"--stage {stage.name}: free={','.join(stage.free)} matches none of "
                         f"the --free paths ({', '.join(bounds)})")
    return paths


def select_tests(stage: Stage, tests: list) -> list:
    if stage.tests is None:
        return list(tests)
    names = [t.name for t in tests]
    unknown = [n for n in stage.tests if n not in names]
    if unknown:
        raise InputError(f"--stage {stage.name}: tests={unknown[0]!r} is not a test (have: "
                         f"{', '.join(names)})")
    return [t for t in tests if t.name in stage.tests]


def calibrate(template: dict, tests: list, bounds: dict[str, tuple[float, float]], options, *,
              objectives=None, method: str = "nsga2",
              stages: list[Stage] | None = None, population: int = 24, generations: int = 8,
              seed: int = 0, decision: str = "knee", weights=None, out: Path | None = None,
              resume: bool = False, max_evaluations: int = 30,
              verbose: bool = True, allow=()) -> dict[str, Any]:
    """Calibrate `template` (ball specification) against `tests` (`CalibrationTest`s and/or
    `compression.CompressionTest`s). `bounds`: path -> (low, high) (SI). `objectives`: None for
    those of each stage's tests (nrmse, cor, contact_time for impact tests, compression for
    compression tests). Returns the result: `chosen` (parameters, objectives,
    per-test comparisons), `pareto` (the last stage's front), `evaluations` (FE runs),
    `stages`, `wall_time_s`, `ball` (the calibrated specification), `not_identified` (the
    refined parameters that the tests do not determine) -- JSON-able -- and `stage_results` (the
    `StageResult`s, with the FE runs of the chosen designs). Each stage's evaluations and plots
    go to `out/<stage name>/`; `resume` continues the searches stopped there. `allow`:
    plausibility checks turned into warnings (e.g. "speed-range")."""
    from .search import MANIFEST_FILE, open_checkpoint

    started = time.perf_counter()
    stages = stages or [Stage("calibration")]
    _check(template, tests, bounds, options, objectives, method, stages, decision, weights,
           max_evaluations, population, generations, allow)
    _check_resume(out, stages, method, resume)
    current = template
    results: list[StageResult] = []
    for k, stage in enumerate(stages):
        paths = select_free(stage, bounds)
        problem = CalibrationProblem(current, select_tests(stage, tests),
                                     [free_parameter(current, p, *bounds[p], allow)
                                      for p in paths],
                                     stage_objectives_of(stage, objectives, select_tests(
                                         stage, tests)), allow=allow)
        folder = stage_folder(out, stage) if out is not None else None
        # a stage the stopped calibration never reached starts afresh
        stage_resume = resume and (folder is None or (folder / MANIFEST_FILE).exists())
        if "nsga2" in method:
            # before the stage's runs: a resume without `out`, a folder holding a search
            # without `resume`, a damaged or foreign checkpoint
            open_checkpoint(problem, options, seed, population, folder, stage_resume,
                            write=False)
        if folder is not None:
            folder.mkdir(parents=True, exist_ok=True)
        if verbose:
            progress_line(f"stage {k + 1}/{len(stages)}: {stage.name}")
        result = run_stage(problem, stage, options, method=method, population=population,
                           generations=generations, seed=seed, decision=decision,
                           weights=weights, out=folder, resume=stage_resume,
                           max_evaluations=max_evaluations, verbose=verbose)
        results.append(result)
        current = problem.spec(result.unit, name=template.get("name", "ball") + "-calibrated")
    last = results[-1]
    chosen_values: dict[str, float] = {}
    for r in results:
        chosen_values.update(r.values)
    return {"chosen": {"parameters": chosen_values, "objectives": last.objectives,
                       "per_test": last.per_test},
            "pareto": last.to_dict().get("pareto", []),
            "evaluations": sum(r.fe_runs for r in results),
            "stages": [r.to_dict() for r in results],
            "wall_time_s": time.perf_counter() - started, "ball": current,
            "not_identified": [path for r in results if r.refinement is not None
                               for path in r.refinement.not_identified],
            "stage_results": results}
