"""The report's tables: one definition each, written as HTML in the page and as a CSV beside it."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..fileio import table_text
from .inputs import ReportTest
from .models import ModelRun


@dataclass(frozen=True)
class Table:
    """`columns` name SI units in their names; `rows` hold numbers or strings."""

    name: str      # the CSV's stem
    title: str
    columns: list[str]
    rows: list[list[Any]]

    def to_csv(self) -> str:
        """The table as CSV text (`fileio.table_text`; numbers with 8 significant digits, a
        non-finite one empty)."""
        return table_text(self.columns, self.rows, ".8g")

    def to_dict(self) -> dict[str, Any]:
        return {"title": self.title, "csv": f"{self.name}.csv", "columns": self.columns,
                "rows": self.rows}


def tests_table(tests: list[ReportTest]) -> Table:
    rows = []
    for t in tests:
        f = t.processed.features
        v = f.values
        rows.append([t.label, Path(t.file).name, v["P15"], v["P16"], f.rebound_speed_source,
                     v["P17"], v["P6"], v["P1"], f.mass_kg])
    return Table("tests", "Tests", ["test", "file", "impact_speed_m_s", "rebound_speed_m_s",
                                    "rebound_speed_source", "cor", "peak_force_n",
                                    "contact_time_s", "mass_kg"], rows)


def comparison_table(runs: list[ModelRun], failures: list[dict[str, str]] = (),
                     tests: list[ReportTest] = ()) -> Table:
    """A row per model run; a failed pair gets a row too, its numbers empty and its reason in
    the last column (`failed`, empty for a run that worked)."""
    rows = []
    for r in runs:
        c = r.comparison
        rows.append([r.model, r.test, r.impact_speed_m_s, c["peak_force_simulated_n"],
                     c["peak_force_measured_n"], c["peak_force_relative_error"],
                     c["contact_time_simulated_s"], c["contact_time_measured_s"],
                     c["contact_time_relative_error"], c["cor_simulated"], c["cor_measured"],
                     c["cor_error"], c["force_nrmse"], check_words(r.check), ""])
    speeds = {t.label: t.speed_m_s for t in tests}
    for f in failures:
        rows.append([f["model"], f["test"], speeds.get(f["test"], math.nan),
                     *[math.nan] * 10, "", f"failed: {f['error']}"])
    return Table("comparison", "Every model against every test",
                 ["model", "test", "impact_speed_m_s", "peak_force_n", "peak_force_test_n",
                  "peak_force_relative_error", "contact_time_s", "contact_time_test_s",
                  "contact_time_relative_error", "cor", "cor_test", "cor_error", "force_nrmse",
                  "check", "failed"],
                 rows)


def check_words(check: dict[str, Any]) -> str:
    """A run's verdict in the table: passed, or each criterion missed."""
    if not check:
        return ""
    return "passed" if check["passed"] else "missed: " + "; ".join(check["missed"])


def model_order(runs: list[ModelRun], failures: list[dict[str, str]] = ()) -> list[str]:
    """The models that ran or failed, in the order they first appear."""
    return list(dict.fromkeys([r.model for r in runs] + [f["model"] for f in failures]))


def by_speed_table(runs: list[ModelRun], tests: list[ReportTest], key: str, name: str,
                   title: str, failures: list[dict[str, str]] = (),
                   models: list[str] | None = None) -> Table:
    """One row per model (`models`, default in the order they ran), one column per test
    (ordered by speed): `comparison[key]`, "failed" where that run failed (its reason is in
    `comparison.csv`), and the mean of its magnitude over the tests that ran."""
    models = models or model_order(runs, failures)
    cells: dict[tuple[str, str], Any] = {(f["model"], f["test"]): "failed" for f in failures}
    cells.update({(r.model, r.test): r.comparison[key] for r in runs})
    rows = []
    for model in models:
        values = [cells.get((model, t.label), math.nan) for t in tests]
        finite = [abs(v) for v in values if isinstance(v, float) and math.isfinite(v)]
        rows.append([model, *values, sum(finite) / len(finite) if finite else math.nan])
    return Table(name, title, ["model", *[t.label for t in tests], "mean_abs"], rows)


def cost_table(runs: list[ModelRun], timed_run_s: dict[str, float]) -> Table:
    """Per model: the mean identification time per test, one (compiled) run, and the total."""
    rows = []
    for model in dict.fromkeys(r.model for r in runs):
        mine = [r for r in runs if r.model == model]
        identification = sum(r.identification_s for r in mine) / len(mine)
        total = sum(r.identification_s + r.simulation_s for r in mine)
        rows.append([model, mine[0].kind, identification, timed_run_s.get(model, math.nan),
                     total])
    return Table("cost", "Computing cost (this machine)",
                 ["model", "kind", "identification_s_per_test", "run_s", "total_s"], rows)


def parameter_tables(runs: list[ModelRun]) -> dict[str, Table]:
    """Per fitted or identified model, its parameters against impact speed laid out as thesis
    tables 7-1..7-3 (a row per parameter, a column per test), each followed by its standard
    error (lumped fits) or the ends of its 90% interval (universal identifications).

    A value the test does not determine (standard error inf or larger than the value) is shown
    as "VALUE (not identified)", in the CSV too: read as a number it would pass for a result.
    An infinite standard error is written "inf" (an empty cell would read as missing)."""
    tables = {}
    for model in dict.fromkeys(r.model for r in runs if r.parameters):
        mine = sorted((r for r in runs if r.model == model), key=lambda r: r.impact_speed_m_s)
        rows: list[list[Any]] = [["impact_speed_m_s", *[r.impact_speed_m_s for r in mine]]]
        for name in mine[0].parameters:
            rows.append([f"{name} [{mine[0].units.get(name, '')}]",
                         *[_value(r, name) for r in mine]])
            if "standard_error" in mine[0].uncertainty:
                rows.append([f"{name} standard error",
                             *[_error(r.uncertainty["standard_error"].get(name, 0.0))
                               for r in mine]])
            elif name in mine[0].uncertainty.get("interval_90", {}):
                for end, label in ((0, "low"), (1, "high")):
                    rows.append([f"{name} 90% {label}",
                                 *[r.uncertainty["interval_90"][name][end] for r in mine]])
        stem = "parameters_" + "".join(c if c.isalnum() else "_" for c in model)
        tables[model] = Table(stem, f"Parameters of {model} against impact speed",
                              ["parameter", *[r.test for r in mine]], rows)
    return tables


def repeats_table(runs: list[ModelRun]) -> Table | None:
    """Per fitted or identified model and speed group of two or more tests (repeats: speeds
    within `repeats.DEFAULT_SPEED_TOLERANCE` of each other), the mean and standard deviation
    (ddof = 1) of each parameter over the repeats; None without repeats."""
    from ..records.repeats import group_by_speed, mean_sd

    rows: list[list[Any]] = []
    for model in dict.fromkeys(r.model for r in runs if r.parameters):
        mine = [r for r in runs if r.model == model and r.parameters]
        groups = group_by_speed([r.impact_speed_m_s for r in mine])
        for label in sorted(set(groups.tolist())):
            members = [r for r, g in zip(mine, groups) if g == label]
            if len(members) < 2:
                continue
            mean, sd = mean_sd([r.parameters for r in members])
            rows += [[model, label, len(members), f"{name} [{members[0].units.get(name, '')}]",
                      mean[name], sd[name]] for name in mean]
    if not rows:
        return None
    return Table("repeats", "Parameters over repeated tests at one speed: mean and standard "
                 "deviation (ddof = 1) of the per-test fits or identifications",
                 ["model", "speed_m_s", "tests", "parameter", "mean", "sd"], rows)


def _value(run: ModelRun, name: str) -> Any:
    value = run.parameters[name]
    return f"{value:.5g} (not identified)" if name in run.not_identified else value


def _error(error: float) -> Any:
    return "inf" if math.isinf(error) else error
