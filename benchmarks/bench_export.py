"""Cost of the exports on this machine, printed as JSON.

Writes the three-layer ball's complete impact deck in every format, axisymmetric (default mesh)
and 3D (16 divisions, whole ball), timing each write and its file size; the reference measured
in the same run is the meshing alone (`ball_geometry`). With --calculix (needs ccx) it also runs
the cross-code case (elastic Mooney-Rivlin ball, 10 m/s; CalculiX on the exported 8-division
half ball, 1 thread) against our axisymmetric solver (compiled).

    python benchmarks/bench_export.py [--calculix]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
from pathlib import Path

from ballimpact.export import ImpactSetup, ball_geometry, export_ball
from ballimpact.fe import load_ball, simulate

FORMATS = (("abaqus", ".inp"), ("calculix", ".inp"), ("lsdyna", ".k"), ("vtk", ".vtu"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calculix", action="store_true")
    args = parser.parse_args()
    ball = load_ball("cricket-3layer")
    setup = ImpactSetup(20.8)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for solver, mesh in (("axisymmetric", {}), ("3d", {"divisions": 16})):
            start = time.perf_counter()
            geom = ball_geometry(ball, solver, **mesh)
            meshing = time.perf_counter() - start
            for fmt, suffix in FORMATS:
                if fmt == "calculix" and solver == "axisymmetric":
                    continue  # ball-only there (CalculiX loses axisymmetric initial velocities)
                path = Path(folder) / f"{solver}-{fmt}{suffix}"
                start = time.perf_counter()
                export_ball(ball, path, fmt, solver=solver, setup=setup, approximate=True, **mesh)
                wall = time.perf_counter() - start
                rows.append({"solver": solver, "format": fmt, "elements": len(geom.elements),
                             "write_s": wall, "meshing_s": meshing,
                             "write_over_meshing": wall / meshing,
                             "file_bytes": path.stat().st_size})
    out = {"machine": {"platform": platform.platform(), "cpus": os.cpu_count(),
                       "processor": platform.processor()}, "exports": rows}
    if args.calculix:
        from ballimpact.export.calculix import CROSS_RUN_BALL, run_impact

        mr = load_ball(CROSS_RUN_BALL)
        simulate(mr, 10.0)  # compile
        ours = simulate(mr, 10.0)
        with tempfile.TemporaryDirectory() as folder:
            theirs = run_impact(mr, 10.0, Path(folder), step_time_s=1.15 * ours.contact_time_s)
        out["calculix_10_m_s"] = {
            "ours_wall_s": ours.wall_time_s, "calculix_wall_s": theirs.wall_time_s,
            "calculix_over_ours": theirs.wall_time_s / ours.wall_time_s,
            "ours_elements": ours.summary().get("elements"),
            "calculix_increments": len(theirs.time_s) - 1}
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
