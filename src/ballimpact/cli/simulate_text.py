"""The text `ballimpact simulate` prints: one axisymmetric or 3D run, a speed sweep, an angle
sweep (from the JSON objects of `fe.runs` and `oblique.sweep`)."""

from __future__ import annotations

from typing import Any


def print_one(result, out: dict[str, Any]) -> None:
    """One axisymmetric run's text."""
    e = result.energies_j
    on = "" if result.target == "rigid plane" else f" on {result.target}"
    print(f"{result.ball_name} at {result.impact_speed_m_s:g} m/s{on} ({out['moduli']} moduli): "
          f"peak force {result.peak_force_n:.5g} N at {result.time_of_peak_s * 1e3:.4g} ms, "
          f"contact time {result.contact_time_s * 1e3:.4g} ms, COR {result.cor:.4f}")
    print(f"  energy balance error {result.energy_balance_error:.2e}; viscous "
          f"{e['viscous_dissipation_j']:.4g} J, bulk viscous "
          f"{e['bulk_viscous_dissipation_j']:.4g} J of {e['initial_kinetic_energy_j']:.4g} J")
    print(f"  {result.elements} elements, {result.steps} steps of "
          f"{result.stable_time_increment_s:.3g} s, {result.wall_time_s:.2f} s wall")
    for layer in out.get("target_layers", []):
        print(f"  target layer {layer['name']}: took {layer['work_j']:.4g} J, largest "
              f"compression {layer['max_compression']:.1%} of its thickness")
    b = out.get("backing")
    if b is not None:
        print(f"  backing: {b['backing_speed_m_s']:.3f} m/s after, peak acceleration "
              f"{b['backing_peak_acceleration_g']:.1f} g, HIC15 {b['hic15']:.1f}, Gadd "
              f"{b['gadd_severity_index']:.1f}, peak transmitted force "
              f"{b['peak_transmitted_force_n']:.4g} N")


def print_3d(result, out: dict[str, Any]) -> None:
    """One 3D run's text."""
    condition, e = result.condition, result.energies_j
    spin = (f"spin {condition.spin_rad_s:g} rad/s" if condition.symmetric else
            f"spin (x, y, z) {', '.join(f'{w:g}' for w in condition.spin_vector_rad_s)} rad/s")
    print(f"{result.ball_name} in 3D at {condition.speed_m_s:g} m/s, "
          f"{condition.angle_deg:g} deg, {spin}, friction {condition.friction:g} on "
          f"{result.target}:")
    print(f"  normal COR {result.normal_cor:.4f}, tangential COR {result.tangential_cor:.4f}, "
          f"rebound angle {result.rebound_angle_deg:.2f} deg, rebound spin "
          f"{result.rebound_spin_rad_s:.1f} rad/s, rebound speed "
          f"{result.rebound_speed_m_s:.3f} m/s")
    if not condition.symmetric:
        print("  rebound spin (x, y, z) "
              f"{', '.join(f'{w:.1f}' for w in out['rebound_spin_vector_rad_s'])} rad/s, "
              "velocity (x, y, z) "
              f"{', '.join(f'{v:.3f}' for v in out['rebound_velocity_m_s'])} m/s")
    print(f"  peak normal force {result.peak_force_n:.5g} N, contact time "
          f"{result.contact_time_s * 1e3:.4g} ms")
    print(f"  energy balance error {result.energy_balance_error:.2e}; viscous "
          f"{e['viscous_dissipation_j']:.4g} J, friction {e['frictional_dissipation_j']:.4g} J,"
          f" bulk viscous {e['bulk_viscous_dissipation_j']:.4g} J of "
          f"{e['initial_kinetic_energy_j']:.4g} J")
    print(f"  {result.elements} hexahedra ({'half' if result.half_model else 'full'} model, "
          f"pole grading {result.pole_grading:.3g}, {result.pole_spacing_m * 1e3:.3g} mm at the "
          f"pole, penalty scale {result.penalty_scale:g}),\n  "
          f"{result.steps} steps of {result.stable_time_increment_s:.3g} s, "
          f"{result.wall_time_s:.2f} s wall")


def print_speed_sweep(out: dict[str, Any]) -> None:
    """A speed sweep's text: a row per speed."""
    print(f"{out['ball']}: {len(out['sweep'])} speeds in one batched run ({out['moduli']} moduli, "
          f"{out['elements']} elements, {out['wall_time_s']:.2f} s wall)")
    print(f"{'speed m/s':>10}{'COR':>8}{'peak kN':>9}{'contact ms':>11}{'deflect mm':>11}"
          f"{'rebound m/s':>12}{'stiff MN/m':>11}{'energy err':>11}")
    for r in out["sweep"]:
        print(f"{r['impact_speed_m_s']:>10.4g}{r['cor']:>8.4f}{r['peak_force_n'] / 1e3:>9.3f}"
              f"{r['contact_time_s'] * 1e3:>11.4f}{r['max_deflection_m'] * 1e3:>11.3f}"
              f"{r['rebound_speed_m_s']:>12.3f}{r['dynamic_stiffness_n_m'] / 1e6:>11.4g}"
              f"{r['energy_balance_error']:>11.1e}")
    print_written(out)


def print_angle_sweep(out: dict[str, Any]) -> None:
    """An angle sweep's text: a row per angle, the batch's mesh and the reference's note."""
    print(f"{out['ball']} in 3D at {out['speed_m_s']:g} m/s, friction {out['friction']:g}, spin "
          f"{out['spin_rad_s']:g} rad/s on {out['target']}: {len(out['runs'])} angles in one "
          "batched run")
    print(f"{'angle deg':>10}{'Psi':>8}{'normal COR':>11}{'tang COR':>9}{'cp COR':>8}"
          f"{'rebound deg':>12}{'spin rad/s':>11}{'norm spin':>10}")
    for r in out["runs"]:
        print(f"{r['angle_deg']:>10.4g}{r['psi']:>8.3f}{r['normal_cor']:>11.4f}"
              f"{r['tangential_cor']:>9.4f}{r['contact_point_tangential_cor']:>8.4f}"
              f"{r['rebound_angle_deg']:>12.2f}{r['rebound_spin_rad_s']:>11.1f}"
              f"{r['normalised_spin']:>10.3f}")
    steps = [r["steps"] for r in out["runs"]]
    print(f"  {out['wall_time_s']:.2f} s wall for the batch, {out['elements']} hexahedra "
          f"({'half' if out['half_model'] else 'full'} model, pole grading "
          f"{out['pole_grading']:.3g}, penalty scale {out['penalty_scale']:g}), "
          f"{min(steps)}-{max(steps)} steps")
    print(f"  {out['reference_note']}")
    print_written(out)


def print_written(out: dict[str, Any]) -> None:
    """The files of a sweep (or `compare`) that were written: its table and plot."""
    for key in ("table", "plot"):
        if out.get(key) is not None:
            print(f"{key} written to {out[key]}")
