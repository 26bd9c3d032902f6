"""The report as one self-contained HTML page: inline CSS, inline SVG figures, no scripts and
nothing fetched from elsewhere, so it opens anywhere and can be mailed as one file."""

from __future__ import annotations

import html
import math
from typing import Any

from .tables import Table

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1200px; color: #222;
       padding: 0 1em; }
h1 { font-size: 1.6em; } h2 { font-size: 1.25em; margin-top: 2em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.85em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; white-space: nowrap; }
.wide { overflow-x: auto; }
th { background: #f2f2f2; } td:first-child, th:first-child { text-align: left; }
figure { margin: 1em 0; } figure svg { max-width: 100%; height: auto; }
figcaption { font-size: 0.85em; color: #555; }
.note { background: #fff8e1; border-left: 4px solid #f0b400; padding: 0.5em 1em; }
.small { font-size: 0.8em; color: #666; }
"""


def cell(value: Any, column: str) -> str:
    """A table cell, formatted by what its column holds."""
    if not isinstance(value, float):
        return html.escape(str(value))
    if not math.isfinite(value):
        return "&ndash;"
    if column.endswith("relative_error"):
        return f"{value:+.2%}"
    if column.endswith("nrmse"):
        return f"{value:.2%}"
    if column.endswith("cor_error"):
        return f"{value:+.4f}"
    return f"{value:.5g}"


def table_html(table: Table, formats: dict[str, str] | None = None) -> str:
    """`formats` maps a column to a Python format for all its cells (else `cell` decides)."""
    formats = formats or {}
    head = "".join(f"<th>{html.escape(c)}</th>" for c in table.columns)
    body = []
    for row in table.rows:
        cells = []
        for column, value in zip(table.columns, row):
            fmt = formats.get(column, formats.get("*"))
            shown = (format(value, fmt) if fmt and isinstance(value, float) and math.isfinite(value)
                     else cell(value, column))
            cells.append(f"<td>{shown}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return (f"<div class=\"wide\"><table><caption>{html.escape(table.title)} "
            f"(<code>{html.escape(table.name)}.csv</code>)</caption><thead><tr>{head}</tr></thead>"
            f"<tbody>{''.join(body)}</tbody></table></div>")


def figure_html(svg_text: str, caption: str) -> str:
    return f"<figure>{svg_text}<figcaption>{html.escape(caption)}</figcaption></figure>"


def page(title: str, sections: list[tuple[str, str]], intro: str) -> str:
    """The whole page: `sections` are (heading, inner HTML) pairs."""
    parts = [f"<h2>{html.escape(h)}</h2>\n{body}" for h, body in sections]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head><body>\n"
            f"<h1>{html.escape(title)}</h1>\n{intro}\n" + "\n".join(parts) + "\n</body></html>\n")
