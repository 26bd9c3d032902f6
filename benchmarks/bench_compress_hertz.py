"""Benchmark: `compress` of an elastic sphere with its default mesh against Hertz and against a
converged reference.

Neo-Hookean spheres (R 36 mm, mu 2 MPa, nu 0.3 and 0.49: D1 = 2 / K) squeezed to D / 2R =
0.25, 1, 2 and 5%, each deflection a run of its own, as a user runs it:
- `default`: `fe.compress` with no options (`compression_options`: both poles refined to about 5
  elements across the Hertz contact radius, platen penalty 30);
- `before`: the mesh and penalty it used before issue 43 (uniform 1.5 mm, penalty 1);
- `reference`: 20 elements across the contact radius at both poles and penalty 100 (10 elements
  and penalty 30 move it by at most 0.3%).
Printed per case: the force over Hertz's for a sphere between two plates (each contact approaches
D / 2: F = 4/3 E* sqrt(R) (D/2)^1.5), the default's and the old mesh's force over the reference's,
elements and wall time. The reference's excess over Hertz grows as sqrt(D / 2R) (Hertz's
half-space ignores the sphere's finite size), so it is reported as excess / sqrt(D / 2R) too.

Run: python benchmarks/bench_compress_hertz.py
"""

from __future__ import annotations

import json
import math
import os
import platform
import time
import warnings

from ballimpact.closedform import hertz_stiffness
from ballimpact.fe import SolverOptions, compress, load_ball

R_M, MU_PA = 0.036, 2.0e6
FRACTIONS = (0.0025, 0.01, 0.02, 0.05)


def sphere(nu: float):
    bulk = 2.0 * MU_PA * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu))
    return load_ball({"name": f"neo-hookean-nu{nu:g}", "layers": [{
        "outer_radius_m": R_M, "density_kg_m3": 1000.0,
        "material": {"model": "neo_hookean", "c10_pa": MU_PA / 2, "d1_per_pa": 2.0 / bulk}}]})


def hertz_n(deflection_m: float, nu: float) -> float:
    """Each platen's contact approaches D / 2."""
    return hertz_stiffness(2.0 * MU_PA * (1.0 + nu), nu, R_M) * (0.5 * deflection_m) ** 1.5


def reference_options(deflection_m: float) -> SolverOptions:
    a = math.sqrt(R_M * deflection_m / 2)
    return SolverOptions(pole_element_size_m=min(a / 20, 1.5e-3), both_poles=True,
                         pole_zone_deg=min(max(math.degrees(2.5 * a / R_M), 5.0), 45.0),
                         penalty_scale=100.0)


def run(ball, deflection_m: float, options) -> tuple[float, int, float]:
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = compress(ball, deflection_m, steps=4, options=options)
    return float(result.force_n[-1]), result.elements, time.perf_counter() - started


def main() -> None:
    cases = []
    for nu in (0.3, 0.49):
        ball = sphere(nu)
        for fraction in FRACTIONS:
            d = fraction * 2 * R_M
            ref, ref_elements, _ = run(ball, d, reference_options(d))
            default, elements, seconds = run(ball, d, None)
            before, before_elements, _ = run(ball, d, SolverOptions())
            excess = ref / hertz_n(d, nu) - 1
            cases.append({
                "nu": nu, "deflection_over_diameter": fraction, "deflection_m": d,
                "hertz_n": hertz_n(d, nu), "reference_n": ref,
                "reference_over_hertz": ref / hertz_n(d, nu),
                "reference_excess_over_sqrt_d_2r": excess / math.sqrt(fraction),
                "default_over_hertz": default / hertz_n(d, nu),
                "default_over_reference": default / ref,
                "before_over_hertz": before / hertz_n(d, nu),
                "before_over_reference": before / ref,
                "elements": {"default": elements, "before": before_elements,
                             "reference": ref_elements},
                "default_wall_s": round(seconds, 2)})
            print(json.dumps(cases[-1]), file=__import__("sys").stderr)
    worst = max(abs(c["default_over_reference"] - 1) for c in cases)
    print(json.dumps({"machine": f"{platform.machine()}, {os.cpu_count()} cores",
                      "cases": cases, "default_worst_vs_reference": worst}, indent=1))


if __name__ == "__main__":
    main()
