"""`ballimpact features`: the 19 characteristic values of a measured impact, or of many
(repeated tests): a table, per-speed means and standard deviations, and the mean pulse's band."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from .common import add_processing, add_speed_grouping, print_lines, record_options


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
    from ..records.text import features_lines

    result, processed = features_of_files(
        args.files, options=record_options(args), nominal_m_s=args.speeds,
        tolerance=args.speed_tolerance, table_path=args.table, plot_path=args.plot)
    if not args.json:
        print_lines(features_lines(result, processed))
    return result
