"""The text of the report's result, as `ballimpact report` prints it: the lines (without their
line ends), so that a Python user gets the command's text."""

from __future__ import annotations

from typing import Any

#: width of a cell of the report's text tables (characters)
CELL_WIDTH = 20


def report_lines(result: dict[str, Any]) -> list[str]:
    """`build.build_report`'s result: the force NRMSE and COR error of every model at every
    test, how many tests each model's check passes, the runs that failed and the page."""
    lines = []
    tables = result["tables"]
    for key in ("nrmse", "cor_error"):
        table = tables[key]
        lines += [table["title"], "  " + "".join(f"{c:>{CELL_WIDTH}}" for c in table["columns"])]
        for row in table["rows"]:
            lines.append("  " + "".join([f"{row[0]:>{CELL_WIDTH}}"]
                                        + [_cell(v, key) for v in row[1:]]))
    for model in dict.fromkeys(r["model"] for r in result["runs"]):
        mine = [r for r in result["runs"] if r["model"] == model]
        passed = sum(r["check"]["passed"] for r in mine)
        lines.append(f"  check {model}: passed on {passed} of {len(mine)} tests")
    lines += [f"failed: {failure['model']} at {failure['test']}: {failure['error']}"
              for failure in result["failures"]]
    return lines + [f"report: {result['report_html']} ({result['wall_time_s']:.1f} s)"]


def _cell(value: Any, key: str) -> str:
    """A table cell: "failed", the NRMSE as a percentage or the signed COR error."""
    if isinstance(value, str):  # "failed"
        return f"{value:>{CELL_WIDTH}}"
    return f"{value:>{CELL_WIDTH}.2%}" if key == "nrmse" else f"{value:>+{CELL_WIDTH}.4f}"


__all__ = ["report_lines"]
