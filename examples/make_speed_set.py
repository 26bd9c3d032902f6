"""Make the built-in multi-speed test set, `src/ballimpact/data/speed_set/` (the demo of
`ballimpact report --builtin speeds`).

The tests are SYNTHETIC: a three-layer ball with the geometry of the thesis' `cricket-3layer`
(core, midsole and cover radii of table 5-1), its densities scaled to a regulation 0.160 kg, its
C10 and the hyperfoam's mu scaled by 0.45, C01 = 0, and one short Prony term (g = 0.88, tau =
20 us) in every layer, so that, like the thesis' tests (section 7.2), its COR falls from 0.62 at
5.5 m/s to 0.49 at 25 m/s; its peak force at 20.8 m/s is 9.2 kN. It is simulated by our explicit FE
engine on a mesh twice as fine as the default at the thesis' speeds 5.5, 10, 20.8 and 25 m/s and
dressed as a load-cell record: 100 kHz, 0.5 ms of baseline, white noise of 1% of the peak force
(seed 2008). The rebound speed in each side file is the run's exact one rounded to 0.01 m/s, as a
light gate gives it. The generating ball is written too (`synthetic-3layer.json`): in the demo
report it plays the thesis' calibrated "detailed FE model", run on the default mesh.

Run from the repository root (about a minute): `python examples/make_speed_set.py`.
"""

import copy
import json
from pathlib import Path

import numpy as np

from ballimpact.calibrate.synthetic import synthetic_record
from ballimpact.fe import SolverOptions
from ballimpact.balls.ball import CRICKET_3LAYER_SPEC, load_ball

SPEEDS_M_S = (5.5, 10.0, 20.8, 25.0)
MASS_KG = 0.160
MODULUS_SCALE = 0.45
PRONY = {"g": 0.88, "k": 0.0, "tau_s": 2e-5}
NOISE_OF_PEAK = 0.01
SEED = 2008
ELEMENT_SIZE_M = 0.75e-3  # half the default


def generating_ball() -> dict:
    spec = copy.deepcopy(CRICKET_3LAYER_SPEC)
    spec["name"] = "synthetic-3layer"
    density_scale = MASS_KG / load_ball(spec).mass_kg
    for layer in spec["layers"]:
        layer["density_kg_m3"] *= density_scale
        material = layer["material"]
        if "c10_pa" in material:  # C01 = 0: the thesis' negative C01 goes Drucker-unstable
            material["c10_pa"] *= MODULUS_SCALE  # at the stretches this softer ball reaches
            material["c01_pa"] = 0.0
        for term in material.get("terms", []):
            term["mu_pa"] *= MODULUS_SCALE
        material["prony"] = [dict(PRONY)]
    return spec


def main() -> None:
    out = Path(__file__).resolve().parents[1] / "src" / "ballimpact" / "data" / "speed_set"
    out.mkdir(exist_ok=True)
    spec = generating_ball()
    (out / "synthetic-3layer.json").write_text(json.dumps(spec, indent=2) + "\n")
    rng = np.random.default_rng(SEED)
    options = SolverOptions(element_size_m=ELEMENT_SIZE_M)
    for speed in SPEEDS_M_S:
        record, fe = synthetic_record(spec, speed, options, NOISE_OF_PEAK, rng)
        stem = f"synthetic_{speed:04.1f}_m_s"
        header = (
            "# SYNTHETIC impact test made by examples/make_speed_set.py - not a measurement.\n"
            f"# FE run of the ball in synthetic-3layer.json ({spec['name']}, {MASS_KG} kg) at "
            f"{speed} m/s, element size {ELEMENT_SIZE_M} m: peak force {fe.peak_force_n:.6g} N, "
            "contact time "
            f"{fe.contact_time_s:.6g} s, COR {fe.cor:.5f}\n"
            f"# sampled at 100 kHz, white noise {NOISE_OF_PEAK:.0%} of the peak (seed {SEED})\n"
            "time_s,force_n\n")
        rows = "".join(f"{t:.8e},{f:.6g}\n" for t, f in zip(record.time_s, record.force_n))
        (out / f"{stem}.csv").write_text(header + rows)
        side = {"comment": f"SYNTHETIC test, see {stem}.csv", "mass_kg": MASS_KG,
                "impact_speed_m_s": speed, "rebound_speed_m_s": round(fe.cor * speed, 2)}
        (out / f"{stem}.json").write_text(json.dumps(side, indent=2) + "\n")
        print(f"{speed:5.1f} m/s: peak {fe.peak_force_n:8.1f} N, contact "
              f"{fe.contact_time_s * 1e3:.4f} ms, COR {fe.cor:.4f}, {fe.wall_time_s:.1f} s")


if __name__ == "__main__":
    main()
