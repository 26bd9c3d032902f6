"""The text of the FE engine's results, as `ballimpact simulate`, `compare` and `compress` print
it (one axisymmetric or 3D run, a speed sweep, balls compared, a compression curve): each
function returns the lines (without their line ends), so that a Python user gets the command's
text. The results are those of `fe.runs`, `fe.sweep` and `fe.compression`."""

from __future__ import annotations

from typing import Any


def impact_lines(result, out: dict[str, Any]) -> list[str]:
    """One axisymmetric run (`fe.runs.simulate_impact`: its `ImpactResult` and JSON object): the
    figures of the impact, the energies, the run's cost, and a target's layers and backing."""
    e = result.energies_j
    on = "" if result.target == "rigid plane" else f" on {result.target}"
    lines = [f"{result.ball_name} at {result.impact_speed_m_s:g} m/s{on} ({out['moduli']} "
             f"moduli): peak force {result.peak_force_n:.5g} N at "
             f"{result.time_of_peak_s * 1e3:.4g} ms, contact time "
             f"{result.contact_time_s * 1e3:.4g} ms, COR {result.cor:.4f}",
             f"  energy balance error {result.energy_balance_error:.2e}; viscous "
             f"{e['viscous_dissipation_j']:.4g} J, bulk viscous "
             f"{e['bulk_viscous_dissipation_j']:.4g} J of {e['initial_kinetic_energy_j']:.4g} J",
             f"  {result.elements} elements, {result.steps} steps of "
             f"{result.stable_time_increment_s:.3g} s, {result.wall_time_s:.2f} s wall"]
    for layer in out.get("target_layers", []):
        lines.append(f"  target layer {layer['name']}: took {layer['work_j']:.4g} J, largest "
                     f"compression {layer['max_compression']:.1%} of its thickness")
    b = out.get("backing")
    if b is not None:
        lines.append(f"  backing: {b['backing_speed_m_s']:.3f} m/s after, peak acceleration "
                     f"{b['backing_peak_acceleration_g']:.1f} g, HIC15 {b['hic15']:.1f}, Gadd "
                     f"{b['gadd_severity_index']:.1f}, peak transmitted force "
                     f"{b['peak_transmitted_force_n']:.4g} N")
    return lines


def impact_3d_lines(result, out: dict[str, Any]) -> list[str]:
    """One 3D run (`fe.runs.simulate_impact` on `fe.Hexahedral`): the condition, the rebound
    (CORs, angle, spin, speed), the force, the energies and the mesh and cost."""
    condition, e = result.condition, result.energies_j
    spin = (f"spin {condition.spin_rad_s:g} rad/s" if condition.symmetric else
            f"spin (x, y, z) {', '.join(f'{w:g}' for w in condition.spin_vector_rad_s)} rad/s")
    lines = [f"{result.ball_name} in 3D at {condition.speed_m_s:g} m/s, "
             f"{condition.angle_deg:g} deg, {spin}, friction {condition.friction:g} on "
             f"{result.target}:",
             f"  normal COR {result.normal_cor:.4f}, tangential COR "
             f"{result.tangential_cor:.4f}, rebound angle {result.rebound_angle_deg:.2f} deg, "
             f"rebound spin {result.rebound_spin_rad_s:.1f} rad/s, rebound speed "
             f"{result.rebound_speed_m_s:.3f} m/s"]
    if not condition.symmetric:
        lines.append("  rebound spin (x, y, z) "
                     f"{', '.join(f'{w:.1f}' for w in out['rebound_spin_vector_rad_s'])} rad/s, "
                     "velocity (x, y, z) "
                     f"{', '.join(f'{v:.3f}' for v in out['rebound_velocity_m_s'])} m/s")
    return lines + [
        f"  peak normal force {result.peak_force_n:.5g} N, contact time "
        f"{result.contact_time_s * 1e3:.4g} ms",
        f"  energy balance error {result.energy_balance_error:.2e}; viscous "
        f"{e['viscous_dissipation_j']:.4g} J, friction {e['frictional_dissipation_j']:.4g} J,"
        f" bulk viscous {e['bulk_viscous_dissipation_j']:.4g} J of "
        f"{e['initial_kinetic_energy_j']:.4g} J",
        f"  {result.elements} hexahedra ({'half' if result.half_model else 'full'} model, "
        f"pole grading {result.pole_grading:.3g}, {result.pole_spacing_m * 1e3:.3g} mm at the "
        f"pole, penalty scale {result.penalty_scale:g}),",
        f"  {result.steps} steps of {result.stable_time_increment_s:.3g} s, "
        f"{result.wall_time_s:.2f} s wall"]


def speed_sweep_lines(out: dict[str, Any]) -> list[str]:
    """A speed sweep (`fe.runs.simulate_speeds`): a row per speed, and the files written."""
    lines = [f"{out['ball']}: {len(out['sweep'])} speeds in one batched run ({out['moduli']} "
             f"moduli, {out['elements']} elements, {out['wall_time_s']:.2f} s wall)",
             f"{'speed m/s':>10}{'COR':>8}{'peak kN':>9}{'contact ms':>11}{'deflect mm':>11}"
             f"{'rebound m/s':>12}{'stiff MN/m':>11}{'energy err':>11}"]
    for r in out["sweep"]:
        lines.append(f"{r['impact_speed_m_s']:>10.4g}{r['cor']:>8.4f}"
                     f"{r['peak_force_n'] / 1e3:>9.3f}{r['contact_time_s'] * 1e3:>11.4f}"
                     f"{r['max_deflection_m'] * 1e3:>11.3f}{r['rebound_speed_m_s']:>12.3f}"
                     f"{r['dynamic_stiffness_n_m'] / 1e6:>11.4g}"
                     f"{r['energy_balance_error']:>11.1e}")
    return lines + written_lines(out)


def written_lines(out: dict[str, Any]) -> list[str]:
    """The files of a sweep (or a comparison) that were written: its table and plot."""
    return [f"{key} written to {out[key]}" for key in ("table", "plot")
            if out.get(key) is not None]


def comparison_lines(out: dict[str, Any]) -> list[str]:
    """Balls compared (`fe.runs.compare_balls(...).to_dict()`): per speed and ball the figures
    and the differences from the first ball, the files written and the time taken."""
    reference = out["reference_ball"]
    width = max(12, *(len(b) + 2 for b in out["balls"]))
    lines = [f"compare: {len(out['balls'])} balls at {len(out['speeds_m_s'])} speed(s), FE on a "
             f"rigid plane; differences from {reference} (COR absolute, others %)",
             f"{'speed m/s':>10}  {'ball':<{width}}{'COR':>8}{'peak kN':>9}{'contact ms':>11}"
             f"{'stiff MN/m':>11}{'dCOR':>9}{'dpeak %':>9}{'dcontact %':>11}{'dstiff %':>10}"]
    for r in out["comparison"]:
        diffs = (f"{'':>9}{'':>9}{'':>11}{'':>10}" if r["ball"] == reference else
                 f"{r['cor_difference']:>+9.4f}{r['peak_force_difference_percent']:>+9.2f}"
                 f"{r['contact_time_difference_percent']:>+11.2f}"
                 f"{r['dynamic_stiffness_difference_percent']:>+10.2f}")
        lines.append(f"{r['impact_speed_m_s']:>10.4g}  {r['ball']:<{width}}{r['cor']:>8.4f}"
                     f"{r['peak_force_n'] / 1e3:>9.3f}{r['contact_time_s'] * 1e3:>11.4f}"
                     f"{r['dynamic_stiffness_n_m'] / 1e6:>11.4g}{diffs}")
    return lines + written_lines(out) + [f"{out['wall_time_s']:.2f} s wall"]


def compression_lines(out: dict[str, Any]) -> list[str]:
    """A compression curve (`fe.compression.compress_ball`): the peak force, the stiffnesses,
    the stretches reached, and the mesh and cost."""
    curve = (f"at {out['rate_m_s']:g} m/s" if out["rate_m_s"] is not None
             else "long-term (relaxed)")
    low, high = out["principal_stretch_range"]
    return [f"{out['ball']} compressed by {out['deflection_m'][-1] * 1e3:.4g} mm between two "
            f"platens, {curve}: peak force {out['peak_force_n']:.5g} N",
            f"  stiffness at the end {out['end_stiffness_n_m'] / 1e3:.5g} N/mm, secant "
            f"{out['secant_stiffness_n_m'] / 1e3:.5g} N/mm; principal stretches "
            f"{low:.3f}-{high:.3f}",
            f"  {out['elements']} elements ({out['geometry']}), {out['increments']} "
            f"increments, {out['newton_iterations']} Newton iterations, "
            f"{out['wall_time_s']:.2f} s wall ({out['compile_time_s']:.2f} s compiling)"]


__all__ = ["comparison_lines", "compression_lines", "impact_3d_lines", "impact_lines",
           "speed_sweep_lines", "written_lines"]
