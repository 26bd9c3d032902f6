"""The text of an angle sweep, as `ballimpact simulate --solver 3d --angle-deg A1,A2,...`
prints it: the lines (without their line ends), so that a Python user gets the command's
text."""

from __future__ import annotations

from typing import Any

from ..fe.text import written_lines


def angle_sweep_lines(out: dict[str, Any]) -> list[str]:
    """An angle sweep (`sweep.simulate_angles`): a row per angle, the batch's mesh and cost, the
    reference's note and the files written."""
    lines = [f"{out['ball']} in 3D at {out['speed_m_s']:g} m/s, friction {out['friction']:g}, "
             f"spin {out['spin_rad_s']:g} rad/s on {out['target']}: {len(out['runs'])} angles "
             "in one batched run",
             f"{'angle deg':>10}{'Psi':>8}{'normal COR':>11}{'tang COR':>9}{'cp COR':>8}"
             f"{'rebound deg':>12}{'spin rad/s':>11}{'norm spin':>10}"]
    for r in out["runs"]:
        lines.append(f"{r['angle_deg']:>10.4g}{r['psi']:>8.3f}{r['normal_cor']:>11.4f}"
                     f"{r['tangential_cor']:>9.4f}{r['contact_point_tangential_cor']:>8.4f}"
                     f"{r['rebound_angle_deg']:>12.2f}{r['rebound_spin_rad_s']:>11.1f}"
                     f"{r['normalised_spin']:>10.3f}")
    steps = [r["steps"] for r in out["runs"]]
    return lines + [
        f"  {out['wall_time_s']:.2f} s wall for the batch, {out['elements']} hexahedra "
        f"({'half' if out['half_model'] else 'full'} model, pole grading "
        f"{out['pole_grading']:.3g}, penalty scale {out['penalty_scale']:g}), "
        f"{min(steps)}-{max(steps)} steps",
        f"  {out['reference_note']}", *written_lines(out)]


__all__ = ["angle_sweep_lines"]
