"""Progress on stderr for long runs, one mechanism for every command.

- `progress_line(text)`: one finished line (ending first a bar left open);
- `redraw_line(text)` / `end_line()`: one line redrawn in place (a counter), and finished;
  `progress_bar(done, total, elapsed_s, new)` draws a bar with them (designs of experiments,
  reports); `line_open()` says whether such a line is unfinished (an interrupt's message then
  starts a new line);
- `Pacer`: when a callback may print (quiet for the first seconds, then at most every so often);
- `RunProgress`: the `progress(t_s)` callback of an explicit FE run (simulated time reached,
  steps per second, time left; `format_progress`);
- `CountProgress`: the `progress(done, total)` callback of a run of counted steps (compression
  increments; `format_count`);
- `Waiting`: a wait that reports nothing itself (a compilation): quiet for its first seconds,
  then one line redrawn every second with the time spent and what is left of the expected wait.

All times are seconds (s); `clock`s return seconds.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from typing import TextIO

#: whether the last `redraw_line` is unfinished (no newline yet): stderr is one terminal; and
#: whether waits are announced without a progress callback (`announce_waits`)
_open = {"line": False, "waits": False}


def announce_waits(on: bool = True) -> None:
    """Announce every long silent wait (`Waiting`: the compilation of a new program) on stderr,
    not only those of runs given a progress callback: the command line's process sets it; the
    library alone stays quiet."""
    _open["waits"] = bool(on)


def waits_announced() -> bool:
    return _open["waits"]


def line_open() -> bool:
    """Whether the last progress line drawn is unfinished (no newline yet)."""
    return _open["line"]


def progress_line(text: str, stream: TextIO | None = None) -> None:
    """Print `text` as one line on `stream` (default stderr, looked up at the call), after
    finishing a `redraw_line` left open on stderr."""
    out = stream if stream is not None else sys.stderr
    if out is sys.stderr:
        end_line()
    print(text, file=out, flush=True)


def redraw_line(text: str) -> None:
    """Draw `text` over the current stderr line, left unfinished (a counter redrawn in place:
    "identified 3/10"); `end_line` finishes it."""
    _open["line"] = True
    print(f"\r{text}", end="", file=sys.stderr, flush=True)


def end_line() -> None:
    """Finish a line `redraw_line` left open (nothing if none is)."""
    if _open["line"]:
        _open["line"] = False
        print(file=sys.stderr, flush=True)


def progress_bar(done: int, total: int, elapsed_s: float, new: int, *, unit: str = "runs",
                 note: str = "") -> None:
    """Redraw one stderr line: `done` of `total` `unit`, the rate of the `new` ones done in
    `elapsed_s` (s) and the time left; `note` says what is running. Ends the line when done."""
    rate = new / elapsed_s if elapsed_s > 0 else 0.0
    left = (total - done) / rate if rate > 0 else math.inf
    width = 30
    filled = int(width * done / total) if total else width
    eta = f"{duration(left)} left" if math.isfinite(left) else "time left unknown"
    note = f", {note}" if note else ""
    redraw_line(f"[{'#' * filled}{'.' * (width - filled)}] {done}/{total} {unit}, "
                f"{rate:.2f} {unit}/s, {eta}{note}   ")
    if done >= total:
        end_line()


def duration(seconds: float) -> str:
    """A time span (s) for a message: "42 s", "3.5 min", "2.1 h", "unknown" if not finite."""
    if not math.isfinite(seconds):
        return "unknown"
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.1f} min"
    if seconds < 3.6e7:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 3600:.2g} h"


class Pacer:
    """When a progress callback may print: not before `quiet_s` (s) after `start`, then at most
    every `interval_s` (s). `clock` returns seconds (tests pass a fake one)."""

    def __init__(self, quiet_s: float, interval_s: float,
                 clock: Callable[[], float] = time.perf_counter) -> None:
        self.quiet_s = quiet_s
        self.interval_s = interval_s
        self.clock = clock
        self._last_s = -math.inf

    def due(self, now_s: float, start_s: float) -> bool:
        """Whether a line is due at `now_s` (s) for a run timed from `start_s` (s); a due line
        counts as printed."""
        if now_s - start_s < self.quiet_s or now_s - self._last_s < self.interval_s:
            return False
        self._last_s = now_s
        return True


def format_progress(t_s: float, end_time_s: float, steps: int, elapsed_s: float,
                    t_first_s: float = 0.0) -> str:
    """One progress line: simulated time `t_s` (s) of the expected `end_time_s` (s), the rate of
    the `steps` done in `elapsed_s` (s of wall time) and the time left at the rate at which
    simulated time advanced from `t_first_s` (s)."""
    rate = steps / elapsed_s if elapsed_s > 0 else 0.0
    advance = (t_s - t_first_s) / elapsed_s if elapsed_s > 0 else 0.0
    line = f"  t = {t_s * 1e3:.3f} ms of ~{end_time_s * 1e3:.3f} ms, {rate:.0f} steps/s, "
    if t_s >= end_time_s:
        return line + "past the estimated end, time left unknown"
    if advance <= 0:
        return line + "time left unknown"
    return line + f"~{duration((end_time_s - t_s) / advance)} left"


class RunProgress:
    """A `progress(t_s)` callback for `fe.simulate`, `fe.simulate_batch`: prints
    `format_progress` lines on `stream` (default stderr).

    The solvers call it after every chunk of `chunk_steps` steps. The first call comes after the
    compilation and the first chunk; the rates are measured from it. Nothing is printed before
    `quiet_s` (s) of stepping, so short runs stay quiet; then a line at most every `interval_s`
    (s). `clock` returns seconds (tests pass a fake one).
    """

    def __init__(self, end_time_s: float, chunk_steps: int, *, stream: TextIO | None = None,
                 quiet_s: float = 3.0, interval_s: float = 5.0,
                 clock: Callable[[], float] = time.perf_counter) -> None:
        self.end_time_s = float(end_time_s)
        self.chunk_steps = int(chunk_steps)
        self.stream = stream
        self.pacer = Pacer(quiet_s, interval_s, clock)
        self.calls = 0
        self.lines = 0
        self._first: tuple[float, float] | None = None  # (wall s, simulated s) at the first call

    def __call__(self, t_s: float) -> None:
        now = self.pacer.clock()
        self.calls += 1
        if self._first is None:
            self._first = (now, float(t_s))
            return
        start, t_first = self._first
        if not self.pacer.due(now, start):
            return
        self.lines += 1
        progress_line(format_progress(float(t_s), self.end_time_s,
                                      (self.calls - 1) * self.chunk_steps, now - start, t_first),
                      self.stream)


def format_count(done: int, total: int, elapsed_s: float, what: str = "increment") -> str:
    """'  increment k of n, ~T left': `done` of `total` `what`s in `elapsed_s` (s), the time
    left at that rate."""
    left = elapsed_s / done * (total - done) if done > 0 else math.inf
    return f"  {what} {done} of {total}, ~{duration(left)} left"


class CountProgress:
    """A `progress(done, total)` callback for a run of counted steps (`fe.compress`: its
    increments): `format_count` lines on `stream` (default stderr), timed from the callback's
    creation; none before `quiet_s` (s) nor for the last step, then at most every `interval_s`
    (s)."""

    def __init__(self, what: str = "increment", *, stream: TextIO | None = None,
                 quiet_s: float = 3.0, interval_s: float = 0.0,
                 clock: Callable[[], float] = time.perf_counter) -> None:
        self.what = what
        self.stream = stream
        self.pacer = Pacer(quiet_s, interval_s, clock)
        self.start_s = clock()
        self.lines = 0

    def __call__(self, done: int, total: int) -> None:
        now = self.pacer.clock()
        if done >= total or not self.pacer.due(now, self.start_s):
            return
        self.lines += 1
        progress_line(format_count(done, total, now - self.start_s, self.what), self.stream)


def format_wait(text: str, elapsed_s: float, expected_s: float | None) -> str:
    """'{text}: 4 s, about 3 s left' (or '..., longer than the expected 6 s', or just the time
    spent when nothing is expected)."""
    line = f"{text}: {elapsed_s:.0f} s"
    if expected_s is None:
        return line
    if elapsed_s <= expected_s:
        return line + f", about {duration(expected_s - elapsed_s)} left"
    return line + f", longer than the expected {duration(expected_s)}"


class Waiting:
    """`with Waiting(text, expected_s):` around a call that reports nothing while it runs (the
    compilation of a new program): after `quiet_s` (s) a line `format_wait` is redrawn on stderr
    every `interval_s` (s) by a background thread, and finished when the call returns; a call
    that ends sooner prints nothing. `expected_s`: how long such a wait took before (s; None:
    unknown)."""

    def __init__(self, text: str, expected_s: float | None = None, *, quiet_s: float = 2.0,
                 interval_s: float = 1.0) -> None:
        self.text, self.expected_s = text, expected_s
        self.quiet_s, self.interval_s = quiet_s, interval_s
        self.lines = 0
        self._stop = None
        self._thread = None

    def __enter__(self) -> Waiting:
        import threading

        self._stop = threading.Event()
        started = time.perf_counter()

        def tick() -> None:
            if self._stop.wait(self.quiet_s):
                return
            while True:
                self.lines += 1
                redraw_line(format_wait(self.text, time.perf_counter() - started,
                                        self.expected_s) + "   ")
                if self._stop.wait(self.interval_s):
                    return

        self._thread = threading.Thread(target=tick, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        self._thread.join()
        if self.lines:
            end_line()
