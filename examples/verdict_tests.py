"""Write three SYNTHETIC impact tests that show `identify`'s verdict (issue 39) into a folder:

- `universal_25.csv`: the cricket-universal preset (a ball of the universal model's own family)
  at 25 m/s, its FE pulse at 100 kHz with 1% noise: in range, the FE check passes (exit 0);
- `half_sine.csv`: a symmetric 1 ms half-sine with a measured COR of 0.35 (its impulse agrees):
  no ball gives a symmetric pulse with that much loss, the FE check misses (exit 3);
- `stiff.csv`: the sample's Hunt-Crossley ball ten times stiffer (contact 0.44 ms, peak 28 kN),
  outside the built-in model's range: the FE check misses (exit 3).

Run: python examples/verdict_tests.py DIR, then `ballimpact identify DIR/<name>.csv`.
"""

import json
import sys
from pathlib import Path

import numpy as np

from ballimpact.records import pulses
from ballimpact.fe import load_ball, simulate

RATE_HZ = 100e3


def write(folder: Path, name: str, time_s, force_n, side: dict) -> Path:
    path = folder / f"{name}.csv"
    np.savetxt(path, np.column_stack([time_s, force_n]), delimiter=",", header="time_s,force_n",
               comments="")
    path.with_suffix(".json").write_text(json.dumps(side))
    return path


def main(folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(1)
    run = simulate(load_ball("cricket-universal", impact_speed_m_s=25.0), 25.0)
    fe = run.record()
    pulse = lambda t: np.interp(t, fe.time_s - fe.time_s[0], fe.force_n, right=0.0)  # noqa: E731
    record = pulses.load_cell_record(pulse, fe.time_s[-1] - fe.time_s[0], RATE_HZ, noise=0.01,
                                     rng=rng)
    write(folder, "universal_25", record.time_s, record.force_n,
          {"mass_kg": fe.mass_kg, "impact_speed_m_s": 25.0,
           "rebound_speed_m_s": round(run.cor * 25.0, 2)})
    # impulse m v (1 + e) = (2/pi) F0 T with e = 0.35: the measured speeds agree with the pulse
    peak = 0.16 * 20.0 * 1.35 * np.pi / 2 / 1e-3
    half = lambda t: np.where((t > 0) & (t < 1e-3),  # noqa: E731
                              peak * np.sin(np.pi * np.clip(t, 0, 1e-3) / 1e-3), 0.0)
    record = pulses.load_cell_record(half, 1e-3, RATE_HZ, noise=0.01, rng=rng)
    write(folder, "half_sine", record.time_s, record.force_n,
          {"mass_kg": 0.16, "impact_speed_m_s": 20.0, "rebound_speed_m_s": 7.0})
    stiff, duration, rebound = pulses.hunt_crossley_pulse(0.55, 20.8, 0.16, 2.06e8)
    record = pulses.load_cell_record(stiff, duration, 2 * RATE_HZ, noise=0.01, rng=rng)
    write(folder, "stiff", record.time_s, record.force_n,
          {"mass_kg": 0.16, "impact_speed_m_s": 20.8, "rebound_speed_m_s": round(rebound, 2)})
    print(f"wrote universal_25.csv, half_sine.csv and stiff.csv (+ .json) to {folder}")


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "verdict-tests"))
