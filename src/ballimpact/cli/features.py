"""`ballimpact features`: the 19 characteristic values of a measured impact, or of many
(repeated tests): a table, per-speed means and standard deviations, and the mean pulse's band."""

from __future__ import annotations

import argparse
import math
from functools import partial
from pathlib import Path
from typing import Any

from ..records import repeats
from ..records.features import FEATURE_NAMES
from ..records.pipeline import ProcessedImpact
from .common import add_processing, add_speed_grouping, load, process_record


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
    add_processing(features)
    features.add_argument("--table", type=Path,
                          help="write a CSV table, a row per record (file, speed group, every "
                               "feature; units in the column names)")
    add_speed_grouping(features)


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..records.summaries import features_of_files

    result, processed = features_of_files(
        args.files, load=partial(load, args=args), process=partial(process_record, args=args),
        nominal_m_s=args.speeds, tolerance=args.speed_tolerance, table_path=args.table,
        plot_path=args.plot)
    if not args.json:
        if len(processed) > 1:
            print_groups(result)
        else:
            print_table(processed[0])
    return result


def print_groups(result: dict[str, Any]) -> None:
    grouping = result["grouping"]
    rule = ("to the nominal speeds" if grouping["rule"] == "nominal"
            else "clustered: a group spans at most the tolerance above its lowest speed")
    print(f"{len(result['records'])} records in {len(result['groups'])} speed groups ({rule}; "
          f"tolerance {grouping['speed_tolerance']:.0%}); mean ± SD (ddof 1)")
    lines = [["speed (m/s)", "n", "impact speed (m/s)", "COR", "peak force (N)",
              "contact time (ms)", "dyn. stiffness (N/m)"]]
    for group in result["groups"]:
        cells = [f"{group['speed_m_s']:.4g}", str(group["count"])]
        for name in repeats.MAIN_COLUMNS:
            scale = 1e3 if name == "contact_time_s" else 1.0
            mean, sd = group["mean"][name] * scale, group["sd"][name] * scale
            cells.append(f"{mean:.5g} ± {sd:.2g}" if math.isfinite(sd) else f"{mean:.5g}")
        lines.append(cells)
    widths = [max(map(len, column)) for column in zip(*lines)]
    for line in lines:
        print("  " + "  ".join(cell.ljust(width) for cell, width in zip(line, widths)).rstrip())
    if "table_csv" in result:
        print(f"table (a row per record): {result['table_csv']}")


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
    print(f"  impulse COR {f.impulse_cor:.4f}; max compression {f.max_compression_m * 1e3:.4g} "
          f"mm; energy lost {f.energy_lost_j:.4g} J; dynamic stiffness "
          f"{f.dynamic_stiffness_n_m:.4g} N/m")
