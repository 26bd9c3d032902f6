"""The 3D solver's cost on this machine, printed as JSON.

The thesis' oblique case (section 5.2.4: the universal ball at 37 m/s, 34 degrees; friction 0.3,
the thesis gives none): 34 degrees to the surface (the thesis' figure 2-1 measures incidence from
the horizontal, so 56 degrees from the normal) in float64 and float32 arithmetic, each run twice
(the first compiles, the second reuses the compiled program), and 34 degrees from the normal
(float32, compiled), on a half model of about 20k hexahedra (24 divisions), with the time JAX spent
tracing, lowering and compiling in each run. Reference measured in
the same run: the axisymmetric solver's normal impact of the same ball at the same normal speed
(default mesh, compiled; the best of 3), and the ratio of the two engines' element updates per
second (issue 28: within 3 times).

    python benchmarks/bench_oblique.py [--divisions 24]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import time

import jax
import jax.monitoring

from ballimpact.fe import Hexahedral, load_ball, simulate
from ballimpact.oblique import ImpactCondition, Options3D

SPEED_M_S, FRICTION = 37.0, 0.3


#: JAX's compile events (s), summed over the process: tracing, lowering, XLA compilation
COMPILE_EVENTS = {"/jax/core/compile/jaxpr_trace_duration": 0.0,
                  "/jax/core/compile/jaxpr_to_mlir_module_duration": 0.0,
                  "/jax/core/compile/backend_compile_duration": 0.0}


def _count_compile(event: str, seconds: float, **kwargs) -> None:
    if event in COMPILE_EVENTS:
        COMPILE_EVENTS[event] += seconds


def main() -> None:
    jax.monitoring.register_event_duration_secs_listener(_count_compile)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--divisions", type=int, default=24)
    args = parser.parse_args()
    ball = load_ball("cricket-universal", impact_speed_m_s=SPEED_M_S)
    runs = []
    for angle, precision in ((56.0, "float64"), (56.0, "float64"), (56.0, "float32"),
                             (56.0, "float32"), (34.0, "float32")):
        condition = ImpactCondition(SPEED_M_S, angle, 0.0, FRICTION)
        options = Options3D(divisions=args.divisions, precision=precision)
        compiling = sum(COMPILE_EVENTS.values())
        started = time.perf_counter()
        r = simulate(ball, condition, geometry=Hexahedral(options))
        wall = time.perf_counter() - started
        compiling = sum(COMPILE_EVENTS.values()) - compiling
        compiled = any(r["precision"] == precision for r in runs)
        runs.append({"angle_from_normal_deg": angle, "precision": precision,
                     "includes_compilation": not compiled, "wall_time_s": wall,
                     "tracing_lowering_compiling_s": compiling,
                     "per_step_ms": wall / r.steps * 1e3, "steps": r.steps,
                     "element_updates_per_s": r.elements * r.steps / wall,
                     "elements": r.elements, "normal_cor": r.normal_cor,
                     "tangential_cor": r.tangential_cor,
                     "rebound_angle_deg": r.rebound_angle_deg,
                     "rebound_spin_rad_s": r.rebound_spin_rad_s,
                     "peak_force_n": r.peak_force_n, "contact_time_s": r.contact_time_s,
                     "energy_balance_error": r.energy_balance_error,
                     "history_digest": r.history_digest(),
                     "frictional_dissipation_j": r.energies_j["frictional_dissipation_j"],
                     "initial_kinetic_energy_j": r.energies_j["initial_kinetic_energy_j"]})
    normal_speed = SPEED_M_S * math.cos(math.radians(56.0))
    simulate(ball, normal_speed)  # compile
    axi_walls = []
    for _ in range(3):
        started = time.perf_counter()
        axi = simulate(ball, normal_speed)
        axi_walls.append(time.perf_counter() - started)
    axi_wall = min(axi_walls)
    axi_rate = axi.elements * axi.steps / axi_wall
    out = {"machine": {"platform": platform.platform(), "processor": platform.processor(),
                       "cpus": os.cpu_count(), "jax_backend": jax.default_backend()},
           "ball": ball.name, "speed_m_s": SPEED_M_S, "friction": FRICTION,
           "divisions": args.divisions, "runs": runs,
           "axisymmetric_reference": {"normal_speed_m_s": normal_speed, "wall_time_s": axi_wall,
                                      "elements": axi.elements, "steps": axi.steps,
                                      "element_updates_per_s": axi_rate},
           # issue 28: the 3D engine's per-element rate within 3 times the axisymmetric one's
           "axisymmetric_rate_over_3d": {
               f"{r['angle_from_normal_deg']:g}deg_{r['precision']}": axi_rate
               / r["element_updates_per_s"] for r in runs if not r["includes_compilation"]},
           "ratio_3d_compiled_to_axisymmetric": {
               f"{r['angle_from_normal_deg']:g}deg_{r['precision']}": r["wall_time_s"] / axi_wall
               for r in runs if not r["includes_compilation"]}}
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
