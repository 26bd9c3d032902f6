"""The `ballimpact` command (DESIGN.md "Command line contract").

Exit codes: 0 success, 2 bad input (one line on stderr naming the problem), 1 failed run.
With `--json` one JSON object goes to stdout; warnings and progress go to stderr.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
import warnings
from importlib import resources
from pathlib import Path
from typing import Any

from . import __version__
from .errors import InputError
from .features import DEFAULT_IMPULSE_TOLERANCE, FEATURE_NAMES
from .filters import FILTER_NAMES
from .loaders import load_record
from .pipeline import ProcessedImpact, process

DEMO_FILTER = "loess"
DEMO_PLOT = "ballimpact-demo.png"


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2, no usage dump
        raise InputError(f"{self.prog}: {message}")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="ballimpact", description="Sports-ball impact modelling (SI units).")
    parser.add_argument("--version", action="version", version=f"ballimpact {__version__}")
    verbs = parser.add_subparsers(dest="verb", required=True, metavar="VERB")

    features = verbs.add_parser(
        "features", help="characteristic values of a measured impact (CSV or WAV)",
        description="Load an impact test, remove the load-cell offset, filter, and print the 19 "
                    "characteristic values (thesis table 6-1) with COR, impulse check, "
                    "compression, energy lost and dynamic stiffness.")
    features.add_argument("file", type=Path, help="test record: CSV with unit headers or WAV")
    features.add_argument("--mass-kg", type=float, help="ball mass (kg)")
    features.add_argument("--impact-speed-m-s", type=float, help="impact speed (m/s)")
    features.add_argument("--rebound-speed-m-s", type=float,
               help="measured rebound speed (m/s); from the impulse if not given")
    features.add_argument("--sensitivity-v-per-n", type=float, help="WAV: load-cell sensitivity (V/N)")
    features.add_argument("--amplifier-gain", type=float, help="WAV: amplifier gain (default 1)")
    features.add_argument("--full-scale-v", type=float, help="WAV: volts at digital full scale (default 1)")
    features.add_argument("--channel", type=int, help="WAV: channel index (default 0)")
    _add_processing(features)

    demo = verbs.add_parser(
        "demo", help="the main job on built-in data",
        description="Process the built-in sample impact (a synthetic cricket-ball test, see "
                    "data/sample_impact.csv) and print its figures.")
    demo.add_argument("--json", action="store_true", help="print one JSON object")
    demo.add_argument("--plot", type=Path, default=Path(DEMO_PLOT),
                      help=f"PNG to write (default {DEMO_PLOT})")
    return parser


def _add_processing(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--filter", default="none",
                        help=f"one of {', '.join(FILTER_NAMES)}, or cfc<N> (default none)")
    parser.add_argument("--filter-window-s", type=float,
                        help="window of savgol/lowess/loess (s); default 10%% of contact time")
    parser.add_argument("--resample-hz", type=float, help="resample to this uniform rate first")
    parser.add_argument("--impulse-tolerance", type=float, default=DEFAULT_IMPULSE_TOLERANCE,
                        help="relative misfit allowed between impulse and m(v_in + v_out) "
                             f"(default {DEFAULT_IMPULSE_TOLERANCE})")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--plot", type=Path, help="write force-time and force-displacement PNG")


def main(argv: list[str] | None = None) -> int:
    try:
        args = build_parser().parse_args(argv)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = {"features": _run_features, "demo": _run_demo}[args.verb](args)
        notes = list(dict.fromkeys(str(w.message) for w in caught))
    except InputError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    except Exception as error:  # noqa: BLE001 - a failed run, reported in one line
        print(f"error: failed run: {type(error).__name__}: {error}", file=sys.stderr)
        return 1
    for note in notes:
        print(f"warning: {note}", file=sys.stderr)
    result["warnings"] = notes
    if args.json:
        print(json.dumps(_json_safe(result), indent=2))
    return 0


def _run_features(args: argparse.Namespace) -> dict[str, Any]:
    _check_plot_path(args.plot)
    started = time.perf_counter()
    record = load_record(
        args.file, mass_kg=args.mass_kg, impact_speed_m_s=args.impact_speed_m_s,
        rebound_speed_m_s=args.rebound_speed_m_s, sensitivity_v_per_n=args.sensitivity_v_per_n,
        amplifier_gain=args.amplifier_gain, full_scale_v=args.full_scale_v, channel=args.channel)
    processed = _process(record, args)
    result = _summary(processed, time.perf_counter() - started)
    if not args.json:
        _print_table(processed)
    if args.plot:
        _plot(processed, args.plot, title=str(args.file.name))
        result["plot"] = str(args.plot)
    return result


def _run_demo(args: argparse.Namespace) -> dict[str, Any]:
    _check_plot_path(args.plot)
    started = time.perf_counter()
    data = resources.files("ballimpact") / "data" / "sample_impact.csv"
    with resources.as_file(data) as path:
        record = load_record(path)
    processed = process(record, filter=DEMO_FILTER)
    result = _summary(processed, time.perf_counter() - started)
    result["record"] = "built-in synthetic cricket-ball test (data/sample_impact.csv)"
    _plot(processed, args.plot, title="ballimpact demo: synthetic cricket-ball impact")
    result["plot"] = str(args.plot)
    if not args.json:
        print("ballimpact demo: built-in synthetic cricket-ball impact test "
              "(Hunt-Crossley model + load-cell ringing and noise, 200 kHz)")
        _print_table(processed)
        print(f"plot written to {args.plot}")
    return result


def _check_plot_path(path: Path | None) -> None:
    if path is None:
        return
    if path.suffix.lower() != ".png":
        raise InputError(f"--plot: {path} must be a .png file")
    if not path.parent.is_dir():
        raise InputError(f"--plot: folder {path.parent} does not exist")


def _process(record, args: argparse.Namespace) -> ProcessedImpact:
    return process(record, filter=args.filter, window_s=args.filter_window_s,
                   resample_hz=args.resample_hz, impulse_tolerance=args.impulse_tolerance)


def _summary(processed: ProcessedImpact, wall_time_s: float) -> dict[str, Any]:
    summary = processed.features.to_dict()
    summary["filter"] = processed.filtered.metadata.get("filter", "none")
    summary["baseline_offset_n"] = processed.raw.metadata.get("baseline_offset_n", 0.0)
    summary["wall_time_s"] = wall_time_s
    return summary


def _plot(processed: ProcessedImpact, path: Path, title: str) -> None:
    from .plotting import plot_impact  # matplotlib only when a plot is asked for

    plot_impact(processed.raw, processed.filtered, processed.features, path, title=title)


def _print_table(processed: ProcessedImpact) -> None:
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


def _json_safe(value: Any) -> Any:
    """Replace non-finite floats (invalid in JSON) by None."""
    if isinstance(value, dict):
        return {key: _json_safe(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(item) for item in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


if __name__ == "__main__":
    sys.exit(main())
