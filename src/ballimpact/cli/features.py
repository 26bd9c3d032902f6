"""`ballimpact features`: the 19 characteristic values of a measured impact."""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from ..features import FEATURE_NAMES
from ..pipeline import ProcessedImpact
from .common import add_processing, add_record_options, check_plot_path, load, process_record


def add_parser(verbs) -> None:
    features = verbs.add_parser(
        "features", help="characteristic values of a measured impact (CSV or WAV)",
        description="Load an impact test, remove the load-cell offset, filter, and print the 19 "
                    "characteristic values (thesis table 6-1) with COR, impulse check, "
                    "compression, energy lost and dynamic stiffness.")
    features.add_argument("file", type=Path, help="test record: CSV with unit headers or WAV")
    add_record_options(features)
    add_processing(features)


def run(args: argparse.Namespace) -> dict[str, Any]:
    check_plot_path(args.plot)
    started = time.perf_counter()
    processed = process_record(load(args.file, args), args)
    result = summary(processed, time.perf_counter() - started)
    if not args.json:
        print_table(processed)
    if args.plot:
        from ..plotting import plot_impact  # matplotlib only when a plot is asked for

        plot_impact(processed.raw, processed.filtered, processed.features, args.plot,
                    title=str(args.file.name))
        result["plot"] = str(args.plot)
    return result


def summary(processed: ProcessedImpact, wall_time_s: float) -> dict[str, Any]:
    out = processed.features.to_dict()
    out["filter"] = processed.filtered.metadata.get("filter", "none")
    out["baseline_offset_n"] = processed.raw.metadata.get("baseline_offset_n", 0.0)
    out["wall_time_s"] = wall_time_s
    return out


def print_table(processed: ProcessedImpact) -> None:
    f = processed.features
    print(f"filter: {processed.filtered.metadata.get('filter', 'none')}   "
          f"baseline offset removed: {processed.raw.metadata.get('baseline_offset_n', 0.0):.4g} N")
    for key, name in FEATURE_NAMES.items():
        print(f"  {key:>4}  {name:<42} {f.values[key]:.6g}")
    check = f.impulse_check_passed
    status = "not checked (rebound speed from impulse)" if check is None else (
        f"{f.impulse_relative_error:+.2%} ({'ok' if check else 'FAILED'}, "
        f"tolerance {f.impulse_tolerance:.1%})")
    print(f"  rebound speed source: {f.rebound_speed_source}")
    print(f"  impulse {f.impulse_n_s:.5g} N s; impulse check: {status}")
    print(f"  impulse COR {f.impulse_cor:.4f}; max compression {f.max_compression_m * 1e3:.4g} mm; "
          f"energy lost {f.energy_lost_j:.4g} J; dynamic stiffness {f.dynamic_stiffness_n_m:.4g} N/m")
