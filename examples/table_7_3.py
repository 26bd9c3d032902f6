"""What the thesis' table 7-3 parameters give in the universal FE ball, at the four speeds of the
table, under both moduli conventions (the thesis does not say which one its constants are).

Run: python examples/table_7_3.py   (prints a Markdown table and one JSON line per run)
"""

import json
import warnings

from ballimpact.fe import SolverOptions, load_ball, simulate

SPEEDS_M_S = (5.5, 10.0, 20.8, 25.0)


def main() -> None:
    options = SolverOptions()
    rows = []
    for moduli in ("long_term", "instantaneous"):
        for speed in SPEEDS_M_S:
            ball = load_ball("cricket-universal", impact_speed_m_s=speed).with_moduli(moduli)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                result = simulate(ball, speed, options)
            rows.append((moduli, speed, result, [str(w.message) for w in caught]))
            print(json.dumps({"moduli": moduli, **result.summary()}))
    print("\n| moduli | speed (m/s) | peak force (kN) | contact time (ms) | COR | energy error |")
    print("|---|---|---|---|---|---|")
    for moduli, speed, r, notes in rows:
        flag = " (Drucker warning)" if notes else ""
        print(f"| {moduli} | {speed:g} | {r.peak_force_n / 1e3:.2f} | {r.contact_time_s * 1e3:.3f} "
              f"| {r.cor:.3f}{flag} | {r.energy_balance_error:.1e} |")


if __name__ == "__main__":
    main()
