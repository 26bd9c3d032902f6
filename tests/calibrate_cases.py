"""A half-sine test record for the calibrate command's tests: cheap to process, so that a case
runs the FE solver only where it means to."""

import json

import numpy as np

MASS_KG, SPEED_M_S, COR = 0.16, 20.0, 0.6


def half_sine_record(folder, contact_s):
    """`folder/ball.csv` (time_s, force_n): a half-sine pulse of `contact_s` from 0.2 ms on,
    whose impulse is m (v_in + v_out) of a 0.16 kg ball at 20 m/s with COR 0.6, sampled at
    100 kHz over 2 ms; with a JSON side file giving the mass and the impact speed."""
    t = np.arange(0.0, 2e-3, 1e-5)
    peak = MASS_KG * SPEED_M_S * (1 + COR) * np.pi / (2 * contact_s)
    inside = (t > 2e-4) & (t < 2e-4 + contact_s)
    force = np.where(inside, peak * np.sin(np.pi * (t - 2e-4) / contact_s), 0.0)
    csv = folder / "ball.csv"
    np.savetxt(csv, np.column_stack([t, force]), delimiter=",", header="time_s,force_n",
               comments="")
    (folder / "ball.json").write_text(json.dumps({"mass_kg": MASS_KG,
                                                  "impact_speed_m_s": SPEED_M_S}))
    return csv
