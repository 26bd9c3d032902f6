"""The stable increment of 3D runs on a deformable target, printed as JSON: the increment with the
contact springs' two-mass factor taken node by node (what the solver does: only the ball nodes
that can meet the target, against the lightest partner they can meet) against the bound over
every pair (the heaviest ball node on the lightest target node, the solver's rule before),
both from the same Lanczos estimate in the same run, and one run with the solver's rule (timed
with its compilation).

Cases: the gripping study's sphere on a slab of its own material (nu 0.23, Psi 1, 16 divisions
graded to 2.9 elements across the contact, penalty 3, the slab matched to the contact) and the
soft-pad example (universal ball at 25 m/s, 8 divisions).

    python benchmarks/bench_target_increment.py
"""

from __future__ import annotations

import json
import math
import os
import platform
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from ballimpact import fe
from ballimpact.fe.steps import cast
from ballimpact.fe.programs import compiled_run
from ballimpact.fe.engine import kernel_for
from ballimpact.fe.hex.geometry import model_arrays
from ballimpact.oblique import ImpactCondition, Options3D, Target

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples"))

import oblique_gripping as gripping  # noqa: E402


def increments_s(ball, condition, options, target) -> tuple[float, float]:
    """(node by node, every pair) stable increments (s) at the first touch."""
    geometry = fe.Hexahedral(options).checked(ball, [condition], target)
    options = geometry.options
    kernel, _ = kernel_for(ball, geometry, target)
    params = model_arrays(ball, target, kernel, options, condition)
    mass, s = params.mass_kg, np.asarray(kernel.contact_nodes)
    top = mass[np.asarray(kernel.target["top"])]
    every_pair = params._replace(contact_spring_factor=np.full(
        len(s), 1.0 + np.max(mass[s]) / np.min(top)))
    _, init = compiled_run(kernel, options.chunk_steps, False)
    out = []
    with jax.enable_x64(True):
        for p in (params, every_pair):
            p = jax.tree_util.tree_map(jnp.asarray, cast(p, kernel.dtype))
            state = init(p, *(jnp.asarray(x, kernel.dtype) for x in (
                condition.speed_m_s, math.radians(condition.angle_deg),
                np.asarray(condition.spin_vector_rad_s))))
            out.append(float(state.dt))
    return out[0], out[1]


def case(name, ball, condition, options, target) -> dict:
    node_by_node, every_pair = increments_s(ball, condition, options, target)
    started = time.perf_counter()
    run = fe.simulate(ball, condition, geometry=fe.Hexahedral(options), target=target)
    return {"case": name, "elements": run.elements, "steps": run.steps,
            "run_with_compilation_s": time.perf_counter() - started,
            "increment_node_by_node_s": node_by_node, "increment_every_pair_s": every_pair,
            "increment_ratio": node_by_node / every_pair,
            "peak_force_n": run.peak_force_n, "normal_cor": run.normal_cor}


def main() -> None:
    sphere = gripping.sphere(0.23)
    options, slab = gripping.setting(0.23, on_slab=True)
    (psi_1,) = gripping.conditions([1.0], gripping.FRICTION, gripping.NORMAL_SPEED_M_S)
    pad = Target.from_dict(json.loads((ROOT / "examples/targets/soft-pad.json").read_text()))
    cases = [case("elastic sphere nu 0.23 on a slab of its own material, Psi 1", sphere, psi_1,
                  options, slab),
             case("universal ball 25 m/s on the soft pad, 8 divisions",
                  fe.load_ball("cricket-universal", impact_speed_m_s=25.0),
                  ImpactCondition(25.0), Options3D(divisions=8), pad)]
    print(json.dumps({"machine": f"{platform.machine()}, {os.cpu_count()} CPUs, JAX "
                                 f"{jax.__version__} on {jax.default_backend()}",
                      "cases": cases}, indent=1))


if __name__ == "__main__":
    main()
