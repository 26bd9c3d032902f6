"""Cost of one quasi-static compression curve (`fe.compress`): the cricket-universal ball (25 m/s
constants) and the cricket-3layer ball on the default mesh, 20 increments to 5 mm, long-term
curve, and the universal ball at a platen speed of 1 m/s. Compilation (first call of the jitted
forces and tangent probes) and the solve are timed apart; a second call of the same structure
compiles nothing. The reference measured in the same run: one explicit impact of the same ball at
25 m/s (`fe.simulate`, default options, second call), and the ratio of a curve's solve to it.
The universal ball's long-term curve on the 3D geometry too (`fe.Hexahedral`, half model of
`DIVISIONS_3D` divisions, the pole grading chosen for the platens; one call), against the
axisymmetric curve's solve and peak force. Prints one JSON object.

    python benchmarks/bench_compress.py
"""

from __future__ import annotations

import json
import os
import platform
import time
import warnings

import jax

from ballimpact.fe import Hexahedral, Options3D, SolverOptions, compress, load_ball, simulate

DEFLECTION_M, STEPS = 5e-3, 20
DIVISIONS_3D = 12


def curve(name: str, rate_m_s=None) -> dict:
    ball = load_ball(name, impact_speed_m_s=25.0)
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        first = compress(ball, DEFLECTION_M, steps=STEPS, rate_m_s=rate_m_s,
                         options=SolverOptions())
        first_wall = time.perf_counter() - started
        second = compress(ball, DEFLECTION_M, steps=STEPS, rate_m_s=rate_m_s,
                          options=SolverOptions())
    return {"ball": name, "rate_m_s": rate_m_s, "deflection_m": DEFLECTION_M, "steps": STEPS,
            "elements": second.elements, "jacobian_products": second.jacobian_products,
            "increments": second.increments, "newton_iterations": second.newton_iterations,
            "peak_force_n": second.peak_force_n,
            "end_stiffness_n_m": second.end_stiffness_n_m,
            "first_call_s": first_wall, "compile_s": first.compile_time_s,
            "solve_s": second.wall_time_s - second.compile_time_s,
            "second_call_s": second.wall_time_s}


def curve_3d(name: str, axisymmetric: dict) -> dict:
    ball = load_ball(name, impact_speed_m_s=25.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = compress(ball, DEFLECTION_M, steps=STEPS,
                          geometry=Hexahedral(Options3D(divisions=DIVISIONS_3D)))
    solve = result.wall_time_s - result.compile_time_s
    return {"ball": name, "geometry": "3d", "divisions": DIVISIONS_3D,
            "deflection_m": DEFLECTION_M, "steps": STEPS, "elements": result.elements,
            "nodes": result.nodes, "jacobian_products": result.jacobian_products,
            "increments": result.increments, "newton_iterations": result.newton_iterations,
            "peak_force_n": result.peak_force_n, "compile_s": result.compile_time_s,
            "solve_s": solve,
            "peak_force_over_axisymmetric": result.peak_force_n / axisymmetric["peak_force_n"],
            "solve_over_axisymmetric": solve / axisymmetric["solve_s"]}


def impact_s(name: str) -> float:
    """Wall time (s) of one impact of the ball at 25 m/s, compiled (second call)."""
    ball = load_ball(name, impact_speed_m_s=25.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        simulate(ball, 25.0)
        started = time.perf_counter()
        simulate(ball, 25.0)
    return time.perf_counter() - started


def main() -> None:
    out = {"machine": {"platform": platform.platform(), "processor": platform.processor(),
                       "cpu_count": os.cpu_count(), "python": platform.python_version(),
                       "jax": jax.__version__, "backend": jax.default_backend()},
           "curves": [curve("cricket-universal"), curve("cricket-universal", rate_m_s=1.0),
                      curve("cricket-3layer")]}
    for c in out["curves"]:
        c["impact_25_m_s_s"] = impact_s(c["ball"])
        c["curve_to_impact_ratio"] = c["solve_s"] / c["impact_25_m_s_s"]
    out["curve_3d"] = curve_3d("cricket-universal", out["curves"][0])
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
