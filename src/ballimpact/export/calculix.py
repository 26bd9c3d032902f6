"""Run a CalculiX deck written by `write_deck` and read its contact force (the cross-code check
of docs/export.md "Checks").

The force is the summed reaction of the fixed plane's nodes, printed every increment to the
`.dat` file (doubled for a half model). COR from the impulse, e = J / (m v_n) - 1, with the mesh's
own mass m (coarse meshes lose a few per cent of the sphere's volume to the chords; the impulse
must be divided by the mass that was hit).
"""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import time as clock
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError, SimulationError
from ..fe.result import contact_end_time

#: the issue's cross-code ball: elastic Mooney-Rivlin, C10 4.72 MPa, C01 -0.45 MPa, D1 = 0,
#: 0.160 kg, 72 mm (the three-layer core's constants on the universal ball's size and mass)
CROSS_RUN_BALL = {
    "name": "elastic-mooney-rivlin",
    "layers": [{"name": "ball", "outer_radius_m": 0.036,
                "density_kg_m3": 0.160 / (4.0 / 3.0 * math.pi * 0.036 ** 3),
                "material": {"model": "mooney_rivlin", "c10_pa": 4.72e6, "c01_pa": -0.45e6,
                             "d1_per_pa": 0.0}}],
}

_TOTAL = re.compile(r"total force \(fx,fy,fz\) for set (\S+) and time"
                    r"\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)")


@dataclass(frozen=True)
class CalculixResult:
    time_s: np.ndarray
    force_n: np.ndarray        # normal contact force on the whole ball (N)
    peak_force_n: float
    contact_time_s: float
    cor: float                 # from the impulse and the mesh mass
    wall_time_s: float


def ccx_path() -> str | None:
    return shutil.which("ccx")


def read_forces(dat_text: str) -> tuple[np.ndarray, np.ndarray]:
    """(time, normal force) of the plane's totals in a CalculiX `.dat` file, from rest."""
    rows = np.array([[float(m.group(2)), float(m.group(5))] for m in _TOTAL.finditer(dat_text)])
    if rows.size == 0:
        raise SimulationError("no 'total force' rows in the CalculiX .dat file")
    return np.concatenate([[0.0], rows[:, 0]]), np.concatenate([[0.0], rows[:, 1]])


def run_deck(deck: Path, mass_kg: float, normal_speed_m_s: float, half: bool,
             threads: int = 1, timeout_s: float = 3600.0) -> CalculixResult:
    """Run `ccx` on `deck` (in its folder) and summarise its contact force history. Forces and
    times in the deck's units: N and s in both systems we write."""
    ccx = ccx_path()
    if ccx is None:
        raise InputError("ccx (CalculiX) is not installed: on Debian/Ubuntu `apt-get install "
                         "calculix-ccx`")
    deck = Path(deck)
    env = {**os.environ, "OMP_NUM_THREADS": str(threads)}
    start = clock.perf_counter()
    done = subprocess.run([ccx, "-i", deck.stem], cwd=deck.parent, env=env, capture_output=True,
                          text=True, timeout=timeout_s)
    wall = clock.perf_counter() - start
    dat = deck.with_suffix(".dat")
    if done.returncode != 0 or not dat.is_file() or "Job finished" not in done.stdout:
        tail = "\n".join(done.stdout.splitlines()[-5:])
        raise SimulationError(f"ccx failed on {deck.name} (exit {done.returncode}): {tail}")
    time, force = read_forces(dat.read_text())
    # the plane's reaction points up (+); it is the force on the plane's nodes holding them
    force = -force if force.sum() < 0 else force
    if half:
        force = 2.0 * force
    impulse = float(np.trapezoid(force, time))
    return CalculixResult(time, force, float(force.max()), contact_end_time(time, force),
                          impulse / (mass_kg * normal_speed_m_s) - 1.0, wall)


def run_impact(ball, speed_m_s: float, folder: Path, *, units: str = "mm-tonne-s",
               divisions: int = 8, step_time_s: float | None = None,
               threads: int = 1) -> CalculixResult:
    """Export `ball`'s normal impact at `speed_m_s` as a CalculiX deck (3D half model,
    `divisions`) into `folder`, run it and summarise it."""
    from . import ImpactSetup, export_ball

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    deck = folder / "ball.inp"
    written = export_ball(ball, deck, "calculix", solver="3d", units=units, divisions=divisions,
                          half=True, setup=ImpactSetup(speed_m_s, step_time_s=step_time_s))
    return run_deck(deck, written.mesh_mass_kg, speed_m_s, half=True, threads=threads)
