"""`ballimpact demo`: the main job on a built-in default (README): the two cricket-ball presets'
FE impacts, printed and plotted, and the built-in sample test identified (`universal.demo`)."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

from ..verdict import verdict_line
from .common import add_json, use_compilation_cache

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
    from ..universal.demo import DEMO_IMPACTS, DEMO_NOTES, demo_impacts, demo_summaries

    use_compilation_cache()
    started = time.perf_counter()
    results = demo_impacts(lambda name, speed: _stderr(f"simulating {name} at {speed:g} m/s ..."),
                           args.plot)
    impacts = demo_summaries(results)
    if not args.json:
        print("ballimpact demo: explicit FE, normal impact on a rigid plane")
        print(f"{'ball':<28}{'speed m/s':>10}{'peak kN':>9}{'contact ms':>11}{'COR':>7}"
              f"{'energy err':>11}{'elements':>9}{'steps':>7}{'wall s':>8}")
        for (name, _), r in zip(DEMO_IMPACTS, results):
            label = r.ball_name + (" *" if name in DEMO_NOTES else "")
            print(f"{label:<28}{r.impact_speed_m_s:>10.4g}{r.peak_force_n / 1e3:>9.3f}"
                  f"{r.contact_time_s * 1e3:>11.4f}{r.cor:>7.3f}{r.energy_balance_error:>11.1e}"
                  f"{r.elements:>9d}{r.steps:>7d}{r.wall_time_s:>8.2f}")
        for name, note in DEMO_NOTES.items():
            print(f"* {name}: {note}")
        print(f"plot written to {args.plot}")
    identified = _demo_identify(args.json)
    return {"impacts": impacts, "identify": identified,
            "plot": str(args.plot), "wall_time_s": time.perf_counter() - started}


def _demo_identify(quiet: bool) -> dict[str, Any]:
    """The built-in sample test identified as a universal ball with the built-in model
    (`universal.demo.identify_sample`), printed unless `quiet`."""
    from ..universal.demo import SAMPLE_CONTACT_TIME_S, SAMPLE_PEAK_FORCE_N, identify_sample

    _stderr("identifying the built-in sample test with the built-in universal model ...")
    sample = identify_sample()
    if not quiet:
        found, contact, u = sample.found, sample.contact_time_s, sample.contact_time_uncertainty_s
        p, v = found.params, found.verification
        print(f"sample test: contact time {contact * 1e3:.3f} +/- {u * 1e3:.3f} ms with the "
              f"default processing (exact {SAMPLE_CONTACT_TIME_S * 1e3:.3f} ms: "
              f"{contact / SAMPLE_CONTACT_TIME_S - 1:+.1%}), peak force "
              f"{sample.peak_force_n:.0f} N (exact {SAMPLE_PEAK_FORCE_N:.0f} N)")
        print(f"identify (built-in sample test at {found.impact_speed_m_s:g} m/s, built-in "
              f"model): C10 {p['c10_pa'] / 1e6:.3f} MPa, C01 {p['c01_pa'] / 1e6:.3f} MPa, "
              f"g1 {p['g1']:.3f}, tau1 {p['tau1_s'] * 1e6:.1f} us")
        print(f"  FE check {verdict_line(v)}")
        print(f"  force NRMSE {v['force_nrmse']:.1%}, COR {v['cor_simulated']:.3f} "
              f"(test {v['cor_measured']:.3f}), contact time "
              f"{v['contact_time_simulated_s'] * 1e3:.3f} ms (test "
              f"{v['contact_time_measured_s'] * 1e3:.3f} ms), {found.wall_time_s:.1f} s")
        for note in sample.notes:
            print(f"  note: {note}")
    return sample.to_dict()
