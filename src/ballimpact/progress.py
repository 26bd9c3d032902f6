"""One progress line on stderr for long runs (design of experiments, reports)."""

from __future__ import annotations

import math
import sys

_line_open = False


def line_open() -> bool:
    """Whether the last progress line drawn is unfinished (no newline yet)."""
    return _line_open


def progress_bar(done: int, total: int, elapsed_s: float, new: int, *, unit: str = "runs",
                 note: str = "") -> None:
    """Redraw one stderr line: `done` of `total` `unit`, the rate of the `new` ones done in
    `elapsed_s` (s) and the time left; `note` says what is running. Ends the line when done."""
    rate = new / elapsed_s if elapsed_s > 0 else 0.0
    left = (total - done) / rate if rate > 0 else math.inf
    width = 30
    filled = int(width * done / total) if total else width
    eta = f"{left:.0f} s left" if math.isfinite(left) else "time left unknown"
    global _line_open
    end = "\n" if done >= total else ""
    _line_open = not end
    note = f", {note}" if note else ""
    print(f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} {unit}, {rate:.2f} {unit}/s, "
          f"{eta}{note}   ", end=end, file=sys.stderr, flush=True)
