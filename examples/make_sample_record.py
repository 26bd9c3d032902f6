"""Make the built-in sample impact test, `src/ballimpact/data/sample_impact.csv` (+ `.json`).

The record is SYNTHETIC: a Hunt-Crossley ball, F = k y^1.5 (1 + lambda y'), with cricket-ball mass
and stiffness, dropped on a rigid load cell at 20.8 m/s (a speed of the thesis' tests), then dressed
as a measurement: a load-cell offset, the cell's ringing at its resonance (a decaying 14 kHz sine
excited at contact) and white noise, sampled at 200 kHz. The exact rebound speed is written to the
side file as the "measured" one, rounded to 0.01 m/s as a light gate would give it.

Run from the repository root: `python examples/make_sample_record.py`.
"""

from pathlib import Path

import numpy as np

from ballimpact.lumped import hunt_crossley_lambda
from ballimpact.records.pulses import hunt_crossley_pulse

MASS_KG = 0.16
IMPACT_SPEED_M_S = 20.8
STIFFNESS_N_M15 = 2.06e7  # k in F = k y^1.5: contact time about 1 ms, peak about 12 kN
TARGET_COR = 0.55
RATE_HZ = 200e3
OFFSET_N = 35.0
RINGING_HZ, RINGING_DECAY_S, RINGING_FRACTION = 14e3, 2e-4, 0.03
NOISE_FRACTION = 0.01
SEED = 20081


def main() -> None:
    lam = hunt_crossley_lambda(TARGET_COR, IMPACT_SPEED_M_S)
    pulse, contact, rebound = hunt_crossley_pulse(TARGET_COR, IMPACT_SPEED_M_S, MASS_KG,
                                                  STIFFNESS_N_M15)
    time = np.arange(-1e-3, contact + 1e-3, 1 / RATE_HZ)
    clean = pulse(time)
    peak = clean.max()
    rng = np.random.default_rng(SEED)
    after = np.clip(time, 0, None)
    ringing = (RINGING_FRACTION * peak * np.sin(2 * np.pi * RINGING_HZ * after)
               * np.exp(-after / RINGING_DECAY_S) * (time >= 0))
    measured = clean + ringing + OFFSET_N + NOISE_FRACTION * peak * rng.standard_normal(time.size)

    out = Path(__file__).resolve().parents[1] / "src" / "ballimpact" / "data"
    header = (
        "# SYNTHETIC impact test made by examples/make_sample_record.py - not a measurement.\n"
        f"# Hunt-Crossley ball F = k y^1.5 (1 + lambda dy/dt), k = {STIFFNESS_N_M15:.4g} N/m^1.5, "
        f"lambda = {lam:.5g} s/m, m = {MASS_KG} kg, v_in = {IMPACT_SPEED_M_S} m/s\n"
        f"# exact contact time {contact:.6g} s, peak force {peak:.6g} N, rebound "
        f"{rebound:.6g} m/s (COR {rebound / IMPACT_SPEED_M_S:.5f})\n"
        f"# plus offset {OFFSET_N} N, {RINGING_HZ:.0f} Hz load-cell ringing "
        f"({RINGING_FRACTION:.0%} of peak, decay {RINGING_DECAY_S} s), white noise "
        f"{NOISE_FRACTION:.0%} of peak RMS (seed {SEED}); sampled at {RATE_HZ:.0f} Hz\n"
        "time_s,force_n\n"
    )
    rows = "".join(f"{t:.8e},{f:.6g}\n" for t, f in zip(time, measured))
    (out / "sample_impact.csv").write_text(header + rows)
    side = (
        '{\n  "comment": "SYNTHETIC test, see sample_impact.csv",\n'
        f'  "mass_kg": {MASS_KG},\n  "impact_speed_m_s": {IMPACT_SPEED_M_S},\n'
        f'  "rebound_speed_m_s": {round(rebound, 2)}\n}}\n'
    )
    (out / "sample_impact.json").write_text(side)
    print(f"contact {contact:.6g} s, peak {peak:.6g} N, rebound {rebound:.5g} m/s -> {out}")


if __name__ == "__main__":
    main()
