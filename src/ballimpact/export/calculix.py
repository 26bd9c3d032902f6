"""Run a CalculiX deck written by `write_deck` and read its contact force (the cross-code check
of DESIGN.md "Verification").

The force is the summed reaction of the fixed plane's nodes, printed every increment to the
`.dat` file (doubled for a half model). COR from the impulse, e = J / (m v_n) - 1, with the mesh's
own mass m (coarse meshes lose a few per cent of the sphere's volume to the chords; the impulse
must be divided by the mass that was hit).
"""

from __future__ import annotations

import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError, SimulationError
from ..fe.solver import contact_end_time

_TOTAL = re.compile(r"total force \(fx,fy,fz\) for set (\S+) and time\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)")


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


def read_forces(dat_text: str, force_unit_n: float = 1.0, time_unit_s: float = 1.0,
                normal_axis: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """(time s, normal force N) of the plane's totals in a CalculiX `.dat` file."""
    rows = np.array([[float(m.group(2)), float(m.group(3 + normal_axis))]
                     for m in _TOTAL.finditer(dat_text)])
    if rows.size == 0:
        raise SimulationError("no 'total force' rows in the CalculiX .dat file")
    time = np.concatenate([[0.0], rows[:, 0] * time_unit_s])
    force = np.concatenate([[0.0], rows[:, 1] * force_unit_n])
    return time, force


def run_deck(deck: Path, mass_kg: float, normal_speed_m_s: float, half: bool,
             force_unit_n: float = 1.0, time_unit_s: float = 1.0, threads: int = 1,
             timeout_s: float = 3600.0) -> CalculixResult:
    """Run `ccx` on `deck` (in its folder) and summarise its contact force history."""
    import os
    import time as clock

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
    time, force = read_forces(dat.read_text(), force_unit_n, time_unit_s)
    # the plane's reaction points up (+); it is the force on the plane's nodes holding them
    force = -force if force.sum() < 0 else force
    if half:
        force = 2.0 * force
    impulse = float(np.trapezoid(force, time))
    return CalculixResult(time, force, float(force.max()), contact_end_time(time, force),
                          impulse / (mass_kg * normal_speed_m_s) - 1.0, wall)
