"""`ballimpact demo`: the main job on a built-in default (README): the two cricket-ball presets'
FE impacts, printed and plotted, and the built-in sample test identified."""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path
from typing import Any

from ..errors import InputWarning
from .common import check_plot_path, use_compilation_cache

DEMO_PLOT = "ballimpact-demo.png"
DEMO_IMPACTS = (("cricket-universal", 25.0), ("cricket-3layer", 20.8))
#: notes on demo impacts whose figures should not be read as a model of the real ball
DEMO_NOTES = {"cricket-3layer": (
    "thesis chapter 5 constants as printed: COR far above the measured 0.5-0.6, because only "
    "the core relaxes; the thesis' calibrated values cannot be reproduced from them "
    "(docs/fe.md, Limits and notes)")}


def add_parser(verbs) -> None:
    demo = verbs.add_parser(
        "demo", help="the main job: FE impacts of the two cricket-ball presets",
        description="Simulate the cricket-universal ball at 25 m/s and the cricket-3layer ball "
                    "at 20.8 m/s on a rigid plane; print peak force, contact time, COR and the "
                    "energy balance error, and write one PNG.")
    demo.add_argument("--json", action="store_true", help="print one JSON object")
    demo.add_argument("--plot", type=Path, default=Path(DEMO_PLOT),
                      help=f"PNG to write (default {DEMO_PLOT})")


def run_demo(args: argparse.Namespace) -> dict[str, Any]:
    from ..fe import load_ball, simulate
    from ..plotting import plot_fe

    check_plot_path(args.plot)
    use_compilation_cache()
    started = time.perf_counter()
    results = []
    for name, speed in DEMO_IMPACTS:
        print(f"simulating {name} at {speed:g} m/s ...", file=sys.stderr, flush=True)
        results.append(simulate(load_ball(name, impact_speed_m_s=speed), speed))
    plot_fe(results, args.plot, title="ballimpact demo: cricket balls on a rigid plane (FE)")
    impacts = [r.summary() for r in results]
    for (name, _), impact in zip(DEMO_IMPACTS, impacts):
        if name in DEMO_NOTES:
            impact["note"] = DEMO_NOTES[name]
    if not args.json:
        print("ballimpact demo: explicit FE, normal impact on a rigid plane")
        print(f"{'ball':<28}{'speed m/s':>10}{'peak kN':>9}{'contact ms':>11}{'COR':>7}"
              f"{'energy err':>11}{'elements':>9}{'steps':>7}{'wall s':>8}")
        for (name, _), r in zip(DEMO_IMPACTS, results):
            label = r.ball_name + (" *" if name in DEMO_NOTES else "")
            print(f"{label:<28}{r.impact_speed_m_s:>10.4g}{r.peak_force_n / 1e3:>9.3f}"
                  f"{r.contact_time_s * 1e3:>11.4f}{r.cor:>7.3f}{r.energy_balance_error:>11.1e}"
                  f"{r.elements:>9d}{r.steps:>7d}{r.wall_time_s:>8.2f}")
        for name, _ in DEMO_IMPACTS:
            if name in DEMO_NOTES:
                print(f"* {name}: {DEMO_NOTES[name]}")
        print(f"plot written to {args.plot}")
    identified = _demo_identify(args.json)
    return {"impacts": impacts, "identify": identified,
            "plot": str(args.plot), "wall_time_s": time.perf_counter() - started}


def _demo_identify(quiet: bool) -> dict[str, Any]:
    """The built-in sample test identified as a universal ball with the built-in model."""
    from importlib import resources

    from ..loaders import load_record
    from ..pipeline import process
    from ..universal import identify, load_model
    from ..verdict import verdict_line

    print("identifying the built-in sample test with the built-in universal model ...",
          file=sys.stderr, flush=True)
    sample = Path(str(resources.files("ballimpact") / "data" / "sample_impact.csv"))
    model = load_model()
    # warnings are about a user's own data (issue 24): the package's sample and model are ours,
    # so what identify would warn about (a C01 interval on its training bound) is a printed note
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InputWarning)
        test = process(load_record(sample))
        found = identify(test, model, options=model.solver_options())
    contact, u = test.features.values["P1"], (test.features.uncertainty or {}).get("P1", 0.0)
    notes = [str(w.message).removeprefix(f"{sample}: ") for w in caught
             if issubclass(w.category, InputWarning)]
    for w in caught:  # anything else goes on as a warning
        if not issubclass(w.category, InputWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    if not quiet:
        p, v = found.params, found.verification
        print(f"sample test: contact time {contact * 1e3:.3f} +/- {u * 1e3:.3f} ms with the "
              f"default processing (exact {SAMPLE_CONTACT_TIME_S * 1e3:.3f} ms: "
              f"{contact / SAMPLE_CONTACT_TIME_S - 1:+.1%}), peak force "
              f"{test.features.values['P6']:.0f} N (exact {SAMPLE_PEAK_FORCE_N:.0f} N)")
        print(f"identify (built-in sample test at {found.impact_speed_m_s:g} m/s, built-in "
              f"model): C10 {p['c10_pa'] / 1e6:.3f} MPa, C01 {p['c01_pa'] / 1e6:.3f} MPa, "
              f"g1 {p['g1']:.3f}, tau1 {p['tau1_s'] * 1e6:.1f} us")
        print(f"  FE check {verdict_line(v)}")
        print(f"  force NRMSE {v['force_nrmse']:.1%}, COR {v['cor_simulated']:.3f} "
              f"(test {v['cor_measured']:.3f}), contact time "
              f"{v['contact_time_simulated_s'] * 1e3:.3f} ms (test "
              f"{v['contact_time_measured_s'] * 1e3:.3f} ms), {found.wall_time_s:.1f} s")
        for note in notes:
            print(f"  note: {note}")
    return {"file": "sample_impact.csv (built-in, synthetic)",
            "sample_contact_time_s": contact, "sample_contact_time_uncertainty_s": u,
            "sample_exact_contact_time_s": SAMPLE_CONTACT_TIME_S, **found.to_dict(),
            "notes": notes}


#: The built-in sample's exact contact time (s) and peak force (N): its header, written by
#: examples/make_sample_record.py.
SAMPLE_CONTACT_TIME_S = 1.09704e-3
SAMPLE_PEAK_FORCE_N = 11219.9
