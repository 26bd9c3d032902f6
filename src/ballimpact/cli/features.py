"""`ballimpact features`: the 19 characteristic values of a measured impact, or of many
(repeated tests): a table, per-speed means and standard deviations, and the mean pulse's band."""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any

from .. import repeats
from ..errors import InputError
from ..features import FEATURE_NAMES
from ..fileio import write_table
from ..pipeline import ProcessedImpact
from .common import (
    add_processing,
    add_record_options,
    check_output_folder,
    check_plot_path,
    load,
    process_record,
)


def add_parser(verbs) -> None:
    features = verbs.add_parser(
        "features", help="characteristic values of measured impacts (CSV or WAV)",
        description="Load an impact test, remove the load-cell offset, filter, and print the 19 "
                    "characteristic values (thesis table 6-1) with COR, impulse check, "
                    "compression, energy lost and dynamic stiffness. With several records (files "
                    "or folders of them): a row per record, the records grouped by impact speed "
                    "(to --speeds, or clustered) with the mean and standard deviation of every "
                    "feature per group, and the mean pulse with its scatter band (--plot).")
    features.add_argument("files", nargs="+", type=Path, metavar="FILE_OR_DIR",
                          help="test records: CSV with unit headers or WAV, or folders of them "
                               "(their *.csv and *.wav files)")
    add_record_options(features)
    add_processing(features)
    features.add_argument("--table", type=Path,
                          help="write a CSV table, a row per record (file, speed group, every "
                               "feature; units in the column names)")
    features.add_argument("--speeds", type=speed_list, metavar="V1,V2,...",
                          help="nominal impact speeds (m/s) to group the records to, e.g. "
                               "5,10,20; default: cluster the measured speeds")
    features.add_argument("--speed-tolerance", type=float,
                          default=repeats.DEFAULT_SPEED_TOLERANCE,
                          help="relative speed tolerance of the grouping: a record within this "
                               "fraction of a nominal speed; without --speeds, a speed more than "
                               "this fraction above its group's lowest starts a new group "
                               f"(default {repeats.DEFAULT_SPEED_TOLERANCE})")


def speed_list(text: str) -> list[float]:
    """argparse type of --speeds: speeds in m/s separated by commas (`sweep.parse_speeds`; that
    they are positive is `repeats.check_nominal`'s)."""
    from ..sweep import parse_speeds

    try:
        return list(parse_speeds(text))
    except InputError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def run(args: argparse.Namespace) -> dict[str, Any]:
    check_plot_path(args.plot)
    check_table_path(args.table)
    repeats.check_tolerance(args.speed_tolerance)
    if args.speeds is not None:
        repeats.check_nominal(args.speeds)
    files = record_files(args.files, args.table)
    if len(files) > 1:
        return run_repeats(files, args)
    started = time.perf_counter()
    processed = process_record(load(files[0], args), args)
    group = [processed.features.values["P15"]]
    if args.speeds is not None:  # a single record must still lie near a nominal speed
        group = repeats.group_by_speed(group, args.speeds, args.speed_tolerance,
                                       files=[str(files[0])])
    result = summary(processed, time.perf_counter() - started)
    if args.table is not None:
        result["table_csv"] = write_repeats_table(
            args.table, repeats.speed_table([processed], [str(files[0])], group))
    if not args.json:
        print_table(processed)
    if args.plot:
        from ..plotting import plot_impact  # matplotlib only when a plot is asked for

        plot_impact(processed.raw, processed.filtered, processed.features, args.plot,
                    title=str(files[0].name))
        result["plot"] = str(args.plot)
    return result


def check_table_path(path: Path | None) -> None:
    if path is None:
        return
    if path.suffix.lower() != ".csv":
        raise InputError(f"--table: {path} must be a .csv file")
    check_output_folder(path, "--table")


def record_files(given: list[Path], table: Path | None) -> list[Path]:
    """The records of FILE_OR_DIR (`repeats.expand_records`), less the --table output when a
    folder holds it (the table of an earlier run); a record given by name is never overwritten."""
    if table is None:
        return repeats.expand_records(given)
    target = table.resolve()
    named = next((p for p in given if not p.is_dir() and p.resolve() == target), None)
    if named is not None:
        raise InputError(f"--table: {table} is one of the records given ({named}); write the "
                         "table to another file")
    files = [p for p in repeats.expand_records(given) if p.resolve() != target]
    if not files:
        raise InputError(f"{table.parent}: the folder holds no test records besides the "
                         f"--table output {table.name}")
    return files


def run_repeats(files: list[Path], args: argparse.Namespace) -> dict[str, Any]:
    """Several records: a row each, grouped by speed, with per-group means and SDs."""
    started = time.perf_counter()
    processed = [process_record(load(path, args), args) for path in files]
    names = [str(path) for path in files]
    speeds = [p.features.values["P15"] for p in processed]
    groups = repeats.group_by_speed(speeds, args.speeds, args.speed_tolerance, files=names)
    repeats.check_masses([p.features.mass_kg for p in processed], names, groups)
    if args.speeds is not None:
        repeats.warn_empty_nominal(args.speeds, groups)
    rows = repeats.speed_table(processed, names, groups)
    summaries = repeats.group_summaries(rows, nominal=args.speeds is not None)
    result: dict[str, Any] = {
        "grouping": {"rule": "nominal" if args.speeds is not None else "clustered",
                     "nominal_speeds_m_s": (sorted(args.speeds) if args.speeds is not None
                                            else None),
                     "speed_tolerance": args.speed_tolerance},
        "groups": summaries,
        "records": rows,
        "wall_time_s": time.perf_counter() - started,
    }
    if args.table is not None:
        result["table_csv"] = write_repeats_table(args.table, rows)
    if args.plot:
        from ..plotting import save_and_close, subplots  # matplotlib only for a plot

        figure, ax = subplots(figsize=(7.5, 4.5), layout="constrained")
        repeats.plot_pulse_bands(ax, repeats.pulse_bands(processed, groups))
        save_and_close(figure, args.plot)
        result["plot"] = str(args.plot)
    if not args.json:
        print_groups(result)
    return result


def write_repeats_table(path: Path, rows: list[dict[str, Any]]) -> str:
    """The table (`repeats.TABLE_COLUMNS`) as CSV (`fileio.write_table`): numbers round-trip
    exactly (the shortest text of each float), a non-finite one is left empty."""
    return write_table(path, repeats.TABLE_COLUMNS, rows, "")


def print_groups(result: dict[str, Any]) -> None:
    grouping = result["grouping"]
    rule = ("to the nominal speeds" if grouping["rule"] == "nominal"
            else "clustered: a group spans at most the tolerance above its lowest speed")
    print(f"{len(result['records'])} records in {len(result['groups'])} speed groups ({rule}; "
          f"tolerance {grouping['speed_tolerance']:.0%}); mean ± SD (ddof 1)")
    header = ["speed (m/s)", "n", "impact speed (m/s)", "COR", "peak force (N)",
              "contact time (ms)", "dyn. stiffness (N/m)"]
    scales = {"contact_time_s": 1e3}
    lines = [header]
    for group in result["groups"]:
        cells = [f"{group['speed_m_s']:.4g}", str(group["count"])]
        for name in repeats.MAIN_COLUMNS:
            scale = scales.get(name, 1.0)
            mean, sd = group["mean"][name] * scale, group["sd"][name] * scale
            cells.append(f"{mean:.5g} ± {sd:.2g}" if math.isfinite(sd) else f"{mean:.5g}")
        lines.append(cells)
    widths = [max(len(line[k]) for line in lines) for k in range(len(header))]
    for line in lines:
        print("  " + "  ".join(cell.ljust(width) for cell, width in zip(line, widths)).rstrip())
    if "table_csv" in result:
        print(f"table (a row per record): {result['table_csv']}")


def summary(processed: ProcessedImpact, wall_time_s: float) -> dict[str, Any]:
    out = processed.features.to_dict()
    out["filter"] = processed.filtered.metadata.get("filter", "none")
    out["baseline_offset_n"] = processed.raw.metadata.get("baseline_offset_n", 0.0)
    out["load_cell_resonance"] = processed.filtered.metadata.get("load_cell_resonance")
    out["wall_time_s"] = wall_time_s
    return out


def print_table(processed: ProcessedImpact) -> None:
    f = processed.features
    u = f.uncertainty or {}
    print(f"filter: {processed.filtered.metadata.get('filter', 'none')}   pulse: {f.method}   "
          f"baseline offset removed: {processed.raw.metadata.get('baseline_offset_n', 0.0):.4g} N")
    resonance = processed.filtered.metadata.get("load_cell_resonance")
    if resonance:
        print(f"  load-cell resonance {resonance['frequency_hz']:.0f} Hz (damping ratio "
              f"{resonance['damping_ratio']:.3f}) divided out")
    if u:
        print("  (+/- the standard uncertainty from the record's noise; 90% interval: +/- 1.645 "
              "of it)")
    for key, name in FEATURE_NAMES.items():
        spread = f"  +/- {u[key]:.2g}" if u.get(key) else ""
        print(f"  {key:>4}  {name:<42} {f.values[key]:.6g}{spread}")
    check = f.impulse_check_passed
    status = "not checked (rebound speed from impulse)" if check is None else (
        f"{f.impulse_relative_error:+.2%} ({'ok' if check else 'FAILED'}, "
        f"tolerance {f.impulse_tolerance:.1%})")
    print(f"  rebound speed source: {f.rebound_speed_source}")
    spread = f" +/- {u['impulse_n_s']:.2g}" if u.get("impulse_n_s") else ""
    print(f"  impulse {f.impulse_n_s:.5g}{spread} N s; impulse check: {status}")
    print(f"  impulse COR {f.impulse_cor:.4f}; max compression {f.max_compression_m * 1e3:.4g} mm; "
          f"energy lost {f.energy_lost_j:.4g} J; dynamic stiffness {f.dynamic_stiffness_n_m:.4g} N/m")
