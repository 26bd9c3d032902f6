"""One value per shot to the method's statistics: per ball (mean, SD, count) and over the balls;
the result as text and as a CSV table."""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from ..fileio import write_table
from .methods import Method


def shot_stats(values: Iterable[float]) -> dict[str, float]:
    """{"mean", "sd", "count"}: the sample standard deviation (n - 1), NaN for one value."""
    values = [float(v) for v in values]
    sd = statistics.stdev(values) if len(values) > 1 else math.nan
    return {"mean": statistics.fmean(values), "sd": sd, "count": len(values)}


def summarise(method: Method, shots: list[dict[str, Any]]) -> dict[str, Any]:
    """Per ball (in order of first appearance) the mean, SD and count of each quantity (and of
    the inbound speed for impacts) over its shots; over all balls the mean and SD of the ball
    means (each ball once)."""
    keys = [q.key for q in method.quantities]
    if method.kind == "impact":
        keys = keys + ["impact_speed_m_s"]
    by_ball: dict[str, list[dict[str, Any]]] = {}
    for shot in shots:
        by_ball.setdefault(shot["ball"], []).append(shot)
    balls = []
    for ball, own in by_ball.items():
        entry: dict[str, Any] = {"ball": ball, "count": len(own)}
        for key in keys:
            entry[key] = shot_stats(shot[key] for shot in own)
        balls.append(entry)
    overall: dict[str, Any] = {"balls": len(balls), "shots": len(shots)}
    for key in keys:
        overall[key] = shot_stats(entry[key]["mean"] for entry in balls)
    return {"balls": balls, "overall": overall}


def stats_text(stats: dict[str, float], unit: str = "") -> str:
    """`shot_stats` as text: "mean +- SD unit" (5 and 3 significant digits; SD n/a for one
    value)."""
    sd = "n/a" if math.isnan(stats["sd"]) else f"{stats['sd']:.3g}"
    return f"{stats['mean']:.5g} +- {sd}" + (f" {unit}" if unit else "")


def table_rows(result: dict[str, Any]) -> tuple[list[str], list[list[Any]]]:
    """The table of a result of `from_records` or `on_model` as (columns, rows): `kind`
    shot|ball|all (model for `on_model`), ball, file, count, then each quantity (value or mean)
    and its SD (`_sd`); impact methods add the inbound speed."""
    keys = list(result["quantities"])
    if result["kind"] == "impact":
        keys.append("impact_speed_m_s")
    header = ["kind", "ball", "file", "count"] + [c for k in keys for c in (k, f"{k}_sd")]

    def cells(values: dict[str, Any]) -> list[Any]:
        out = []
        for key in keys:
            value = values.get(key)
            out += [value["mean"], value["sd"]] if isinstance(value, dict) else [value, None]
        return out

    if result["source"] == "model":
        return header, [["model", result["ball"], "", 1] + cells(result["result"])]
    rows = [["shot", shot["ball"], shot["file"], 1] + cells(shot) for shot in result["shots"]]
    rows += [["ball", entry["ball"], "", entry["count"]] + cells(entry)
             for entry in result["balls"]]
    overall = result["overall"]
    rows.append(["all", "", "", overall["balls"]] + cells(overall))
    return header, rows


def write_result_table(path: Path, result: dict[str, Any]) -> str:
    """`table_rows` as CSV (`fileio.write_table`, 12 significant digits); returns the path as
    text."""
    return write_table(path, *table_rows(result), ".12g")
