"""Write the ball presets of other sports (docs/balls.md, "Presets"), once.

For each ball of `data/sports_balls.json` with a published `specification` or stated `targets`
(not `golf-core` or `softball-12in`, which are sizes): a homogeneous universal ball at the middle
of its rule's size and mass limits, written to `src/ballimpact/data/presets/<name>.json` as a
ball file whose `description` and `source` say where everything comes from. Its constants:

- `specification` (a COR at 60 mph and a compression force at a platen approach): calibrated to
  both by FE impacts and compressions (`standards.specification.ball_for_specification`);
- `targets` (a COR and a dynamic stiffness at 26.8 m/s): identified by the built-in universal
  model (`universal.targets.constants_for`, with its FE check and, where the surrogate misses,
  FE-driven corrections).

Prints a table.

    python examples/make_sports_presets.py [name ...]   (default: every ball with either)
"""

import json
import sys
import time
from pathlib import Path

from ballimpact.cli.common import use_compilation_cache
from ballimpact.fe import load_ball
from ballimpact.progress import progress_line
from ballimpact.standards.specification import Specification, ball_for_specification
from ballimpact.universal import load_model
from ballimpact.universal.families import nominal_size, sports_balls
from ballimpact.universal.targets import constants_for

FOLDER = Path(__file__).resolve().parents[1] / "src" / "ballimpact" / "data" / "presets"


def preset(name: str, rule: dict, found: dict) -> dict:
    """The ball file of preset `name` from its rule entry and `constants_for`'s answer."""
    t, fe = rule["targets"], found["fe_check"]
    size = found["ball_size"]
    spec = dict(found["ball"])
    spec["name"] = name
    spec["description"] = (
        f"{name}: a homogeneous universal ball, {size['diameter_m'] * 1e3:.2f} mm and "
        f"{size['mass_kg'] * 1e3:.2f} g (the middle of its rule's limits): constants identified "
        f"by the universal model from the stated COR {t['cor']:g} and DS "
        f"{t['dynamic_stiffness_n_m']:.4g} N/m at {t['impact_speed_m_s']:g} m/s (not measured "
        f"here). FE check of this ball at {t['impact_speed_m_s']:g} m/s: COR {fe['cor']:.3f}, "
        f"DS {fe['dynamic_stiffness_n_m']:.4g} "
        f"N/m (peak force {fe['peak_force_n']:.4g} N, contact time "
        f"{fe['contact_time_s'] * 1e3:.3f} ms). Choices: C01 = 0, tau1 at the middle of the "
        "model's range (log axis) scaled to the ball.")
    spec["source"] = (f"size and mass: {rule['source']}. COR: {t['cor_source']}. DS: "
                      f"{t['dynamic_stiffness_source']}.")
    return finished(spec, size["mass_kg"])


def finished(spec: dict, mass_kg: float) -> dict:
    """`spec` with the figures `balls --json` adds (outer radius, mass), checked as a preset will
    be."""
    spec["outer_radius_m"] = spec["layers"][0]["outer_radius_m"]
    spec["mass_kg"] = mass_kg
    load_ball(spec)
    return spec


def specified(name: str, rule: dict, size) -> dict:
    """The ball file of preset `name` calibrated to its rule's published `specification`."""
    t = rule["specification"]
    spec = Specification(2 * size.radius_m, size.mass_kg, t["cor"], t["compression_force_n"],
                         t["compression_deflection_m"], t["impact_speed_m_s"])
    found = ball_for_specification(spec, name, progress=progress_line)
    p, fe = found["params"], found["check"]
    ball = dict(found["ball"])
    ball["description"] = (
        f"{name}: a homogeneous universal ball, {2e3 * size.radius_m:.2f} mm and "
        f"{size.mass_kg * 1e3:.2f} g (the middle of its rule's limits): constants calibrated by "
        f"FE runs to the published COR {t['cor']:g} at {t['impact_speed_m_s']:g} m/s off a rigid "
        f"wall (ASTM F1887) and compression {t['compression_force_n']:.4g} N at "
        f"{t['compression_deflection_m'] * 1e3:.4g} mm (ASTM F1888; long-term), not measured "
        f"here. FE check on the mesh of `standard --ball` ({found['element_size_m'] * 1e3:.3g} "
        f"mm elements): COR {fe['cor']:.4f}, compression {fe['compression_force_n']:.4g} N; DS "
        f"{fe['dynamic_stiffness_n_m']:.4g} N/m (peak force {fe['peak_force_n']:.4g} N, contact "
        f"time {fe['contact_time_s'] * 1e3:.3f} ms). Choices: C01 = 0, tau1 at the middle of the "
        "universal model's range (log axis) scaled to the ball.")
    ball["source"] = (f"size and mass: {rule['source']}. COR: {t['cor_source']}. Compression: "
                      f"{t['compression_source']}.")
    finished(ball, size.mass_kg)
    print(f"{name:<15}{2e3 * size.radius_m:7.2f}{size.mass_kg * 1e3:8.2f}{t['cor']:7.3f}"
          f"{t['compression_force_n']:9.4g} N | {p['c10_pa'] / 1e6:8.3f}{p['g1']:7.4f}"
          f"{p['tau1_s'] * 1e6:8.2f} | {fe['cor']:7.4f}{fe['compression_force_n']:9.4g} N "
          f"DS {fe['dynamic_stiffness_n_m']:.4g} {found['wall_time_s']:5.1f} s", flush=True)
    return ball


def main(names: list[str]) -> None:
    use_compilation_cache()
    model = load_model()
    balls = sports_balls()
    names = names or [n for n, b in balls.items() if "targets" in b or "specification" in b]
    FOLDER.mkdir(parents=True, exist_ok=True)
    print(f"{'preset':<15}{'D mm':>7}{'m g':>8}{'COR':>7}{'DS N/m':>10} | {'C10 MPa':>8}{'g1':>7}"
          f"{'tau1 us':>8} | {'FE COR':>7}{'FE DS':>10}{'dCOR':>8}{'dDS':>7} corr   s")
    for name in names:
        rule = balls[name]
        if "specification" in rule:
            spec = specified(name, rule, nominal_size(name))
            (FOLDER / f"{name}.json").write_text(json.dumps(spec, indent=2) + "\n")
            continue
        if "targets" not in rule:
            raise SystemExit(f"{name}: no specification or targets in data/sports_balls.json")
        t = rule["targets"]
        started = time.perf_counter()
        found = constants_for(model, nominal_size(name), t["cor"], t["dynamic_stiffness_n_m"],
                              t["impact_speed_m_s"])
        spec = preset(name, rule, found)
        (FOLDER / f"{name}.json").write_text(json.dumps(spec, indent=2) + "\n")
        p, fe, size = found["params"], found["fe_check"], found["ball_size"]
        print(f"{name:<15}{size['diameter_m'] * 1e3:7.2f}{size['mass_kg'] * 1e3:8.2f}"
              f"{t['cor']:7.3f}{t['dynamic_stiffness_n_m']:10.4g} | {p['c10_pa'] / 1e6:8.3f}"
              f"{p['g1']:7.3f}{p['tau1_s'] * 1e6:8.2f} | {fe['cor']:7.3f}"
              f"{fe['dynamic_stiffness_n_m']:10.4g}{fe['cor_error']:+8.4f}"
              f"{fe['ds_relative_error']:+7.2%} {found['corrections']:4d} "
              f"{time.perf_counter() - started:5.1f}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
