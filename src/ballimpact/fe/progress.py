"""Cost of an explicit run before it starts; its progress lines while it runs come from the
package's one progress module (`ballimpact.progress`), re-exported here.

Both solvers (axisymmetric `fe` and 3D `oblique`) estimate a run's cost from the mesh before they
compile it (`RunEstimate`) and warn when it is so large that the run may take very long or exhaust
memory; `RunProgress` (`ballimpact.progress`) is a `progress(t_s)` callback that prints the time
reached, steps per second and the time left, and stays quiet for runs that end within a few
seconds.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Collection
from dataclasses import dataclass

from ..checks import flag
from ..progress import RunProgress, format_progress
from ..progress import duration as _duration

__all__ = ["MEMORY_WARNING_BYTES", "RunEstimate", "RunProgress", "available_memory_bytes",
           "format_progress", "process_memory_bytes"]

#: memory (bytes) of the histories and kept frames above which a run is flagged
MEMORY_WARNING_BYTES = 4 * 2 ** 30


def available_memory_bytes() -> float | None:
    """Memory (bytes) a new allocation can get without swapping: MemAvailable of /proc/meminfo
    (Linux), else the free physical pages (`os.sysconf`), else None (unknown: not checked)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except (OSError, ValueError, IndexError):
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES")) * float(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


def process_memory_bytes() -> float:
    """Memory (bytes) this process holds now: the resident set of /proc/self/statm (Linux), else
    its peak resident set (`resource.getrusage`), else 0 (unknown: nothing is counted as held)."""
    try:
        with open("/proc/self/statm", encoding="ascii") as f:
            return float(f.read().split()[1]) * float(os.sysconf("SC_PAGE_SIZE"))
    except (OSError, ValueError, IndexError, AttributeError):
        pass
    try:
        import resource

        peak = float(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
    except (ImportError, OSError, ValueError):
        return 0.0
    return peak if sys.platform == "darwin" else peak * 1024.0  # macOS: bytes; else KiB


#: the largest extra memory (bytes) of a `check_memory` in this process that fitted, and of one
#: let through by "large-run": a later run needing no more is let through unchecked, so that a
#: brief dip in free memory does not stop a calibration or study partway, and `simulate` after
#: `fe.estimate` (the same run) is judged, and warned about, once
_JUDGED_BYTES = {"fitted": 0.0, "allowed": 0.0}


def _judged_before(needed_bytes: float, allowed: bool) -> bool:
    """Whether a run needing `needed_bytes` more memory was judged already in this process."""
    return (needed_bytes <= _JUDGED_BYTES["fitted"]
            or (allowed and needed_bytes <= _JUDGED_BYTES["allowed"]))


@dataclass(frozen=True)
class RunEstimate:
    """A run's cost, estimated before it starts (on the high side: the end time from a Hertz
    contact time with the ball's softest long-term modulus, the increment from its smallest
    element).

    - `elements`, `steps`: of the mesh and of the run (the longest run of a batch).
    - `end_time_s`: simulated time (s) at which the run is expected to end.
    - `memory_bytes`: the histories (one row per step, every run of a batch) and any frames kept
      for output.
    - `element_steps_limit`: elements x steps above which `warning` flags the run (per solver;
      per run: a batch of many runs on a sound mesh is not flagged).
    - `seconds_per_element_step`: the solver's cost on a 2-core CPU (s), for the warning's time
      figure.
    - `hint`: how to make the mesh coarser (the option and the command-line flag).
    - `model_bytes`: the rest of the run's memory: the process with JAX and the compiled
      program, the mesh, its geometry and the state of every run held at once (an estimate from
      measured peaks, docs/fe.md "Progress and very large runs").
    - `base_bytes`: the process's part of `model_bytes` (Python, JAX, the compiled program), which
      a process that has imported JAX already holds in part (`check_memory`).
    - `runs`: runs of the batch.
    - `chunk_steps`: steps between the run's progress reports (`ExplicitOptions.chunk_steps`).
    - `announce`: what is about to run, a line for the user (`fe.runs.started` sets it).
    """

    elements: int
    steps: int
    end_time_s: float
    memory_bytes: float
    element_steps_limit: float
    seconds_per_element_step: float
    hint: str = ""
    model_bytes: float = 0.0
    runs: int = 1
    base_bytes: float = 0.0
    chunk_steps: int = 200
    announce: str = ""

    @property
    def element_steps(self) -> float:
        """Element updates of one run (elements x steps)."""
        return float(self.elements) * float(self.steps)

    @property
    def total_bytes(self) -> float:
        """The whole run's memory (bytes): histories, frames and `model_bytes`."""
        return float(self.memory_bytes) + float(self.model_bytes)

    @property
    def wall_time_s(self) -> float:
        """Wall time of every run on a 2-core CPU (s), at `seconds_per_element_step`."""
        return self.element_steps * self.runs * self.seconds_per_element_step

    def check_memory(self, allow: Collection[str] = (), available_bytes: float | None = None,
                     what: str = "the run") -> None:
        """The `large-run` check: `InputError` (an `InputWarning` if allowed) when the memory the
        run still needs exceeds `available_bytes` (default `available_memory_bytes()`; unknown:
        nothing is checked). What it still needs is `total_bytes` less the part of `base_bytes`
        this process already holds (`process_memory_bytes`): the free memory does not include
        it. The message states the estimate (GiB, elements, steps, time) and `hint`.

        Measured checks (`available_bytes` None) are judged once per size in a process: a run
        needing no more than one that fitted before (or, when allowed, that was let through) is
        not checked again (`_JUDGED_BYTES`)."""
        held = min(self.base_bytes, process_memory_bytes())
        needed = self.total_bytes - held
        measured = available_bytes is None
        if measured and _judged_before(needed, "large-run" in allow):
            return
        available = available_memory_bytes() if measured else available_bytes
        if available is None:
            return
        if needed > available:
            flag("large-run", self._memory_message(needed, held, available, what), allow)
        if measured:  # it fitted, or was allowed (else `flag` raised)
            key = "fitted" if needed <= available else "allowed"
            _JUDGED_BYTES[key] = max(_JUDGED_BYTES[key], needed)

    def _memory_message(self, needed: float, held: float, available: float, what: str) -> str:
        size = f"{_count(self.elements)} elements"
        if self.steps:  # a run (an export runs nothing)
            size += f" x {_count(self.steps)} steps" + (f" x {self.runs} runs" if self.runs > 1
                                                        else "")
        besides = f" besides the {held / 2 ** 30:.2g} GiB this process holds" if held else ""
        took = (f", and take about {_duration(self.wall_time_s)} on a 2-core CPU"
                if self.steps else "")
        return (f"{what} would need about {needed / 2 ** 30:.3g} GiB of memory{besides} ({size}), "
                f"more than the {available / 2 ** 30:.3g} GiB available{took}: "
                f"{self.hint or 'a coarser mesh'}")

    def warning(self) -> str | None:
        """The warning text (starting "large run:") when the run is above a guard, else None."""
        parts = []
        if self.element_steps > self.element_steps_limit:
            minutes = self.element_steps * self.seconds_per_element_step / 60.0
            parts.append(f"about {self.elements} elements x {self.steps} steps = "
                         f"{self.element_steps:.2g} element updates, above the guard's "
                         f"{self.element_steps_limit:.2g} (about {minutes:.0f} min on a "
                         "2-core CPU)")
        if self.memory_bytes > MEMORY_WARNING_BYTES:
            parts.append(f"about {self.memory_bytes / 2 ** 30:.1f} GiB of histories and frames, "
                         f"above the guard's {MEMORY_WARNING_BYTES / 2 ** 30:.0f} GiB")
        if not parts:
            return None
        return ("large run: " + "; ".join(parts) + ": it may take very long or exhaust memory"
                + (f" ({self.hint})" if self.hint else ""))


def _count(n: float) -> str:
    """A count for a message: plain below a million, else 1.5e+09."""
    return f"{int(n)}" if n < 1e6 else f"{n:.2g}"
