"""Speed sweeps of FE balls and ball-against-ball comparisons (`simulate --speed-m-s 5,10,20`,
`compare`): one ball at several impact speeds as one batched run (`fe.simulate_batch`), a row of
figures per speed, the differences of each ball from a reference ball, a CSV table, and the plots
(functions that draw on matplotlib Axes given to them and return them; nothing here chooses a
backend).

A speed-dependent ball (the `cricket-universal` preset, a ball file with a speed table) is loaded
once per speed, so each speed runs the constants interpolated for it: the balls of a sweep share
their layer structure and differ in constants, which is what `simulate_batch` vmaps over.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..records.features import dynamic_stiffness

#: the columns of a sweep's rows (SI, unit in the name), in the table's order
ROW_KEYS = ("impact_speed_m_s", "cor", "peak_force_n", "contact_time_s", "max_deflection_m",
            "rebound_speed_m_s", "dynamic_stiffness_n_m")
#: the differences of a ball from the reference ball in `compare_rows`
DIFFERENCE_KEYS = ("cor_difference", "peak_force_difference_percent",
                   "contact_time_difference_percent", "dynamic_stiffness_difference_percent")
#: the quantities plotted against speed: (row key, axis label, factor to the unit shown)
VERSUS_SPEED = (("cor", "COR", 1.0), ("peak_force_n", "peak force (kN)", 1e-3),
                ("contact_time_s", "contact time (ms)", 1e3))


def parse_speeds(text: str) -> tuple[float, ...]:
    """Impact speeds (m/s) from a comma-separated list ("5,10,20.5"): each item a finite number,
    none empty, none given twice (a sweep that ran one speed twice would look like two points).
    Their order is kept; the range is checked by the solver (`fe.speed_range.check_fe_speed`).
    Raises `InputError` with a message naming the item."""
    items = text.split(",")
    speeds: list[float] = []
    for k, item in enumerate(items, 1):
        where = f"item {k} of {text!r}: " if len(items) > 1 else ""
        if not item.strip():
            raise InputError(f"{where}empty; give speeds separated by commas, e.g. 5,10,20")
        try:
            value = float(item)
        except ValueError:
            raise InputError(f"{where}{item.strip()!r} is not a number") from None
        if not math.isfinite(value):
            raise InputError(f"{where}{item.strip()!r} is not a finite number")
        if value in speeds:
            raise InputError(f"{where}{value:g} m/s is given twice; give each speed once")
        speeds.append(value)
    return tuple(speeds)


@dataclass(frozen=True, eq=False)
class Sweep:
    """One ball run at several impact speeds (m/s): `results[i]` (`fe.ImpactResult`) at
    `speeds_m_s[i]`, the balls actually run (one per speed) and the batch's wall time (s)."""

    label: str
    speeds_m_s: tuple[float, ...]
    balls: tuple = field(repr=False)
    results: tuple = field(repr=False)
    wall_time_s: float = 0.0

    def rows(self) -> list[dict[str, float]]:
        return [sweep_row(r) for r in self.results]


def sweep_balls(spec, speeds_m_s: Sequence[float], *, moduli: str | None = None,
                allow=()) -> list:
    """The ball `spec` (preset, file or dict: `fe.load_ball`) loaded at each speed (m/s), with
    `moduli` ("long_term" or "instantaneous") overriding its convention when given."""
    from . import load_ball

    balls = [load_ball(spec, impact_speed_m_s=float(s), allow=allow) for s in speeds_m_s]
    if moduli is not None:
        balls = [b.with_moduli(moduli) for b in balls]
    return balls


def run_sweep(balls: Sequence, speeds_m_s: Sequence[float], options=None, *, label: str = "",
              progress=None, allow=()) -> Sweep:
    """`balls[i]` at `speeds_m_s[i]` (m/s) in one `fe.simulate_batch` call (vmapped groups of
    one compiled program: the balls must share their layer structure, as `sweep_balls` gives).
    Errors and warnings are `simulate_batch`'s (speed range, memory, unresolved contact)."""
    from . import SolverOptions, simulate_batch

    options = SolverOptions() if options is None else options
    speeds = tuple(float(s) for s in speeds_m_s)
    if len(balls) != len(speeds):
        raise InputError(f"speeds_m_s: expected one speed per ball ({len(balls)}), got "
                         f"{len(speeds)}")
    started = time.perf_counter()
    results = simulate_batch(list(balls), list(speeds), options, progress=progress, allow=allow)
    return Sweep(label or balls[0].name, speeds, tuple(balls), tuple(results),
                 time.perf_counter() - started)


def max_deflection_m(result) -> float:
    """The largest displacement (m) of the ball's centre of mass toward the plane during the
    impact, from the FE history: the ball starts touching the plane, so the displacement is
    measured from the centre's height before the first step (the first row, moved back by one
    step at the first row's velocity: an error of a * dt^2 / 2, below 1e-9 m). It is the
    compression a load-cell test reports (twice-integrated -F/m, `features.max_compression_m`)."""
    h = result.history
    z0 = h["centre_z_m"][0] - h["centre_velocity_z_m_s"][0] * h["time_s"][0]
    return float(z0 - np.min(h["centre_z_m"]))


def sweep_row(result) -> dict[str, float]:
    """The row of one FE run (`ROW_KEYS`, SI): COR, peak force, contact time, the centre's
    largest displacement, the rebound speed and the dynamic stiffness F_peak^2 / (m v_in^2) (N/m:
    the stiffness of the linear spring whose peak force at this impact would be F_peak)."""
    v = result.impact_speed_m_s
    return {"impact_speed_m_s": float(v), "cor": float(result.cor),
            "peak_force_n": float(result.peak_force_n),
            "contact_time_s": float(result.contact_time_s),
            "max_deflection_m": max_deflection_m(result),
            "rebound_speed_m_s": float(result.rebound_speed_m_s),
            "dynamic_stiffness_n_m": float(dynamic_stiffness(result.peak_force_n, result.mass_kg,
                                                             v))}


def sweep_json_row(result) -> dict[str, Any]:
    """A speed sweep's row (`sweep.sweep_row`, SI) with the run's energy balance error, steps and
    ball name."""
    return {**sweep_row(result), "energy_balance_error": result.energy_balance_error,
            "steps": result.steps, "ball_name": result.ball_name}


def differences(row: dict[str, float], reference: dict[str, float]) -> dict[str, float]:
    """`row` against `reference` at the same speed: the COR difference (absolute, row minus
    reference) and the peak force, contact time and dynamic stiffness differences in % of the
    reference's."""
    def percent(key: str) -> float:
        return 100.0 * (row[key] - reference[key]) / reference[key]

    return {"cor_difference": row["cor"] - reference["cor"],
            "peak_force_difference_percent": percent("peak_force_n"),
            "contact_time_difference_percent": percent("contact_time_s"),
            "dynamic_stiffness_difference_percent": percent("dynamic_stiffness_n_m")}


def compare_rows(sweeps: Sequence[Sweep]) -> list[dict[str, Any]]:
    """Per speed and ball (the sweeps' common speeds, in the first sweep's order): the ball's
    row and its `differences` from the first sweep's ball (zeros for the first), as flat rows
    with a `ball` column: the long table of `compare`."""
    reference = sweeps[0]
    rows = []
    for i, speed in enumerate(reference.speeds_m_s):
        ref_row = sweep_row(reference.results[i])
        for sweep in sweeps:
            row = sweep_row(sweep.results[sweep.speeds_m_s.index(speed)])
            rows.append({"ball": sweep.label, **row, **differences(row, ref_row)})
    return rows


def write_table(rows: Sequence[dict[str, Any]], path: str | Path) -> str:
    """`rows` as CSV (`fileio.write_table`: the header from the first row's keys, SI units in
    the names; numbers with 10 significant digits, a non-finite one empty)."""
    from ..fileio import write_table as write_csv

    rows = list(rows)
    return write_csv(Path(path), list(rows[0]), rows, ".10g")


# --------------------------------------------------------------------------- balls side by side


def _ball_key(spec: str) -> str:
    """What makes two --ball values the same ball: a file by its resolved path, else the name."""
    path = Path(spec)
    return str(path.resolve()) if path.is_file() else spec


def check_balls(specs: Sequence[str]) -> list[str]:
    """Two or more balls, each given once (a file under two spellings counts as twice)."""
    specs = list(specs)
    if len(specs) < 2:
        raise InputError(f"--ball: give two or more balls to compare (got {len(specs)}); one "
                         "ball at several speeds is `simulate --speed-m-s 5,10,20`")
    seen: dict[str, str] = {}
    for spec in specs:
        key = _ball_key(spec)
        if key in seen:
            spelling = f" (as {seen[key]})" if seen[key] != spec else ""
            raise InputError(f"--ball: {spec} is given twice{spelling}; give each ball once")
        seen[key] = spec
    return specs


@dataclass
class BallComparison:
    """`compare_balls`' result: the balls (`specs`, the first the reference), the speeds (m/s),
    each ball's `sweep.Sweep`, the long table (`sweep.compare_rows`) and the runs' wall time."""

    specs: list[str]
    speeds_m_s: tuple[float, ...]
    sweeps: list
    rows: list[dict[str, Any]]
    wall_time_s: float
    written: dict[str, str] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """The JSON of `ballimpact compare`: with the files written ("table", "plot")."""
        return {"balls": self.specs, "reference_ball": self.specs[0],
                "speeds_m_s": list(self.speeds_m_s), "comparison": self.rows,
                "sweeps": [{"ball": s.label, "ball_names": [r.ball_name for r in s.results],
                            "mass_kg": s.results[0].mass_kg, "wall_time_s": s.wall_time_s,
                            "rows": s.rows()} for s in self.sweeps],
                "wall_time_s": self.wall_time_s, **self.written}


# --------------------------------------------------------------------------- plots


def plot_versus_speed(axes, sweeps: Sequence[Sweep]):
    """COR, peak force and contact time of each sweep against the impact speed on the three
    `axes` (a marker per run, a line through them; one colour per sweep). Returns `axes`."""
    axes = list(axes)
    if len(axes) != len(VERSUS_SPEED):
        raise ValueError(f"axes: expected {len(VERSUS_SPEED)}, got {len(axes)}")
    for k, sweep in enumerate(sweeps):
        rows = sorted(sweep.rows(), key=lambda r: r["impact_speed_m_s"])
        speed = [r["impact_speed_m_s"] for r in rows]
        for ax, (key, _, scale) in zip(axes, VERSUS_SPEED):
            ax.plot(speed, [r[key] * scale for r in rows], "o-", color=f"C{k % 10}", ms=4,
                    label=sweep.label)
    for ax, (_, label, _) in zip(axes, VERSUS_SPEED):
        ax.set(xlabel="impact speed (m/s)", ylabel=label)
        ax.grid(alpha=0.3)
    if len(sweeps) > 1:
        axes[0].legend(fontsize=7)
    return axes


def plot_force_overlay(ax, sweeps: Sequence[Sweep], speed_m_s: float):
    """The contact force against time of each sweep's run at `speed_m_s` (m/s) on `ax` (one
    colour per sweep, as `plot_versus_speed`). Returns `ax`."""
    for k, sweep in enumerate(sweeps):
        h = sweep.results[sweep.speeds_m_s.index(speed_m_s)].history
        ax.plot(h["time_s"] * 1e3, h["contact_force_n"] * 1e-3, color=f"C{k % 10}", lw=1.3,
                label=sweep.label)
    ax.set(xlabel="time (ms)", ylabel="contact force (kN)", title=f"{speed_m_s:g} m/s")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    return ax


def sweep_figure(sweeps: Sequence[Sweep], *, overlays: bool = False, title: str | None = None):
    """A matplotlib `Figure` (no pyplot, no backend chosen): the three quantities against speed
    in one row, and with `overlays` the force-time overlays per speed in rows of three above."""
    from matplotlib.figure import Figure

    speeds = list(sweeps[0].speeds_m_s) if overlays else []
    overlay_rows = math.ceil(len(speeds) / 3)
    figure = Figure(figsize=(13.5, 3.8 * (overlay_rows + 1)), layout="constrained")
    grid = figure.add_gridspec(overlay_rows + 1, 3)
    for k, speed in enumerate(speeds):
        plot_force_overlay(figure.add_subplot(grid[k // 3, k % 3]), sweeps, speed)
    plot_versus_speed([figure.add_subplot(grid[overlay_rows, j]) for j in range(3)], sweeps)
    if title:
        figure.suptitle(title)
    return figure
