"""The size-free universal model on balls of other sports (docs/universal.md, "Any solid ball").

For each family (sizes and masses from their rules, `data/sports_balls.json`): synthetic tests of
homogeneous balls of that size with constants inside the built-in model's ranges, 1% white noise
at 100 kHz, identified with the built-in (cricket-ball) model through similarity and
re-simulated; prints the closed-loop figures per family and writes them to
identify_other_balls.json.

    python examples/identify_other_balls.py [runs per family, default 12]
"""

import json
import sys
import time

from ballimpact.cli.common import use_compilation_cache
from ballimpact.universal import load_model
from ballimpact.universal.families import FAMILIES, family_closed_loop, nominal_size


def main(runs: int) -> None:
    use_compilation_cache()
    model = load_model()
    table = []
    for seed, name in enumerate((*FAMILIES, "cricket-men")):
        started = time.perf_counter()
        # a seed per family: each family's test balls are other points of the model's ranges
        out = family_closed_loop(model, nominal_size(name), runs=runs, seed=seed, label=name)
        s = out["summary"]
        s["wall_time_s"] = time.perf_counter() - started
        table.append(s)
        print(f"{name:<14} D {s['diameter_m'] * 1e3:5.1f} mm  m {s['mass_kg'] * 1e3:5.1f} g  "
              f"force NRMSE median {s['force_nrmse']['median']:.2%} p90 "
              f"{s['force_nrmse']['p90']:.2%} max {s['force_nrmse']['max']:.2%} | "
              f"|COR error| median {s['cor_error']['median']:.4f} max {s['cor_error']['max']:.4f} | "
              f"contact time median {s['contact_time_relative_error']['median']:.2%} max "
              f"{s['contact_time_relative_error']['max']:.2%} | failed {s['failed']} | "
              f"{s['wall_time_s']:.0f} s", flush=True)
    with open("identify_other_balls.json", "w") as f:
        json.dump(table, f, indent=2)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 12)
