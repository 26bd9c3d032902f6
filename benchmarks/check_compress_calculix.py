"""Check with an independent code: is an elastic sphere between two platens stiffer than Hertz?

CalculiX (`ccx`, CAX4, linear elastic, small strain) on the meshes `compress` refines at both
poles: Hertz's pressure p0 sqrt(1 - r^2/a^2) of the deflection D on both poles (a = sqrt(R D/2)),
the sphere's centre held. Hertz's half-space would move each pole by a^2 / R = D / 2 towards
the centre; the sphere's finite size makes the approach smaller, so at equal approach the force is
larger by (D / 2 / approach)^1.5. Prints one JSON object. The pressure is constant on each
surface segment (taken at its middle), which makes the figures jagged by a few per cent: this
checks the sign and size of `benchmarks/bench_compress_hertz.py`'s excess over Hertz, not a
tolerance (docs/materials.md).

Run: python benchmarks/check_compress_calculix.py   (needs ccx: apt-get install calculix-ccx)
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from ballimpact.closedform import hertz_stiffness
from ballimpact.fe.axi.mesh import layered_sphere_mesh

R_M, MU_PA, ELEMENTS_ACROSS = 0.036, 2.0e6, 25


def pole_approach(nu: float, fraction: float, folder: Path) -> dict:
    e = 2 * MU_PA * (1 + nu)
    delta = fraction * R_M  # each pole's approach, D / 2
    a = math.sqrt(R_M * delta)
    force = hertz_stiffness(e, nu, R_M) * delta**1.5
    p0 = 3 * force / (2 * math.pi * a * a)
    mesh = layered_sphere_mesh((R_M,), 1.5e-3, a / ELEMENTS_ACROSS,
                               min(max(math.degrees(2.5 * a / R_M), 5.0), 45.0), both_poles=True)
    x, elements, surface = mesh.nodes_m, mesh.elements, list(mesh.surface_nodes)
    face = {frozenset((c[f], c[(f + 1) % 4])): (k, f + 1)
            for k, c in enumerate(elements) for f in range(4)}
    axis = [i for i in range(len(x)) if abs(x[i, 0]) < 1e-12 * R_M]
    centre = min(axis, key=lambda i: abs(x[i, 1]))
    lines = ["*NODE"] + [f"{i + 1},{r:.12e},{z:.12e}" for i, (r, z) in enumerate(x)]
    lines += ["*ELEMENT,TYPE=CAX4,ELSET=ALL"]
    lines += [f"{k + 1}," + ",".join(str(c + 1) for c in conn) for k, conn in enumerate(elements)]
    lines += [f"*NSET,NSET=NALL,GENERATE\n1,{len(x)},1", "*MATERIAL,NAME=M", "*ELASTIC",
              f"{e:.6e},{nu}", "*SOLID SECTION,ELSET=ALL,MATERIAL=M", "*BOUNDARY"]
    lines += [f"{i + 1},1,1" for i in axis] + [f"{centre + 1},2,2", "*STEP", "*STATIC", "*DLOAD"]
    for s0, s1 in zip(surface[:-1], surface[1:]):
        r = 0.5 * (x[s0, 0] + x[s1, 0])
        if r < a:
            k, f = face[frozenset((s0, s1))]
            lines.append(f"{k + 1},P{f},{p0 * math.sqrt(1 - (r / a) ** 2):.6e}")
    lines += ["*NODE PRINT,NSET=NALL", "U", "*END STEP"]
    (folder / "sphere.inp").write_text("\n".join(lines) + "\n")
    subprocess.run(["ccx", "-i", "sphere"], cwd=folder, capture_output=True, check=True)
    uz = {}
    for row in (folder / "sphere.dat").read_text().splitlines():
        parts = row.split()
        if len(parts) >= 3 and parts[0].isdigit():
            uz[int(parts[0]) - 1] = float(parts[2])
    approach = uz[surface[0]] - uz[centre]
    return {"nu": nu, "deflection_over_diameter": fraction, "elements": int(len(elements)),
            "approach_over_hertz": approach / delta,
            "force_over_hertz_at_equal_approach": (delta / approach) ** 1.5}


def main() -> None:
    if shutil.which("ccx") is None:
        sys.exit("CalculiX (ccx) is not installed: apt-get install calculix-ccx")
    with tempfile.TemporaryDirectory() as folder:
        cases = [pole_approach(nu, fraction, Path(folder)) for nu in (0.3, 0.49)
                 for fraction in (0.0025, 0.005, 0.01, 0.02)]
    print(json.dumps({"elements_across_contact_radius": ELEMENTS_ACROSS, "cases": cases},
                     indent=1))


if __name__ == "__main__":
    main()
