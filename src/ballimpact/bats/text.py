"""The text of a ball on a bat, as `ballimpact bat` prints it: the lines (without their line
ends), so that a Python user gets the command's text."""

from __future__ import annotations

from typing import Any


def ball_on_bat_lines(out: dict[str, Any]) -> list[str]:
    """`study.ball_on_bat`'s result: the bat, the ball (its FE runs or its law), then the one
    impact point's figures, or a row per point of a sweep and the sweet spot."""
    lines = [_bat_line(out), _ball_line(out["ball"])]
    speeds = f"ball {out['speed_m_s']:g} m/s, bat {out['bat_speed_m_s']:g} m/s"
    if "points" not in out:  # one point
        return lines + _point_lines(out, speeds)
    lines += [speeds, "  x (m)  from end (m)  e_A     BBS (m/s)  vibration (J)  stress (MPa)"]
    for p in out["points"]:
        lines.append(f"  {p['impact_m']:.3f}  {p['from_barrel_end_m']:.3f}         "
                     f"{p['collision_efficiency']:.4f}  {p['batted_ball_speed_m_s']:9.2f}  "
                     f"{p['bat_vibration_energy_total_j']:13.3f}  "
                     f"{p['max_bending_stress_pa'] / 1e6:12.1f}")
    s = out["sweet_spot"]
    return lines + [
        f"sweet spot: largest e_A {s['max_collision_efficiency']:.4f} at "
        f"{s['max_efficiency_m']:.3f} m ({s['max_efficiency_from_barrel_end_m']:.3f} m from "
        f"the barrel end); least vibration at {s['least_vibration_m']:.3f} m "
        f"({s['least_vibration_from_barrel_end_m']:.3f} m from the barrel end)"]


def _bat_line(out: dict[str, Any]) -> str:
    moi = out["bat_moment_of_inertia_kg_m2"]
    freqs = ", ".join(f"{f:.0f}" for f in out["mode_frequencies_hz"])
    return (f"{out['bat']}: {out['bat_mass_kg']:.3f} kg, centre of mass "
            f"{out['bat_centre_of_mass_m']:.3f} m, I knob {moi['knob']:.3f} / CM "
            f"{moi['centre_of_mass']:.4f} kg m^2, {out['support']}; modes {freqs} Hz")


def _ball_line(ball: dict[str, Any]) -> str:
    if ball.get("model") == "fe":
        f = ball["fe"]
        return (f"ball {ball['name']} (FE, {f['elements']} elements): {ball['mass_kg']:.4g} kg; "
                f"on a rigid plane at {f['relative_speed_m_s']:g} m/s COR "
                f"{f['rigid_plane_cor']:.4f}, contact "
                f"{f['rigid_plane_contact_time_s'] * 1e3:.3f} ms "
                f"({f['rigid_plane_wall_time_s']:.2f} s); on the bat {f['bat_run_steps']} "
                f"steps, {f['modes_in_contact']} modes ({f['bat_run_wall_time_s']:.2f} s)")
    cal = ball.get("calibration") or {}
    return (f"ball {ball['name']} (law): {ball['mass_kg']:.4g} kg, k "
            f"{ball['stiffness_n_m1_5']:.4g} N/m^1.5, c {ball['damping_s_m']:.4g} s/m"
            + (f" (FE at {cal['speed_m_s']:g} m/s: COR {cal['fe_cor']:.4f}, contact "
               f"{cal['fe_contact_time_s'] * 1e3:.3f} ms, peak force "
               f"{cal['fe_peak_force_n']:.4g} N; law: COR {cal['law_cor']:.4f}, peak force "
               f"{cal['law_peak_force_n']:.4g} N)" if cal else ""))


def _point_lines(out: dict[str, Any], speeds: str) -> list[str]:
    hands = ""
    if "hands_force" in out:
        hands = (f"; largest force on the hands "
                 f"{max(map(abs, out['hands_force']['force_n'])):.4g} N, speed "
                 f"{max(map(abs, out['hands_force']['velocity_m_s'])):.3g} m/s")
    return [f"at {out['impact_m']:g} m from the knob ({out['from_barrel_end_m']:.3f} m from the "
            f"barrel end), {speeds}: e_A {out['collision_efficiency']:.4f} (rigid bat "
            f"{out['rigid_collision_efficiency']:.4f}), batted-ball speed "
            f"{out['batted_ball_speed_m_s']:.2f} m/s",
            f"  contact {out['contact_duration_s'] * 1e3:.3f} ms, peak force "
            f"{out['peak_force_n']:.4g} N; ball lost {out['ball_energy_lost_j']:.4g} J, bat "
            f"vibration {out['bat_vibration_energy_total_j']:.4g} J, rigid "
            f"{out['bat_rigid_energy_j']:.4g} J (energy balance error "
            f"{out['energy_balance_error']:.1e})",
            f"  largest bending stress {out['max_bending_stress_pa'] / 1e6:.4g} MPa at "
            f"{out['max_bending_stress_x_m']:.3f} m from the knob; the surface under the "
            f"ball tilts up to {out['max_contact_rotation_rad']:.3g} rad in contact{hands}"]


__all__ = ["ball_on_bat_lines"]
