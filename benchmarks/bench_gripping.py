"""The cost of the gripping-regime checks on this machine, printed as JSON: the elastic-sphere
reference (`oblique.elastic_reference`, 200 incidences, the curves a sweep plot draws), one 3D
run of the elastic sphere on the default mesh, and an angle sweep of six angles as one batch on
the same mesh (`ballimpact simulate --solver 3d --angle-deg 5,10,20,30,45,60`'s run), each
compiled first so the times are the runs'. Reference measured in the same run: the single run.

    python benchmarks/bench_gripping.py [--divisions 16]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

import jax
import numpy as np

from ballimpact.balls.ball import BallModel, Layer
from ballimpact.constitutive import material_from_dict
from ballimpact.fe import Hexahedral, simulate_batch
from ballimpact.oblique import ImpactCondition, Options3D
from ballimpact.oblique.elastic_reference import normalised_curves

ANGLES_DEG, SPEED_M_S, FRICTION = (5.0, 10.0, 20.0, 30.0, 45.0, 60.0), 3.0, 0.3


def sphere() -> BallModel:
    material = {"model": "linear_elastic", "youngs_modulus_pa": 100e6, "poissons_ratio": 0.3}
    return BallModel("elastic sphere", (Layer("sphere", 0.036, 800.0,
                                              material_from_dict(material)),))


def timed(fn):
    started = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--divisions", type=int, default=16)
    args = parser.parse_args()
    ball, options = sphere(), Options3D(divisions=args.divisions)
    _, reference_s = timed(lambda: normalised_curves(np.linspace(0.05, 12.0, 200), 0.3))
    single = [ImpactCondition(SPEED_M_S, 30.0, 0.0, FRICTION)]
    sweep = [ImpactCondition(SPEED_M_S, a, 0.0, FRICTION) for a in ANGLES_DEG]
    _, single_first_s = timed(lambda: simulate_batch(ball, single, geometry=Hexahedral(options)))
    one, single_s = timed(lambda: simulate_batch(ball, single, geometry=Hexahedral(options)))
    _, sweep_first_s = timed(lambda: simulate_batch(ball, sweep, geometry=Hexahedral(options)))
    runs, sweep_s = timed(lambda: simulate_batch(ball, sweep, geometry=Hexahedral(options)))
    print(json.dumps({
        "machine": f"{platform.machine()}, {os.cpu_count()} CPUs, JAX {jax.__version__} "
                   f"on {jax.default_backend()}",
        "ball": "elastic sphere E 100 MPa, nu 0.3, R 36 mm, 800 kg/m^3",
        "speed_m_s": SPEED_M_S, "friction": FRICTION, "divisions": args.divisions,
        "elements": one[0].elements,
        "reference_200_incidences_s": reference_s,
        "single_run_first_s": single_first_s, "single_run_s": single_s,
        "single_run_steps": one[0].steps,
        "sweep_angles_deg": list(ANGLES_DEG), "sweep_first_s": sweep_first_s,
        "sweep_s": sweep_s, "sweep_steps": [r.steps for r in runs],
        "sweep_over_single": sweep_s / single_s,
        "sweep_per_run_over_single": sweep_s / len(ANGLES_DEG) / single_s}, indent=1))


if __name__ == "__main__":
    main()
