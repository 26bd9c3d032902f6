"""A universal model on the material families of solid sports balls (issue 42; docs/universal.md,
"A study in the groups").

For each family of `data/ball_families.json` (lacrosse-like soft to golf-core-like stiff, typical
boxes of the constants and speeds on the ball of its rules' size and mass): `runs` synthetic
tests of homogeneous balls (seeded Sobol over the family's boxes), 1% white noise at 100 kHz,
identified with the model and re-simulated on the model's mesh scaled to the ball. Prints the
closed-loop figures per family (force NRMSE, |COR error|, contact time and peak force errors:
median and 90th percentile) and writes them to identify_ball_families.json.

    python examples/identify_ball_families.py [--model MODEL] [--runs 12] [--family NAME ...]
"""

import argparse
import json
import time

from ballimpact.cli.common import use_compilation_cache
from ballimpact.universal import load_model
from ballimpact.universal.families import (
    MATERIAL_FAMILIES,
    family_box_tests,
    family_closed_loop,
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--model", help="model path (default: the built-in model)")
    parser.add_argument("--runs", type=int, default=12, help="balls per family (default 12)")
    parser.add_argument("--family", action="append", choices=MATERIAL_FAMILIES,
                        help="only these families (repeatable; default all six)")
    parser.add_argument("--out", default="identify_ball_families.json")
    args = parser.parse_args()
    use_compilation_cache()
    model = load_model(args.model)
    table = []
    for seed, name in enumerate(MATERIAL_FAMILIES):
        if args.family and name not in args.family:
            continue
        started = time.perf_counter()
        size, params, speeds = family_box_tests(name, args.runs, seed)
        out = family_closed_loop(model, size, label=name, seed=seed, tests=(params, speeds))
        s = out["summary"]
        s["wall_time_s"] = time.perf_counter() - started
        s["on_training_bound"] = sum(bool(r.get("at_training_bound")) for r in out["rows"])
        table.append(s)
        print(f"{name:<16} force NRMSE median {s['force_nrmse']['median']:.2%} p90 "
              f"{s['force_nrmse']['p90']:.2%} | |COR error| median "
              f"{s['cor_error']['median']:.4f} p90 {s['cor_error']['p90']:.4f} | contact time "
              f"median {s['contact_time_relative_error']['median']:.2%} p90 "
              f"{s['contact_time_relative_error']['p90']:.2%} | peak force p90 "
              f"{s['peak_force_relative_error']['p90']:.2%} | failed {s['failed']}, on a bound "
              f"{s['on_training_bound']} | {s['wall_time_s']:.0f} s", flush=True)
    with open(args.out, "w") as f:
        json.dump(table, f, indent=2)


if __name__ == "__main__":
    main()
