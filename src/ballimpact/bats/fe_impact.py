"""The FE ball on the bat: the axisymmetric FE ball (`fe`) hits a rigid plane carried by the
bat's modes at the impact point (`fe.backing.PlaneBacking`), both stepped in the same explicit
run; docs/equipment.md, "The FE ball on the bat".

The contact is the ball's surface on the bat's surface at x_i, taken as a plane normal to the
ball's path that moves with the bat's deflection there: the bat's curvature across the contact
(a barrel of radius R_b against the ball's R) and the bat's rotation during the contact are
left out (docs/equipment.md bounds both), and so is the contact's spread along the bat (the
force acts at x_i). The bat's modes are those of `bats.modes` (mass-normalised; Timoshenko
beam), damped by its loss factor and a grip's dashpots; modes with no motion at x_i or above
`fe.backing.MAX_FREQUENCY_HZ` are left out of the contact (they cannot take part).

Frames as `bats.impact`: the ground frame, the bat swung at `bat_speed_m_s` at x_i toward the
ball; e_A = (v_z' - V) / (v + V) with the ball's rebound velocity v_z' along the FE run's z
(away from the bat). After the separation the bat's free vibration is followed exactly (the
matrix exponential of its modal equations) for the bending stress and the hands' force and
velocity.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.linalg import expm

from ..fe.backing import MAX_FREQUENCY_HZ, PlaneBacking
from .beam import DEFAULT_ELEMENTS
from .impact import (DEFAULT_MODES, BatImpactResult, _swing, bat_model, checked_collision,
                     contact_rotation, hands_history, largest_bending_stress, modal_momentum,
                     rigid_efficiency)
from .modes import BatModes
from .properties import bat_properties

#: samples of the bat's free vibration after the separation per period of its highest mode
SAMPLES_PER_PERIOD = 16


def contact_modes(bm: BatModes, points_m) -> np.ndarray:
    """The indices of the modes that take part in a contact at any of `points_m` (m from the
    knob): moving there, and at most `fe.backing.MAX_FREQUENCY_HZ`."""
    w = np.abs(np.stack([bm.deflection(float(x))[:, 0] for x in np.atleast_1d(points_m)]))
    moving = (w > 1e-9 * w.max(axis=1, keepdims=True)).any(axis=0)
    return np.flatnonzero(moving & (bm.frequencies_hz <= MAX_FREQUENCY_HZ))


def bat_backing(bm: BatModes, x_i: float, bat_speed_m_s: float, pivot_m: float | None,
                keep: np.ndarray | None = None) -> tuple[PlaneBacking, np.ndarray]:
    """The bat at x_i as a `PlaneBacking` (z = -w: the plane moves down as the bat deflects
    along the ball's path) of the modes `keep` (default `contact_modes` at x_i), and those
    modes' indices."""
    w = bm.deflection(x_i)[:, 0]
    keep = contact_modes(bm, x_i) if keep is None else keep
    swing = _swing(bm, x_i, bat_speed_m_s, pivot_m)
    damping = bm.modal_damping()[np.ix_(keep, keep)]
    labels = [("rigid " if f < 1e-6 * max(bm.frequencies_hz.max(), 1.0) else "")
              + f"mode {k + 1} ({f:.0f} Hz)" for k, f in zip(keep, bm.frequencies_hz[keep])]
    backing = PlaneBacking(tuple(-w[keep]), tuple(np.maximum(bm.frequencies_hz[keep], 0.0)),
                           tuple(map(tuple, damping)), tuple(swing[keep]), tuple(labels),
                           name=f"bat {bm.bat.name} at {x_i:g} m")
    return backing, keep


def _free_vibration(bm: BatModes, q0: np.ndarray, qd0: np.ndarray, duration_s: float
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(times from 0 s, q, qd (count, times)) of the bat's free modal vibration: the exact
    step of q'' + C q' + Omega^2 q = 0."""
    n = bm.count
    top = max(bm.frequencies_hz.max(), 1.0)
    steps = max(2, int(np.ceil(duration_s * top * SAMPLES_PER_PERIOD)))
    steps = min(steps, 200_000)
    dt = duration_s / steps
    a = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.diag(bm.omega_rad_s ** 2), -bm.modal_damping()]])
    step = expm(a * dt)
    out = np.empty((2 * n, steps + 1))
    out[:, 0] = np.concatenate([q0, qd0])
    for i in range(steps):
        out[:, i + 1] = step @ out[:, i]
    return np.arange(steps + 1) * dt, out[:n], out[n:]


def fe_bat_impact(bat, ball, speed_m_s: float, impact_m: float, *, bat_speed_m_s: float = 0.0,
                  support: str = "free", pivot_m: float | None = None, grip=None,
                  modes: int = DEFAULT_MODES, elements: int = DEFAULT_ELEMENTS, options=None,
                  after_s: float | None = None, reference=None, allow=()) -> BatImpactResult:
    """The FE `ball` (a preset name, ball file, dict or `fe.BallModel`) at `speed_m_s` on `bat`
    (anything `load_bat` takes, or `BatModes`) at `impact_m` from the knob end, the bat swung at
    `bat_speed_m_s` there (module docstring). `options`: the FE run's `fe.SolverOptions`.
    `after_s`: the bat's vibration followed after the separation (default: 2 periods of its
    lowest flexural mode). Also runs the same ball on a fixed rigid plane at the relative speed
    (the rigid bat's e_A, and the cost of the ball alone), unless given that run as
    `reference` (an `fe.ImpactResult`): `ball["fe"]` holds both runs' figures and wall
    times."""
    return fe_bat_impacts(bat, ball, speed_m_s, [impact_m], bat_speed_m_s=bat_speed_m_s,
                          support=support, pivot_m=pivot_m, grip=grip, modes=modes,
                          elements=elements, options=options, after_s=after_s,
                          reference=reference, allow=allow)[0]


def fe_bat_impacts(bat, ball, speed_m_s: float, points_m, *, bat_speed_m_s: float = 0.0,
                   support: str = "free", pivot_m: float | None = None, grip=None,
                   modes: int = DEFAULT_MODES, elements: int = DEFAULT_ELEMENTS, options=None,
                   after_s: float | None = None, reference=None, progress: bool = False,
                   allow=()) -> list[BatImpactResult]:
    """`fe_bat_impact` at each of `points_m` (m from the knob end) as one batched FE run
    (`fe.simulate_batch`, one target per point: the bat's modes at that point, the modes of
    every point kept so that all share one compiled program), and one rigid-plane run (or
    `reference`). `progress`: the batched run's progress lines on stderr
    (`progress.RunProgress`)."""
    from .. import fe
    from ..fe.engine import check_speeds

    bm = bat_model(bat, support=support, pivot_m=pivot_m, grip=grip, modes=modes,
                   elements=elements)
    points = np.atleast_1d(np.asarray(points_m, dtype=float))
    collisions = [checked_collision(bm, speed_m_s, bat_speed_m_s, float(x), pivot_m)
                  for x in points]
    v, V, _, pivot_m = collisions[0]
    model = ball if isinstance(ball, fe.BallModel) else fe.load_ball(
        ball, impact_speed_m_s=v + V, allow=allow)
    geometry = fe.Axisymmetric(options or fe.SolverOptions())
    check_speeds([v + V], geometry, allow)  # the ball meets the bat at v + V
    keep = contact_modes(bm, points)
    backings = [bat_backing(bm, x_i, V, pivot_m, keep)[0] for _, _, x_i, _ in collisions]
    rigid = reference or fe.simulate(model, v + V, geometry=geometry, allow=allow)
    start = time.perf_counter()
    lines = None
    if progress:
        from ..progress import RunProgress

        cost = fe.estimate(model, [v] * len(backings), geometry=geometry, target=backings)
        lines = RunProgress(cost.end_time_s, geometry.options.chunk_steps)
    runs = fe.simulate_batch(model, v, geometry=geometry, target=backings, progress=lines,
                             allow=allow)
    bat_wall = (time.perf_counter() - start) / len(runs)
    return [_collision_result(bm, run, rigid, v, V, x_i, pivot_m, keep, after_s, bat_wall)
            for run, (_, _, x_i, _) in zip(runs, collisions)]


def _collision_result(bm: BatModes, run, rigid, v: float, V: float, x_i: float,
                      pivot_m: float | None, keep: np.ndarray, after_s: float | None,
                      bat_wall: float) -> BatImpactResult:
    """The collision's figures from the FE run of the ball on the bat's modes `keep` at x_i
    (`run`) and its run on the fixed plane (`rigid`); `bat_wall` the bat run's wall time (s,
    a batch's share)."""
    spec = bm.bat
    h, n = run.history, bm.count
    t = h["time_s"]
    q = np.zeros((n, t.size))
    qd = np.zeros((n, t.size))
    for j, k in enumerate(keep):
        q[k], qd[k] = h[f"backing_q_{j}"], h[f"backing_qd_{j}"]
    flex = bm.frequencies_hz[bm.rigid_count:]
    if after_s is None:
        after_s = 2.0 / flex[0] if flex.size else 3.0 * run.contact_time_s
    tf, qf, qdf = _free_vibration(bm, q[:, -1], qd[:, -1], after_s)
    times = np.concatenate([t, t[-1] + tf[1:]])
    q_all = np.concatenate([q, qf[:, 1:]], axis=1)
    qd_all = np.concatenate([qd, qdf[:, 1:]], axis=1)

    e_a = (run.cor * v - V) / (v + V)
    e_rigid, m_eff = rigid_efficiency(bm, x_i, pivot_m, run.mass_kg, rigid.cor)
    separation = min(int(np.searchsorted(t, run.contact_time_s)), t.size - 1)
    q_s, qd_s = q[:, separation], qd[:, separation]
    modal_energy = 0.5 * (qd_s ** 2 + bm.omega_rad_s ** 2 * q_s ** 2)
    en = run.energies_j
    ball_lost = (en["internal_work_j"] - en["strain_energy_j"] + en["contact_dissipation_j"])
    e0 = en["initial_kinetic_energy_j"] + en["backing_initial_energy_j"]
    balance = (abs(run.energy_balance_error) * en["initial_kinetic_energy_j"]
               + abs(en["backing_balance_error"]) * en["initial_kinetic_energy_j"]) / e0
    momentum = None
    p_modes = modal_momentum(bm)
    if p_modes is not None:
        # along the ball's path (w): the ball's -m v_z, the bat's modal momentum
        p = -run.mass_kg * h["centre_velocity_z_m_s"] + p_modes @ qd
        momentum = float(np.max(np.abs(p - (run.mass_kg * v + p_modes @ qd_all[:, 0])))
                         / (run.mass_kg * (v + V)))
    stress = largest_bending_stress(bm, q_all, times)
    hands, hands_v = hands_history(bm, q_all, qd_all)
    props = bat_properties(spec)
    ball_info = {"name": run.ball_name, "mass_kg": run.mass_kg, "model": "fe",
                 "fe": {"relative_speed_m_s": v + V, "rigid_plane_cor": rigid.cor,
                        "rigid_plane_contact_time_s": rigid.contact_time_s,
                        "rigid_plane_peak_force_n": rigid.peak_force_n,
                        "rigid_plane_wall_time_s": rigid.wall_time_s,
                        "bat_run_wall_time_s": bat_wall,
                        "bat_run_steps": run.steps, "elements": run.elements,
                        "modes_in_contact": len(keep),
                        "ball_energy_balance_error": run.energy_balance_error,
                        "bat_energy_balance_error": en["backing_balance_error"]}}
    contact = h["contact_force_n"] > 0
    first, last = np.flatnonzero(contact)[[0, -1]] if contact.any() else (0, t.size - 1)
    window = slice(max(first - 1, 0), min(last + 2, t.size))
    return BatImpactResult(
        spec.name, ball_info, v, V, x_i, bm.support, pivot_m, float(e_a),
        float(e_a * v + (1.0 + e_a) * V), e_rigid, m_eff, props.mass_kg,
        props.centre_of_mass_m,
        {"knob": props.moi_knob_kg_m2, "centre_of_mass": props.moi_cm_kg_m2},
        bm.frequencies_hz.copy(), float(ball_lost), modal_energy[bm.rigid_count:],
        float(modal_energy[:bm.rigid_count].sum()), float(en["backing_damping_j"]), e0,
        float(balance), momentum, *stress,
        float(run.contact_time_s), float(run.peak_force_n), 1, spec.length_m,
        t[window], h["contact_force_n"][window], times, hands, hands_v, rigid,
        contact_rotation(bm, x_i, q, contact))
