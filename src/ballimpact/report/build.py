"""Build the comparison report (thesis chapter 7): every model against every test, then the
tables, the figures, `report.html`, `report.json` and one CSV per table in the output folder
(`build_report`); `report_files` is the whole `report` command, from record files or a
built-in set."""

from __future__ import annotations

import datetime
import html
import json
import time
import warnings
from pathlib import Path
from typing import Any

from .. import __version__
from ..checks import check_allow, check_integer
from ..errors import CheckFailed, InputError, InputWarning, SimulationError
from ..fileio import check_distinct_files, check_output_folder, json_safe, write_atomic
from ..progress import progress_bar
from ..records.options import RecordOptions
from . import figures
from .inputs import (ReportTest, builtin_ball, builtin_files, builtin_note, check_test_record,
                     label_tests)
from .models import ModelRun, ModelSpec, check_balls, parse_models, run_model
from .page import figure_html, page, table_html
from .tables import (
    Table,
    by_speed_table,
    comparison_table,
    cost_table,
    parameter_tables,
    repeats_table,
    tests_table,
)

_THESIS = ("The thesis (section 7.2) found the three-element and the universal model within 4% of "
           "each other in RMSE, the single-element model overestimating the peak force by "
           "7.5-13% and missing the unloading, and its FE runs taking 25 s (universal) and 87 s "
           "(detailed) each on a 2008 PC.")

#: the models of a report when none are named (`report_files`)
DEFAULT_MODELS = "single_element,three_element,universal"


def build_report(tests: list[ReportTest], models: list[ModelSpec], out: Path, *, seed: int = 0,
                 universal_model=None, options=None, note: str = "",
                 progress: bool = True, allow=(), tolerances=None) -> dict[str, Any]:
    """Run every model against every test and write the report into the folder `out` (made if
    missing). `note` is shown at the top of the page (e.g. that the tests are synthetic);
    `allow`: the plausibility checks that only warn in the model runs (`--allow`).
    A model run that fails is listed in the report and the others go on. Every run is judged
    (`verdict.judge` with `tolerances`, default `verdict.Tolerances()`, and the test's
    uncertainty): `check` of each run, and `unmatched_tests`, the tests no model passes."""
    from ..verdict import Tolerances, judge

    started = time.perf_counter()
    out.mkdir(exist_ok=True)
    total = len(models) * (len(tests) + 1)
    done = 0

    def step(what: str) -> None:
        nonlocal done
        done += 1
        if progress:
            progress_bar(done, total, time.perf_counter() - started, done, unit="steps",
                         note=what)

    runs: list[ModelRun] = []
    failures: list[dict[str, str]] = []
    errors: list[Exception] = []
    for spec in models:
        for test in tests:
            try:
                runs.append(run_model(spec, test, seed=seed, universal_model=universal_model,
                                      options=options, allow=allow))
            except (InputError, SimulationError) as error:
                # one model that cannot follow one test (a fit that fails, an FE run that
                # stops, a pulse that cannot be measured) must not take the report down
                errors.append(error)
                failures.append({"model": spec.label, "test": test.label, "error": str(error)})
                warnings.warn(f"{spec.label} at {test.label}: failed run: {error}", stacklevel=2)
            step(f"{spec.label} at {test.label}")
    if not runs:
        reason = "every model run failed: " + "; ".join(
            f"{f['model']} at {f['test']}: {f['error']}" for f in failures)
        # all refused as bad input: the input is the problem (exit 2), else a failed run
        raise (InputError if all(isinstance(e, InputError) for e in errors)
               else SimulationError)(reason)
    _warn_not_identified(runs)
    uncertainty = {t.label: t.processed.features.uncertainty for t in tests}
    for run in runs:
        run.check = judge(run.comparison, tolerances or Tolerances(), uncertainty[run.test])
    timed = {}
    for spec in models:
        mine = sorted((r for r in runs if r.model == spec.label), key=lambda r: r.impact_speed_m_s)
        if mine:
            try:
                timed[spec.label] = mine[(len(mine) - 1) // 2].rerun()
            except (InputError, SimulationError):  # it ran once: the cost shows as unknown
                timed[spec.label] = float("nan")
        step(f"timing {spec.label}")

    tables = _tables(tests, runs, timed, failures, [m.label for m in models])
    html_text = _page(tests, runs, tables, failures, note)
    (out / "report.html").write_text(html_text, encoding="utf-8")
    for table in tables.values():
        write_atomic(out / f"{table.name}.csv", table.to_csv())
    result = {
        "report_html": str(out / "report.html"), "report_json": str(out / "report.json"),
        "csv": [str(out / f"{t.name}.csv") for t in tables.values()],
        "tests": [{"test": t.label, "file": t.file, **t.processed.features.to_dict()}
                  for t in tests],
        "models": [{"label": m.label, "kind": m.kind, "name": m.name} for m in models],
        "runs": [r.to_dict() for r in runs], "failures": failures,
        "unmatched_tests": [t.label for t in tests
                            if not any(r.check["passed"] for r in runs if r.test == t.label)],
        "tables": {key: t.to_dict() for key, t in tables.items()},
        "seed": seed, "note": note, "ballimpact_version": __version__,
        "wall_time_s": time.perf_counter() - started,
    }
    (out / "report.json").write_text(json.dumps(json_safe(result), indent=1))
    return result


def report_files(files: list[Path], out: Path, *, options: RecordOptions = RecordOptions(),
                 builtin: str | None = None, models: str | None = None,
                 universal_model: str | Path | None = None,
                 seed: int = 0, progress: bool = True, allow=(),
                 tolerances=None) -> dict[str, Any]:
    """`build_report` into the folder `out` (its parent must exist) on the test record `files`,
    each loaded and processed as `options` say (the record must carry its impact speed and
    mass, `inputs.check_test_record`), or on the built-in set `builtin` (`inputs.BUILTIN_SETS`;
    its generating FE ball joins the default models and the page notes that the tests are
    synthetic). `models`: comma-separated
    (`models.parse_models`; default `DEFAULT_MODELS`), the universal one loaded from
    `universal_model` (None: the built-in model). `InputError`, before anything runs, for both
    or neither of `files` and `builtin`, a bad `out`, `seed` < 0, a file given twice, an empty
    or unknown model and a ball file that is not a ball."""
    if bool(files) == bool(builtin):
        raise InputError("report: give test files or --builtin sample|speeds (one of the two)")
    check_output_folder(out, "--out")
    if out.exists() and not out.is_dir():
        raise InputError(f"--out: {out} is a file, not a folder")
    seed = check_integer("--seed", seed, 0)
    check_distinct_files(files, "TEST")  # each once, and each with its own speed
    # the generating ball of a built-in set joins the default models
    ball = builtin_ball(builtin) if builtin and models is None else None
    # an empty --models is a mistake, not a request for the default
    specs = parse_models(models if models is not None
                         else DEFAULT_MODELS + (f",{ball}" if ball is not None else ""))
    files = builtin_files(builtin) if builtin else files
    options = options.allowing(check_allow(allow))
    tests = label_tests([str(f) for f in files],
                        [options.process(check_test_record(options.load(path), path,
                                                           len(files)))
                         for path in files])
    check_balls(specs, tests[len(tests) // 2].speed_m_s, allow)
    universal = None
    if any(m.kind == "universal" for m in specs):
        from ..universal.model import load_model

        universal = load_model(universal_model)
    return build_report(tests, specs, out, seed=seed, universal_model=universal,
                        note=builtin_note(builtin, ball) if builtin else "", progress=progress,
                        allow=allow, tolerances=tolerances)


def best_miss(result: dict[str, Any], test: str) -> str:
    """The model of the smallest force NRMSE at `test` (a label of `build_report`'s result) and
    the criteria its check missed, in words."""
    runs = [r for r in result["runs"] if r["test"] == test]
    best = min(runs, key=lambda r: r["comparison"]["force_nrmse"])
    return f"{test}: best {best['model']} missed {', '.join(best['check']['missed'])}"


def raise_if_unmatched(result: dict[str, Any]) -> None:
    """`CheckFailed` (exit 3, the report printed all the same) when no model passes its check
    on some test of `build_report`'s result: how many, and per test the best model's misses."""
    unmatched = result["unmatched_tests"]
    if unmatched:
        raise CheckFailed(f"no model passes its check on {len(unmatched)} of "
                          f"{len(result['tests'])} tests ({', '.join(unmatched)}): "
                          + "; ".join(best_miss(result, t) for t in unmatched)
                          + f"; see {result['report_html']}", result)


def _warn_not_identified(runs: list[ModelRun]) -> None:
    """One warning per lumped model whose fits leave parameters undetermined, naming them per
    test (the parameter tables mark each such value "not identified")."""
    for model in dict.fromkeys(r.model for r in runs):
        found = [f"{', '.join(r.not_identified)} at {r.test}" for r in runs
                 if r.model == model and r.not_identified]
        if found:
            warnings.warn(f"{model}: not identified (standard error inf or larger than the "
                          f"value): {'; '.join(found)}", InputWarning, stacklevel=3)


def _tables(tests: list[ReportTest], runs: list[ModelRun], timed: dict[str, float],
            failures: list[dict[str, str]], models: list[str]) -> dict[str, Table]:
    def by_speed(key, name, title):  # every model ran or failed at each test: a row each
        return by_speed_table(runs, tests, key, name, title, failures, models)

    tables = {
        "tests": tests_table(tests),
        "comparison": comparison_table(runs, failures, tests),
        "nrmse": by_speed("force_nrmse", "nrmse_by_speed",
                          "Force NRMSE (of the test's peak) per model and speed"),
        "cor_error": by_speed("cor_error", "cor_error_by_speed",
                              "COR error (model - test) per model and speed"),
        "peak_force_error": by_speed("peak_force_relative_error", "peak_force_error_by_speed",
                                     "Peak force relative error per model and speed"),
        "contact_time_error": by_speed("contact_time_relative_error",
                                       "contact_time_error_by_speed",
                                       "Contact time relative error per model and speed"),
        "cost": cost_table(runs, timed),
    }
    tables.update({f"parameters:{model}": t for model, t in parameter_tables(runs).items()})
    repeated = repeats_table(runs)
    if repeated is not None:
        tables["repeats"] = repeated
    return tables


def _page(tests, runs, tables, failures, note) -> str:
    models = list(dict.fromkeys(r.model for r in runs))
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    intro = (f"<p class=\"small\">ballimpact {__version__}, {when}. {len(models)} models against "
             f"{len(tests)} tests"
             + (f", {len(failures)} failed runs (listed below)" if failures else "")
             + ". SI units; figures in ms and kN for reading.</p>")
    if note:
        intro += f"<p class=\"note\">{html.escape(note)}</p>"
    intro += ("<p>Each model's pulse is compared with the test's as a calibration compares "
              "them: the force NRMSE is the RMS difference over the span where either touches, "
              "divided by the test's peak force, with the model's pulse at the best time shift "
              "within 5% of the contact time (a noisy test's contact start is uncertain by tens "
              "of microseconds); peak force, contact time and COR of the model are measured as "
              "the test's were (docs/report.md). Lumped models are fitted to each test, the "
              "universal model identifies its ball from each test and runs it, ball files run "
              "as they are.</p>")
    pct = {"*": ".2%"}
    cor = {"*": "+.4f", "mean_abs": ".4f"}
    sections = [
        ("Tests", table_html(tables["tests"])),
        ("Accuracy per model and speed",
         table_html(tables["nrmse"], pct) + table_html(tables["cor_error"], cor)
         + table_html(tables["peak_force_error"], {"*": "+.2%", "mean_abs": ".2%"})
         + table_html(tables["contact_time_error"], {"*": "+.2%", "mean_abs": ".2%"})
         + figure_html(figures.svg(figures.nrmse_bars(tests, runs)),
                       "Force NRMSE per model and test.")),
        ("Force-time curves",
         figure_html(figures.svg(figures.force_overlays(tests, runs)),
                     "Force against time from first contact: tests (grey) and models "
                     "(thesis figures 7-1 to 7-4).")),
        ("Against impact speed",
         figure_html(figures.svg(figures.versus_speed(tests, runs, "P17", "COR")),
                     "COR against impact speed (thesis figure 7-7).")
         + figure_html(figures.svg(figures.versus_speed(tests, runs, "P1",
                                                        "contact time (ms)", 1e3)),
                       "Contact time against impact speed.")
         + figure_html(figures.svg(figures.versus_speed(tests, runs, "P6", "peak force (kN)",
                                                        1e-3)),
                       "Peak force against impact speed.")),
        ("All results", table_html(tables["comparison"])),
        ("Computing cost",
         table_html(tables["cost"])
         + "<p>Identification: the GA fit of a lumped model, or the universal model's network; "
           "one run: the model simulated once more at the median test speed, compiled (JAX "
           "compilation, a few seconds the first time, is left out). " + html.escape(_THESIS)
         + "</p>"
         + figure_html(figures.svg(figures.cost_bars(tables["cost"])),
                       "Wall time per model on this machine (thesis figure 7-5), log scale.")),
    ]
    parameters = "".join(
        table_html(t) + figure_html(figures.svg(figures.parameters_vs_speed(key[11:], runs)),
                                    f"Parameters of {key[11:]} against impact speed, with "
                                    "standard errors (lumped) or 90% intervals (universal); "
                                    "open markers without a bar: not identified (standard "
                                    "error inf or larger than the value).")
        for key, t in tables.items() if key.startswith("parameters:"))
    if "repeats" in tables:
        parameters += table_html(tables["repeats"])
    if parameters:
        sections.append(("Parameters against impact speed (thesis tables 7-1 to 7-3)",
                         parameters))
    if failures:  # right after the tests, before any table that has holes because of them
        items = "".join(f"<li>{html.escape(f['model'])} at {html.escape(f['test'])}: "
                        f"{html.escape(f['error'])}</li>" for f in failures)
        sections.insert(1, ("Failed runs",
                            "<p>These model runs failed; their cells read \"failed\" and the "
                            f"means leave them out.</p><ul>{items}</ul>"))
    return page("Ball models against impact tests", sections, intro)

