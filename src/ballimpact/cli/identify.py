"""`ballimpact identify`: a universal FE ball from measured impacts."""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

from .common import (
    add_processing,
    add_record_options,
    check_output_folder,
    check_plot_path,
    load,
    process_record,
    use_compilation_cache,
)


def add_parser(verbs) -> None:
    identify = verbs.add_parser(
        "identify", help="universal FE ball (C10, C01, g1, tau1) from measured impacts",
        description="Features of the test -> the universal ball's parameters with 90%% "
                    "intervals (inverse deep ensemble), optionally refined on the forward surrogate -> one "
                    "FE run of the identified ball compared with the test. Several tests (one "
                    "per speed) give a table of parameters against speed, like thesis table 7-3.")
    identify.add_argument("files", type=Path, nargs="+", metavar="FILE",
                          help="test record(s): CSV with unit headers or WAV")
    identify.add_argument("--model", help="model path (MODEL.json + MODEL.npz); default: the "
                                          "built-in cricket-ball model")
    identify.add_argument("--verify", action=argparse.BooleanOptionalAction, default=True,
                          help="run the identified ball in the FE engine and compare (default)")
    identify.add_argument("--refine", choices=("none", "surrogate"), default="none",
                          help="least squares on the forward surrogate after the inverse "
                               "estimate; default none: on held-out runs it made the closed loop worse, see docs/universal.md")
    identify.add_argument("--table", type=Path, help="with several files: write the speed table")
    identify.add_argument("--ball-out", type=Path, metavar="FILE.json",
                          help="write the identified ball for `simulate --ball`: with several "
                               "files, a ball holding the speed table, interpolated at the "
                               "impact speed as the cricket-universal preset")
    add_record_options(identify)
    add_processing(identify)


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..universal.identify import identify
    from ..universal.model import load_model

    check_plot_path(args.plot)
    check_output_folder(args.table, "--table")
    check_output_folder(args.ball_out, "--ball-out")
    started = time.perf_counter()
    model = load_model(args.model)
    if args.verify:
        use_compilation_cache()
    options = model.solver_options()
    results = []
    for path in args.files:
        processed = process_record(load(path, args), args)
        found = identify(processed, model, verify=args.verify, refine=args.refine,
                         options=options)
        results.append((path, processed, found))
        if not args.json:
            _print(path, found)
    out: dict[str, Any] = {**results[0][2].to_dict(), "file": str(results[0][0])} \
        if len(results) == 1 else {"identifications": [
            {**f.to_dict(), "file": str(p)} for p, _, f in results]}
    if len(results) > 1:
        rows = speed_table_ball([f for _, _, f in results], model)["speed_table"]["rows"]
        out["table"] = rows
        if args.table is not None:
            lines = [",".join(rows[0])] + [",".join(f"{v:.6g}" for v in r.values()) for r in rows]
            args.table.write_text("\n".join(lines) + "\n")
            out["table_csv"] = str(args.table)
        if not args.json:
            print("speed_m_s,c10_pa,c01_pa,g1,tau1_s")
            for r in rows:
                print(",".join(f"{v:.6g}" for v in r.values()))
    if args.ball_out is not None:
        ball = results[0][2].ball if len(results) == 1 else speed_table_ball(
            [f for _, _, f in results], model)
        args.ball_out.write_text(json.dumps(ball, indent=2))
        out["ball_file"] = str(args.ball_out)
    if args.plot is not None:
        from ..universal.plots import plot_identification

        plot_identification([(p.name, pr, f) for p, pr, f in results], args.plot)
        out["plot"] = str(args.plot)
    out["wall_time_s"] = time.perf_counter() - started
    return out


def speed_table_ball(found: list, model) -> dict[str, Any]:
    """A ball file holding the identified parameters against impact speed."""
    template = model.metadata["template"]
    rows = sorted(({"speed_m_s": f.impact_speed_m_s, **{k: f.params[k] for k in
                   ("c10_pa", "c01_pa", "g1", "tau1_s")}} for f in found),
                  key=lambda r: r["speed_m_s"])
    return {"name": "identified-universal", "speed_table": {
        "outer_radius_m": template["radius_m"], "density_kg_m3": template["density_kg_m3"],
        "moduli": template["moduli"], "rows": rows}}


def _print(path: Path, found) -> None:
    from ..universal.model import TARGET_UNITS

    print(f"{path.name}: universal ball at {found.impact_speed_m_s:g} m/s "
          f"(refine: {found.refine})")
    for name, value in found.params.items():
        low, high = found.interval_90[name]
        unit = TARGET_UNITS[name] if TARGET_UNITS[name] != "1" else ""
        print(f"  {name:<8} {value:11.5g} {unit:<3} 90% interval {low:.4g} .. {high:.4g}")
    v = found.verification
    if v:
        print(f"  FE check: force NRMSE {v['force_nrmse']:.2%}; COR {v['cor_simulated']:.4f} vs "
              f"{v['cor_measured']:.4f}; contact time {v['contact_time_simulated_s'] * 1e3:.4g} vs "
              f"{v['contact_time_measured_s'] * 1e3:.4g} ms; peak {v['peak_force_simulated_n']:.5g}"
              f" vs {v['peak_force_measured_n']:.5g} N")
