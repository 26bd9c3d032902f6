"""How the helmet liner's figures depend on the mesh, both geometries, printed as JSON (issue 41,
docs/equipment.md "Protective equipment").

The men's cricket ball at 19 m/s on the flat helmet of `examples/targets/helmet-on-headform.json`
(3 mm shell, 22 mm hyperfoam liner, 5 kg headform): the liner's largest compression (of its
thickness, on the axis) and work (J), the largest transmitted force (N), the headform's peak
acceleration (g), on
- the axisymmetric geometry at the default pole element (1.5 mm: 8 cells through the liner) and
  at half of it (12 cells, the most `fe.axi.target_mesh.cells_through` puts in a layer);
- the 3D geometry at 4, 6 and 8 divisions, with the slab's default layout (2 cells through the
  liner) and with its cells through the depth of 5.5, 2.75 and 1.5 mm
  (`Options3D.slab_depth_cell_m`: 4, 8 and 15 through the liner), and with `--graded` graded
  through the depth (`Options3D.slab_depth_growth` 1.15: cells of the ball's pole spacing at
  the surface, growing down; its in-plane cells are coarser).

    python benchmarks/bench_liner_mesh.py [--divisions 4 6 8] [--depth-cells-m ...] [--graded]

About 10 min on a 2-core CPU (the 3D runs); about 2 min on an H200.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
import warnings
from pathlib import Path

TARGET = Path(__file__).resolve().parents[1] / "examples" / "targets" / "helmet-on-headform.json"
SPEED_M_S = 19.0


def _figures(geometry) -> dict:
    from ballimpact import fe
    from ballimpact.errors import InputWarning
    from ballimpact.fe.hex.target import load_target
    from ballimpact.protect.headform import backing_figures

    ball = fe.load_ball("cricket-men", impact_speed_m_s=SPEED_M_S)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)
        run = fe.simulate(ball, SPEED_M_S, geometry=geometry, target=load_target(TARGET))
    e = run.energies_j
    return {"elements": run.elements, "wall_s": time.perf_counter() - start,
            "liner_max_compression": e["target_liner_max_compression"],
            "liner_work_j": e["target_liner_work_j"],
            "max_transmitted_force_n": e["target_max_transmitted_force_n"],
            "headform_peak_acceleration_g":
                backing_figures(run, histories=False)["backing_peak_acceleration_g"],
            "energy_balance_error": run.energy_balance_error}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--divisions", type=int, nargs="*", default=[4, 6, 8])
    parser.add_argument("--depth-cells-m", type=float, nargs="*", default=[5.5e-3, 2.75e-3,
                                                                           1.5e-3])
    parser.add_argument("--graded", action="store_true")
    args = parser.parse_args()
    import jax

    from ballimpact import fe

    rows = {"axisymmetric pole 1.5 mm": fe.Axisymmetric(),
            "axisymmetric pole 0.75 mm": fe.Axisymmetric(fe.SolverOptions(
                pole_element_size_m=0.75e-3))}
    for d in args.divisions:
        rows[f"3d {d} divisions, default slab"] = fe.Hexahedral(fe.Options3D(divisions=d))
        for cell in args.depth_cells_m:
            rows[f"3d {d} divisions, depth cells {cell * 1e3:g} mm"] = fe.Hexahedral(
                fe.Options3D(divisions=d, slab_depth_cell_m=cell))
        if args.graded:
            rows[f"3d {d} divisions, graded 1.15"] = fe.Hexahedral(fe.Options3D(
                divisions=d, slab_depth_growth=1.15))
    out = {"machine": {"platform": platform.platform(), "cpus": os.cpu_count(),
                       "jax_backend": jax.default_backend()},
           "ball": "cricket-men", "speed_m_s": SPEED_M_S, "target": TARGET.name, "runs": {}}
    for name, geometry in rows.items():
        out["runs"][name] = _figures(geometry)
        print(name, json.dumps(out["runs"][name]), flush=True, file=__import__("sys").stderr)
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
