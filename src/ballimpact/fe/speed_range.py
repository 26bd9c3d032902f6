"""The impact speeds at which the FE geometries were checked, and the `speed-range` check that
refuses a run outside them (an override: `allow={"speed-range"}`, `--allow speed-range`)."""

from __future__ import annotations

from collections.abc import Collection

from ..checks import flag

#: Impact speeds (m/s) at which the FE solvers were checked (docs/fe.md, docs/oblique.md): both
#: presets run at the default options, ending at separation with an energy balance error below
#: 3e-4. Axisymmetric: 0.001 to 80 m/s; at 100 m/s both stop unstable (energy error above 5%).
#: 3D: 0.001 to 45 m/s; the three-layer ball stops unstable from 50 m/s. Below about 1 m/s the
#: speed is not the limit but the mesh: a contact patch narrower than two pole elements is not
#: resolved, and the solvers warn (`fe.engine.contact_resolution_note`).
FE_SPEED_RANGE_M_S = (0.001, 80.0)
FE_3D_SPEED_RANGE_M_S = (0.001, 45.0)
#: what was checked, per solver (for the message)
_SPEED_CHECKED = {
    "axisymmetric": "both presets run there at the default options; at 100 m/s both stop as "
                    "unstable; docs/fe.md",
    "3d": "both presets run there at the default options; from 50 m/s cricket-3layer stops as "
          "unstable; docs/oblique.md",
}


def check_fe_speed(speed_m_s: float, allow: Collection[str] = (), *, solver: str = "axisymmetric"
                   ) -> float:
    """`speed_m_s` (m/s) if inside the speeds `solver` was checked at ("axisymmetric":
    `FE_SPEED_RANGE_M_S`, "3d": `FE_3D_SPEED_RANGE_M_S`); else the `speed-range` check fails."""
    low, high = FE_3D_SPEED_RANGE_M_S if solver == "3d" else FE_SPEED_RANGE_M_S
    if not low <= speed_m_s <= high:
        flag("speed-range", f"impact speed {float(speed_m_s):g} m/s is outside {low:g}..{high:g} "
             f"m/s, the speeds at which the {solver} FE solver was checked "
             f"({_SPEED_CHECKED[solver]})", allow)
    return speed_m_s
