"""Repeated tests: many records of one ball, grouped by impact speed, as a table, per-group means
and standard deviations, and an aligned mean pulse with its scatter band.

A lab tests a ball several times at each of a few speeds. Each record keeps its own row (its
features as `extract_features` gives them); the records are grouped by impact speed, either to
the nominal speeds the lab aimed at or by clustering the measured speeds (`group_by_speed`); each
group gets the mean and the sample standard deviation (ddof = 1) of every feature
(`group_summaries`) and the mean pulse with its band, the pulses aligned at their contact start
(`pulse_bands`). docs/features.md "Repeated tests" gives the rules.

Pure functions on paths, `ProcessedImpact`s and numbers; `plot_pulse_bands` draws on a matplotlib
Axes it is given (this module imports no matplotlib and sets no backend). `summarise_repeats` and
`record_summary` are what the `features` command reports for many records and for one.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError, InputWarning
from .features import FEATURE_NAMES, ImpactFeatures
from ..fileio import check_distinct_files, write_table
from .pipeline import ProcessedImpact
from .record import ImpactRecord

#: Suffixes of the record files a folder is expanded to (side files `x.json` are not records).
RECORD_SUFFIXES = (".csv", ".wav")

#: Default relative speed tolerance of the grouping (5% of the speed: repeats aimed at one speed
#: scatter by a few percent, while the speeds of a series differ by 20% or more, e.g. the
#: thesis' 5.5, 10, 20.8 and 25 m/s).
DEFAULT_SPEED_TOLERANCE = 0.05

#: Masses of the records of one speed group may differ by this fraction of the smallest.
DEFAULT_MASS_TOLERANCE = 0.01

#: The table's numeric columns after `file` and `group_speed_m_s`: the 19 values by their
#: descriptive names (P1..P19, units in the names), then the load-cell quantities of
#: `ImpactFeatures.to_dict`.
FEATURE_COLUMNS: tuple[str, ...] = (*FEATURE_NAMES.values(), "mass_kg", "impulse_n_s",
                                    "impulse_cor", "max_compression_m", "energy_lost_j",
                                    "dynamic_stiffness_n_m")

#: Every column of the table, in order (`rebound_speed_source`: measured or impulse).
TABLE_COLUMNS: tuple[str, ...] = ("file", "group_speed_m_s", *FEATURE_COLUMNS,
                                  "rebound_speed_source")

#: The quantities the command prints per group, with their labels.
MAIN_COLUMNS: dict[str, str] = {
    "impact_speed_m_s": "impact speed (m/s)",
    "cor": "COR",
    "peak_force_n": "peak force (N)",
    "contact_time_s": "contact time (s)",
    "dynamic_stiffness_n_m": "dynamic stiffness (N/m)",
}


# --------------------------------------------------------------------------- record files


def expand_records(paths: Sequence[Path]) -> list[Path]:
    """The record files of `paths`: each file as given, each folder replaced by its record files
    (`RECORD_SUFFIXES`, any case, sorted by name; not its subfolders, hidden files or side files
    `x.json`); a built-in data set (`builtin:speed-set`, `datasets.resolve`) by its files.

    **Raises** `InputError` for a path that does not exist, a folder that holds no records, a
    file given twice (also under two spellings, or once itself and once in its folder) and an
    empty list. Files given explicitly are not checked for their type here: the loader names a
    wrong one.
    """
    if not paths:
        raise InputError("FILES_OR_DIRS: no test records given")
    from .datasets import resolve  # `builtin:NAME`: the package's own data sets

    found: list[Path] = []
    for path in map(resolve, paths):
        if path.is_dir():
            inside = sorted((p for p in path.iterdir()
                             if p.is_file() and not p.name.startswith(".")
                             and p.suffix.lower() in RECORD_SUFFIXES), key=lambda p: p.name)
            if not inside:
                raise InputError(f"{path}: the folder holds no test records "
                                 f"({', '.join('*' + s for s in RECORD_SUFFIXES)})")
            found.extend(inside)
        elif path.exists():
            found.append(path)
        else:
            raise InputError(f"{path}: no such file or folder")
    check_distinct_files(found, "FILES_OR_DIRS")
    return found


def record_files(paths: Sequence[Path], table: Path | None = None) -> list[Path]:
    """The records of `paths` (`expand_records`), less the `table` output (a CSV written by
    `write_speed_table`, the --table of the `features` command) when a folder holds it: the
    table of an earlier run. **Raises** `InputError` when `table` is one of the files given by
    name (a record is never overwritten) or when nothing but the table is left."""
    if table is None:
        return expand_records(paths)
    target = Path(table).resolve()
    named = next((p for p in paths if not p.is_dir() and p.resolve() == target), None)
    if named is not None:
        raise InputError(f"--table: {table} is one of the records given ({named}); write the "
                         "table to another file")
    files = [p for p in expand_records(paths) if p.resolve() != target]
    if not files:
        raise InputError(f"{table.parent}: the folder holds no test records besides the "
                         f"--table output {table.name}")
    return files


# --------------------------------------------------------------------------- grouping by speed


def group_by_speed(
    speeds_m_s: Sequence[float],
    nominal_m_s: Sequence[float] | None = None,
    tolerance: float = DEFAULT_SPEED_TOLERANCE,
    *,
    files: Sequence[str | Path] | None = None,
) -> np.ndarray:
    """The speed group of each record, as the group's speed (m/s): records with equal labels are
    repeats at one speed.

    - With `nominal_m_s` (the speeds the lab aimed at): each record goes to the nominal speed
      nearest to it in relative terms, |v - v_n| / v_n, which must be at most `tolerance`; the
      label is that nominal speed.
    - Without: the speeds are clustered. Sorted, each speed joins the group of the speeds
      before it while it exceeds that group's lowest speed by at most `tolerance` times it, and
      starts a new group otherwise: a group never spans more than the tolerance (a series of
      speeds 8% apart stays a series); the label is the group's mean speed.

    `tolerance` is a fraction of the speed (0.1 = 10%), in (0, 1). `files` (one per speed) names
    the record in errors.

    **Raises** `InputError` for a speed that is not a positive finite number, nominal speeds that
    are not positive and distinct, a tolerance outside (0, 1), and a record farther than
    `tolerance` from every nominal speed (naming its file, its speed and the nominal ones).
    """
    speeds = np.asarray(speeds_m_s, dtype=float)
    names = [str(f) for f in files] if files is not None else [f"record {i + 1}"
                                                               for i in range(speeds.size)]
    if speeds.ndim != 1 or speeds.size == 0:
        raise InputError("speeds_m_s: need one impact speed per record")
    if len(names) != speeds.size:
        raise InputError(f"files: {len(names)} names for {speeds.size} speeds")
    tolerance = check_tolerance(tolerance)
    for name, speed in zip(names, speeds):
        if not (math.isfinite(speed) and speed > 0):
            raise InputError(f"{name}: impact speed {speed!r} m/s must be finite and > 0")
    if nominal_m_s is not None:
        nominal = check_nominal(nominal_m_s)
        distance = np.abs(speeds[:, None] - nominal[None, :]) / nominal[None, :]
        nearest = np.argmin(distance, axis=1)
        for i, name in enumerate(names):
            if distance[i, nearest[i]] > tolerance:
                listed = ", ".join(f"{v:g}" for v in nominal)
                raise InputError(
                    f"{name}: impact speed {speeds[i]:.4g} m/s is not within {tolerance:.0%} of "
                    f"any nominal speed ({listed} m/s); add its speed to --speeds or widen "
                    "--speed-tolerance")
        return nominal[nearest]
    order = np.argsort(speeds, kind="stable")
    groups: list[list[int]] = []
    for i in order:
        if groups and speeds[i] <= speeds[groups[-1][0]] * (1 + tolerance):
            groups[-1].append(i)
        else:
            groups.append([i])
    labels = np.empty_like(speeds)
    for members in groups:
        labels[members] = np.mean(speeds[members])
    return labels


def check_tolerance(tolerance: float) -> float:
    """A relative speed tolerance in (0, 1), else `InputError` (a percentage names the slip)."""
    value = float(tolerance)
    if not (math.isfinite(value) and 0 < value < 1):
        hint = f" (a percentage? {value:g}% is {value / 100:g})" if 1 <= value < 100 else ""
        raise InputError(f"speed_tolerance (--speed-tolerance): must be a fraction of the speed "
                         f"in (0, 1), e.g. 0.1 for 10%; got {value:g}{hint}")
    return value


def check_nominal(nominal_m_s: Sequence[float]) -> np.ndarray:
    """Nominal speeds as a sorted array: positive, finite and distinct, else `InputError`."""
    nominal = np.asarray(nominal_m_s, dtype=float)
    if nominal.ndim != 1 or nominal.size == 0:
        raise InputError("nominal speeds (--speeds): give at least one speed in m/s, e.g. 5,10,20")
    bad = [v for v in nominal if not (math.isfinite(v) and v > 0)]
    if bad:
        raise InputError(f"nominal speeds (--speeds): {bad[0]:g} m/s must be finite and > 0")
    ordered = np.sort(nominal)
    same = np.flatnonzero(np.diff(ordered) == 0)
    if same.size:
        raise InputError(f"nominal speeds (--speeds): {ordered[same[0]]:g} m/s is given twice")
    return ordered


def check_masses(
    masses_kg: Sequence[float],
    files: Sequence[str | Path],
    groups: Sequence[float],
    tolerance: float = DEFAULT_MASS_TOLERANCE,
    what: str | None = None,
) -> None:
    """Repeats at one speed are tests of one ball kind: within each group the largest mass may
    exceed the smallest by at most `tolerance` of the smallest (1%), else `InputError` naming
    the two files and their masses. Groups at different speeds are not compared. `what` names
    the records in the message (default: "the repeats at V m/s")."""
    masses = np.asarray(masses_kg, dtype=float)
    labels = np.asarray(groups, dtype=float)
    for label in np.unique(labels):
        members = np.flatnonzero(labels == label)
        light = members[np.argmin(masses[members])]
        heavy = members[np.argmax(masses[members])]
        if masses[heavy] > masses[light] * (1 + tolerance):
            raise InputError(
                f"{files[light]} ({masses[light]:.4g} kg) and {files[heavy]} "
                f"({masses[heavy]:.4g} kg): mixed masses among "
                f"{what or f'the repeats at {label:.4g} m/s'} "
                f"(differ by {masses[heavy] / masses[light] - 1:.1%}, more than "
                f"{tolerance:.0%}); give the records of one ball kind, or check their mass_kg")


# --------------------------------------------------------------------------- table and summaries


def record_row(processed: ProcessedImpact, file: str | Path, group_speed_m_s: float
               ) -> dict[str, Any]:
    """One row of the table (`TABLE_COLUMNS`): the record's file, its group and its features."""
    features = processed.features
    summary = features.to_dict()
    row: dict[str, Any] = {"file": str(file), "group_speed_m_s": float(group_speed_m_s)}
    row.update(features.named())
    for name in FEATURE_COLUMNS[len(FEATURE_NAMES):]:
        row[name] = float(summary[name])
    row["rebound_speed_source"] = features.rebound_speed_source
    return row


def speed_table(
    processed_list: Sequence[ProcessedImpact],
    files: Sequence[str | Path],
    groups: Sequence[float],
) -> list[dict[str, Any]]:
    """A row per record (`record_row`), in the records' order."""
    if not (len(processed_list) == len(files) == len(groups)):
        raise InputError(f"speed_table: {len(processed_list)} records, {len(files)} files and "
                         f"{len(groups)} groups; need one of each per record")
    return [record_row(p, f, g) for p, f, g in zip(processed_list, files, groups)]


def write_speed_table(path: Path, rows: Sequence[Mapping[str, Any]]) -> str:
    """The table (`TABLE_COLUMNS`, rows of `speed_table`) as CSV through `fileio.write_table`:
    numbers round-trip exactly (the shortest text of each float), a non-finite one is left
    empty. Returns the path as text."""
    return write_table(path, TABLE_COLUMNS, rows, "")


def record_summary(processed: ProcessedImpact) -> dict[str, Any]:
    """One record's result: `ImpactFeatures.to_dict` with the processing's `filter`, the
    `baseline_offset_n` removed (N) and the `load_cell_resonance` divided out (or None)."""
    return {**processed.features.to_dict(),
            "filter": processed.filtered.metadata.get("filter", "none"),
            "baseline_offset_n": processed.raw.metadata.get("baseline_offset_n", 0.0),
            "load_cell_resonance": processed.filtered.metadata.get("load_cell_resonance")}


def record_group(processed: ProcessedImpact, file: str | Path,
                 nominal_m_s: Sequence[float] | None = None,
                 tolerance: float = DEFAULT_SPEED_TOLERANCE) -> float:
    """The speed group (m/s) of a single record: the nominal speed it lies within `tolerance`
    of (`group_by_speed`; `InputError` when none), or without `nominal_m_s` its impact speed."""
    speed = processed.features.values["P15"]
    if nominal_m_s is None:
        return speed
    return float(group_by_speed([speed], nominal_m_s, tolerance, files=[str(file)])[0])


def summarise_repeats(
    processed_list: Sequence[ProcessedImpact],
    files: Sequence[str | Path],
    nominal_m_s: Sequence[float] | None = None,
    tolerance: float = DEFAULT_SPEED_TOLERANCE,
) -> dict[str, Any]:
    """Many records of one ball kind, grouped by speed (`group_by_speed`, to `nominal_m_s` or
    clustered within `tolerance`), their masses checked per group (`check_masses`) and a nominal
    speed no record went to warned of (`warn_empty_nominal`): `grouping` (`rule` nominal or
    clustered, `nominal_speeds_m_s`, `speed_tolerance`), `groups` (`group_summaries`: mean and
    SD, ddof 1, of every feature per group) and `records` (`speed_table`: a row per record)."""
    names = [str(f) for f in files]
    speeds = [p.features.values["P15"] for p in processed_list]
    groups = group_by_speed(speeds, nominal_m_s, tolerance, files=names)
    check_masses([p.features.mass_kg for p in processed_list], names, groups)
    if nominal_m_s is not None:
        warn_empty_nominal(nominal_m_s, groups)
    rows = speed_table(processed_list, names, groups)
    return {"grouping": {"rule": "nominal" if nominal_m_s is not None else "clustered",
                         "nominal_speeds_m_s": (sorted(nominal_m_s) if nominal_m_s is not None
                                                else None),
                         "speed_tolerance": tolerance},
            "groups": group_summaries(rows, nominal=nominal_m_s is not None),
            "records": rows}


def mean_sd(rows: Sequence[Mapping[str, Any]], columns: Sequence[str] | None = None
            ) -> tuple[dict[str, float], dict[str, float]]:
    """Mean and sample standard deviation (ddof = 1) of each numeric column over `rows`
    (`columns`, default the numeric ones of the first row). One row: SD NaN (unknown)."""
    if not rows:
        raise InputError("rows: need at least one row")
    if columns is None:
        columns = [k for k, v in rows[0].items()
                   if isinstance(v, (int, float)) and not isinstance(v, bool)]
    mean: dict[str, float] = {}
    sd: dict[str, float] = {}
    for name in columns:
        values = np.array([row[name] for row in rows], dtype=float)
        mean[name] = float(np.mean(values))
        sd[name] = float(np.std(values, ddof=1)) if values.size > 1 else math.nan
    return mean, sd


def group_summaries(rows: Sequence[Mapping[str, Any]], nominal: bool = False
                    ) -> list[dict[str, Any]]:
    """Per speed group (by increasing speed): `speed_m_s` (the nominal speed, or the group's
    mean speed when clustered), `speed_source`, `count`, `files`, and `mean` and `sd` (ddof = 1)
    of every feature column (`FEATURE_COLUMNS`)."""
    out = []
    for label in sorted({row["group_speed_m_s"] for row in rows}):
        members = [row for row in rows if row["group_speed_m_s"] == label]
        mean, sd = mean_sd(members, FEATURE_COLUMNS)
        out.append({"speed_m_s": label, "speed_source": "nominal" if nominal else "group mean",
                     "count": len(members), "files": [row["file"] for row in members],
                     "mean": mean, "sd": sd})
    return out


# --------------------------------------------------------------------------- mean pulse and band


@dataclass(frozen=True)
class PulseBand:
    """The mean pulse of a speed group and its scatter, on a common grid `time_s` (s from each
    pulse's contact start): mean, sample SD (ddof = 1; NaN for one record), min and max (N)."""

    speed_m_s: float
    count: int
    time_s: np.ndarray
    mean_n: np.ndarray
    sd_n: np.ndarray
    min_n: np.ndarray
    max_n: np.ndarray

    def record(self, mass_kg: float, impact_speed_m_s: float,
               rebound_speed_m_s: float | None = None, lead_samples: int = 20) -> ImpactRecord:
        """The mean pulse as an `ImpactRecord` (to fit or identify the mean of the repeats):
        the grid with `lead_samples` zero-force samples before and after at its step, so that
        the pipeline finds the contact window and a zero baseline; the scalars are the
        caller's (e.g. the group's mean speeds and the ball's mass)."""
        step = float(self.time_s[1] - self.time_s[0])
        pad = np.arange(1, lead_samples + 1) * step
        time = np.concatenate([-pad[::-1], self.time_s, self.time_s[-1] + pad])
        force = np.concatenate([np.zeros(lead_samples), self.mean_n, np.zeros(lead_samples)])
        return ImpactRecord(time, force, mass_kg=mass_kg, impact_speed_m_s=impact_speed_m_s,
                            rebound_speed_m_s=rebound_speed_m_s,
                            metadata={"source": f"mean of {self.count} repeats at "
                                                f"{self.speed_m_s:.4g} m/s"})

    def to_dict(self) -> dict[str, Any]:
        return {"speed_m_s": self.speed_m_s, "count": self.count, "time_s": self.time_s.tolist(),
                "mean_n": self.mean_n.tolist(), "sd_n": self.sd_n.tolist(),
                "min_n": self.min_n.tolist(), "max_n": self.max_n.tolist()}


def aligned_pulse(features: ImpactFeatures, time_s: np.ndarray) -> np.ndarray:
    """The pulse of `features` at `time_s` (s from its contact start, as `extract_features`
    places it: where the rising edge reaches zero force): the piecewise-linear curve the
    features are computed from, zero before contact and after the ball has left."""
    return np.interp(time_s, features.time_s, features.force_n, left=0.0, right=0.0)


def pulse_band(features_list: Sequence[ImpactFeatures], speed_m_s: float = math.nan,
               points: int = 201) -> PulseBand:
    """The band of pulses aligned at their contact start, on `points` equal steps from 0 to the
    longest contact time of the group (a shorter pulse is zero after its own end)."""
    if not features_list:
        raise InputError("features_list: need at least one record")
    if points < 2:
        raise InputError(f"points: need at least 2, got {points}")
    end = max(f.values["P1"] for f in features_list)
    grid = np.linspace(0.0, end, points)
    forces = np.array([aligned_pulse(f, grid) for f in features_list])
    sd = (np.std(forces, axis=0, ddof=1) if len(features_list) > 1
          else np.full(points, math.nan))
    return PulseBand(float(speed_m_s), len(features_list), grid, forces.mean(axis=0), sd,
                     forces.min(axis=0), forces.max(axis=0))


def pulse_bands(processed_list: Sequence[ProcessedImpact], groups: Sequence[float],
                points: int = 201) -> list[PulseBand]:
    """`pulse_band` of each speed group (by increasing speed)."""
    labels = np.asarray(groups, dtype=float)
    return [pulse_band([processed_list[i].features for i in np.flatnonzero(labels == label)],
                       float(label), points)
            for label in np.unique(labels)]


def plot_pulse_bands(ax, bands: Sequence[PulseBand]):
    """Draw each group's mean pulse, its mean +/- SD band (shaded) and its min/max envelope
    (dotted) on the matplotlib Axes `ax` (time in ms, force in kN); returns `ax`."""
    for i, band in enumerate(bands):
        color = f"C{i % 10}"
        t_ms = band.time_s * 1e3
        ax.plot(t_ms, band.mean_n / 1e3, color=color, lw=1.6,
                label=f"{band.speed_m_s:.3g} m/s: mean of {band.count}")
        if band.count > 1:
            ax.fill_between(t_ms, (band.mean_n - band.sd_n) / 1e3,
                            (band.mean_n + band.sd_n) / 1e3, color=color, alpha=0.25, lw=0)
            ax.plot(t_ms, band.min_n / 1e3, color=color, lw=0.7, ls=":")
            ax.plot(t_ms, band.max_n / 1e3, color=color, lw=0.7, ls=":")
    ax.plot([], [], color="0.4", lw=6, alpha=0.3, label="mean ± SD")
    ax.plot([], [], color="0.4", lw=0.7, ls=":", label="min / max")
    ax.set(xlabel="time from contact start (ms)", ylabel="normal force (kN)",
           title="mean pulse per speed, aligned at contact start")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return ax


def warn_empty_nominal(nominal_m_s: Sequence[float], groups: Sequence[float]) -> list[float]:
    """Nominal speeds that no record went to, each with an `InputWarning` (a likely typo in
    --speeds, or records missing); returns them."""
    present = set(np.asarray(groups, dtype=float).tolist())
    empty = [float(v) for v in check_nominal(nominal_m_s) if float(v) not in present]
    for speed in empty:
        warnings.warn(f"nominal speed {speed:g} m/s: no record within the speed tolerance",
                      InputWarning, stacklevel=2)
    return empty
