"""`ballimpact demo`: the main job on a built-in default (README): the two cricket-ball presets'
FE impacts, printed and plotted, and the built-in sample test identified (`universal.demo`)."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

from .common import add_json, print_lines, use_compilation_cache

DEMO_PLOT = "ballimpact-demo.png"


def add_parser(verbs) -> None:
    demo = verbs.add_parser(
        "demo", help="the main job: FE impacts of the two cricket-ball presets",
        description="Simulate the cricket-universal ball at 25 m/s and the cricket-3layer ball "
                    "at 20.8 m/s on a rigid plane; print peak force, contact time, COR and the "
                    "energy balance error, and write one PNG.")
    add_json(demo)
    demo.add_argument("--plot", type=Path, default=Path(DEMO_PLOT),
                      help=f"PNG to write (default {DEMO_PLOT})")


def _stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def run_demo(args: argparse.Namespace) -> dict[str, Any]:
    from ..universal.demo import demo_impacts, demo_summaries
    from ..universal.text import demo_lines

    use_compilation_cache()
    started = time.perf_counter()
    results = demo_impacts(lambda name, speed: _stderr(f"simulating {name} at {speed:g} m/s ..."),
                           args.plot)
    impacts = demo_summaries(results)
    if not args.json:
        print_lines(demo_lines(results, args.plot))
    identified = _demo_identify(args.json)
    return {"impacts": impacts, "identify": identified,
            "plot": str(args.plot), "wall_time_s": time.perf_counter() - started}


def _demo_identify(quiet: bool) -> dict[str, Any]:
    """The built-in sample test identified as a universal ball with the built-in model
    (`universal.demo.identify_sample`), printed unless `quiet`."""
    from ..universal.demo import identify_sample
    from ..universal.text import sample_lines

    _stderr("identifying the built-in sample test with the built-in universal model ...")
    sample = identify_sample()
    if not quiet:
        print_lines(sample_lines(sample))
    return sample.to_dict()
