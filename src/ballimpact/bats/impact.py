"""The ball-bat collision: a ball (one degree of freedom, a contact law `ball_law`) on the bat's
modal model (`modes`); docs/equipment.md, "Ball on bat".

x along the bat from the knob end; displacements positive in the direction the ball travels
in. The ball (mass m, at u, inbound speed v) and the bat (w(x, t) = sum_n w_n(x) q_n(t), modes
mass-normalised) interact through the law's force F(d, d') at the impact point x_i, d = u -
w(x_i): m u'' = -F, q'' + C q' + Omega^2 q = w(x_i) F (C: the loss factor's modal damping and
the grip's dashpots). `scipy.integrate.solve_ivp` (DOP853, rtol 1e-10) integrates the contact
until the separation (an event, d = 0 going down), then the free flight and bat vibration for
`after_s` with an event for a second contact (which starts another contact phase).

The swing: the bat starts in rigid motion with the impact point at `bat_speed_m_s` V toward the
ball: a rotation about `pivot_m` if given (the pin of `support="pivot"`, or a point the free
bat turns about), else a translation; the field is projected onto the kept modes. Everything is
integrated in the ground frame. e_A (the collision efficiency) is the ball's rebound speed over
its inbound speed, both relative to the bat's initial motion at x_i: e_A = -(u'_end + V) / (v +
V); the batted-ball speed e_A v + (1 + e_A) V (Nathan 2003, Am. J. Phys. 71:134; Cross 2011,
"Physics of Baseball & Softball") is the ball's own final ground speed.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from ..checks import check_range, shown
from ..errors import InputError, SimulationError
from .ball_law import HuntCrossleyBall
from .beam import DEFAULT_ELEMENTS, shape_functions
from .modes import BatModes, modes as bat_modes
from .properties import bat_properties
from .section import outer_radius_m

#: bat modes kept by default (rigid ones included): the 12th of the free wood bat is at 6.2 kHz
DEFAULT_MODES = 12
RTOL = 1e-10
#: contacts followed at most (a ball caught again by the vibrating bat)
MAX_CONTACTS = 5
#: samples of the histories per contact, and of the stress per period of the highest mode
CONTACT_SAMPLES = 401
STRESS_SAMPLES_PER_PERIOD = 16


@dataclass(frozen=True)
class BatImpactResult:
    """One ball-bat collision (SI; module docstring). Energies at the (last) separation, in the
    ground frame; `bat_vibration_energy_j` per flexural mode. `contact_time_s`/`contact_force_n`
    sample the contacts; `hands_force_n` (the force on the hands, at `history_time_s`) with a
    grip, else None. `energy_balance_error`: largest |E(t) - E0| / E0 (E the ball's kinetic,
    the law's stored and dissipated, the bat's kinetic, strain and damped energy);
    `momentum_balance_error`: largest |P(t) - P0| / (m (v + V)), free bat without grip only."""

    bat: str
    ball: dict
    speed_m_s: float
    bat_speed_m_s: float
    impact_m: float
    support: str
    pivot_m: float | None
    collision_efficiency: float
    batted_ball_speed_m_s: float
    rigid_collision_efficiency: float
    effective_mass_kg: float
    bat_mass_kg: float
    bat_centre_of_mass_m: float
    bat_moment_of_inertia_kg_m2: dict
    mode_frequencies_hz: np.ndarray
    ball_energy_lost_j: float
    bat_vibration_energy_j: np.ndarray
    bat_rigid_energy_j: float
    bat_damping_loss_j: float
    initial_energy_j: float
    energy_balance_error: float
    momentum_balance_error: float | None
    max_bending_stress_pa: float
    max_bending_stress_x_m: float
    max_bending_stress_time_s: float
    contact_duration_s: float
    peak_force_n: float
    contacts: int
    bat_length_m: float
    contact_time_s: np.ndarray = field(repr=False)
    contact_force_n: np.ndarray = field(repr=False)
    history_time_s: np.ndarray = field(repr=False)
    hands_force_n: np.ndarray | None = field(repr=False)
    #: the bat's velocity at the hands (m/s, their mean, along the ball's path), with a grip
    hands_velocity_m_s: np.ndarray | None = field(default=None, repr=False)
    #: the FE ball's run on the rigid plane at the relative speed (`fe_impact`; None: the law)
    fe_reference: Any = field(default=None, repr=False)
    #: the largest tilt of the bat's surface at x_i while in contact (rad, |dw/dx|): what the
    #: contact plane, kept normal to the ball's path, leaves out (`contact_rotation`)
    max_contact_rotation_rad: float = float("nan")

    @property
    def from_barrel_end_m(self) -> float:
        return float(self.bat_length_m - self.impact_m)

    def summary(self, histories: bool = True) -> dict[str, Any]:
        """JSON-able figures (and, with `histories`, the contact force and hands' force)."""
        out = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in _HISTORIES:
                continue
            out[f.name] = (value.tolist() if isinstance(value, np.ndarray)
                           else dict(value) if isinstance(value, dict) else value)
            if f.name == "impact_m":
                out["from_barrel_end_m"] = self.from_barrel_end_m
            elif f.name == "bat_vibration_energy_j":
                out["bat_vibration_energy_total_j"] = float(value.sum())
        if histories:
            out["contact_force"] = {"time_s": self.contact_time_s.tolist(),
                                    "force_n": self.contact_force_n.tolist()}
            if self.hands_force_n is not None:
                out["hands_force"] = {"time_s": self.history_time_s.tolist(),
                                      "force_n": self.hands_force_n.tolist(),
                                      "velocity_m_s": self.hands_velocity_m_s.tolist()}
        return out


_HISTORIES = ("contact_time_s", "contact_force_n", "history_time_s", "hands_force_n",
              "hands_velocity_m_s", "fe_reference")


def bat_model(bat, *, support: str = "free", pivot_m: float | None = None, grip=None,
              modes: int = DEFAULT_MODES, elements: int = DEFAULT_ELEMENTS) -> BatModes:
    """The bat's modes for collisions: `modes.modes` (the pin only with support "pivot"; a
    free bat's `pivot_m` is only its swing's centre). A `BatModes` is returned as it is."""
    if isinstance(bat, BatModes):
        return bat
    return bat_modes(bat, support=support, pivot_m=pivot_m if support == "pivot" else None,
                     grip=grip, count=modes, elements=elements)


def _curvatures(bm: BatModes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each mode's bending curvature d(theta)/dx at both ends of every element (count, 2 E),
    those points (m), and the distance c (m) of the outermost fibre there."""
    nodes, beam = bm.nodes_m, bm.beam
    h = np.diff(nodes)
    xi = np.array([0.0, 1.0])
    dt = shape_functions(xi[None, :], h[:, None], beam.element_phi[:, None])[3]  # (E, 2, 4)
    idx = 2 * np.arange(h.size)[:, None] + np.arange(4)[None, :]
    u = bm.vectors[idx]  # (E, 4, count)
    kappa = np.einsum("eqj,ejn->neq", dt, u).reshape(bm.count, -1)
    x = np.stack([nodes[:-1], nodes[1:]], axis=1).ravel()
    bat = bm.bat
    c = outer_radius_m(bat, x)
    if bat.blade is not None:
        xb, tb = np.array(bat.blade.profile_thickness).T
        # an element's end at the shoulder belongs to the blade if the element is on it
        on = np.stack([nodes[:-1], nodes[:-1]], axis=1).ravel() >= bat.blade.start_m - 1e-12
        c = np.where(on, np.interp(x, xb, tb) / 2.0, c)
    return kappa, x, c


def modal_momentum(bm: BatModes) -> np.ndarray | None:
    """The bat's linear momentum per unit modal velocity (count,): P = p . q' along the ball's
    path; None where it is not conserved (a pinned bat, or one held by springs or dashpots)."""
    if bm.support != "free" or (bm.grip is not None and (bm.grip.stiffness_n_m != 0
                                                         or bm.grip.damping_n_s_m != 0)):
        return None
    return (np.where(np.arange(bm.beam.dofs) % 2 == 0, 1.0, 0.0) @ bm.beam.mass
            @ bm.vectors)


def largest_bending_stress(bm: BatModes, q: np.ndarray, times_s: np.ndarray
                           ) -> tuple[float, float, float]:
    """(largest |sigma| Pa, where m, when s) of the bending stress E c kappa over the modal
    coordinates q (count, times) at `times_s`."""
    kappa, xs, c = _curvatures(bm)
    sigma = bm.bat.material.youngs_modulus_pa * c[:, None] * (kappa.T @ q)
    j, i = np.unravel_index(np.argmax(np.abs(sigma)), sigma.shape)
    return float(abs(sigma[j, i])), float(xs[j]), float(times_s[i])


def contact_rotation(bm: BatModes, x_i: float, q: np.ndarray, in_contact: np.ndarray) -> float:
    """The largest |dw/dx| (rad) of the bat at x_i over the samples `in_contact` (a mask) of the
    modal coordinates q (count, times): the tilt of its surface under the ball, rigid rotation
    and bending together."""
    if not np.any(in_contact):
        return 0.0
    return float(np.max(np.abs(bm.slope(x_i)[:, 0] @ q[:, in_contact])))


def hands_history(bm: BatModes, q: np.ndarray, qd: np.ndarray):
    """(force on the hands N, the bat's mean velocity at them m/s) over time from the modal
    coordinates q, qd (count, times): the grip's springs and dashpots; (None, None) without a
    grip."""
    if bm.grip is None:
        return None, None
    g = bm.grip
    wh = bm.deflection(list(g.positions_m))  # (count, hands)
    velocity = wh.T @ qd
    force = g.stiffness_n_m * (wh.T @ q).sum(0) + g.damping_n_s_m * velocity.sum(0)
    return force, velocity.mean(0)


def _swing(bm: BatModes, x_i: float, speed: float, pivot_m: float | None) -> np.ndarray:
    """Initial modal velocities of the bat's rigid swing (impact point at -speed)."""
    if speed == 0.0:
        return np.zeros(bm.count)
    nodes = bm.nodes_m
    field_ = np.zeros(bm.beam.dofs)
    if pivot_m is None:
        field_[0::2] = -speed
    else:
        if abs(x_i - pivot_m) < 1e-3 * bm.bat.length_m:
            raise InputError(f"pivot_m = {pivot_m:g}: at the impact point, which then has no "
                             "swing speed")
        rate = -speed / (x_i - pivot_m)
        field_[0::2], field_[1::2] = rate * (nodes - pivot_m), rate
    return bm.vectors.T @ bm.beam.mass @ field_


def checked_collision(bm: BatModes, speed_m_s: float, bat_speed_m_s: float, impact_m: float,
                      pivot_m: float | None) -> tuple[float, float, float, float | None]:
    """(ball speed m/s, bat speed m/s, impact point m, pivot m or None) checked: speeds > 0 and
    >= 0, the point and the pivot on the bat, the point not at a pin."""
    spec = bm.bat
    pivot_m = bm.pivot_m if bm.support == "pivot" else pivot_m
    v = check_range("speed_m_s", speed_m_s, 0.0, low_open=True, unit="m/s")
    V = check_range("bat_speed_m_s", bat_speed_m_s, 0.0, unit="m/s")
    x_i = check_range("impact_m", impact_m, 0.0, spec.length_m, unit="m",
                      note="from the knob end, on the bat")
    if pivot_m is not None:
        pivot_m = check_range("pivot_m", pivot_m, 0.0, spec.length_m, unit="m")
    if bm.support == "pivot" and abs(x_i - bm.pivot_m) < 1e-3 * spec.length_m:
        raise InputError(f"impact_m = {x_i:g}: at the pivot, where the bat cannot move")
    return v, V, x_i, pivot_m


def rigid_efficiency(bm: BatModes, x_i: float, pivot_m: float | None, ball_mass_kg: float,
                     cor: float) -> tuple[float, float]:
    """The rigid bat's collision efficiency (e - r) / (1 + r), r = m / M_eff, and M_eff (kg):
    1/M_eff = 1/M + b^2 / I_cm for a free bat, b^2 / I_pivot pinned (b from the centre of mass
    or the pivot to x_i); `cor` the ball's COR on a rigid plane at the relative speed."""
    props = bat_properties(bm.bat)
    b = x_i - (props.centre_of_mass_m if bm.support == "free" else pivot_m)
    inv = (1.0 / props.mass_kg + b ** 2 / props.moi_cm_kg_m2 if bm.support == "free"
           else b ** 2 / props.moi_about_kg_m2(pivot_m))
    r = ball_mass_kg * inv
    return float((cor - r) / (1.0 + r)), float(1.0 / inv)


def bat_impact(bat, law: HuntCrossleyBall, speed_m_s: float, impact_m: float, *,
               bat_speed_m_s: float = 0.0, support: str = "free", pivot_m: float | None = None,
               grip=None, modes: int = DEFAULT_MODES, elements: int = DEFAULT_ELEMENTS,
               after_s: float | None = None) -> BatImpactResult:
    """A ball (`law`, a `HuntCrossleyBall`: `ball_law`) at `speed_m_s` on `bat` (anything
    `load_bat` takes, or its `BatModes` from `bat_model`) at `impact_m` from the knob end, the
    bat swung at `bat_speed_m_s` there (module docstring). `support`, `pivot_m`, `grip`,
    `modes`, `elements`: `bat_model`. `after_s`: flight after the separation followed for a
    second contact and the bending stress (default: 2 periods of the lowest flexural mode, at
    least 3 contact times)."""
    if not isinstance(law, HuntCrossleyBall):
        raise InputError(f"law = {shown(law)}: expected a HuntCrossleyBall (bats.ball_law)")
    bm = bat_model(bat, support=support, pivot_m=pivot_m, grip=grip, modes=modes,
                   elements=elements)
    spec = bm.bat
    v, V, x_i, pivot_m = checked_collision(bm, speed_m_s, bat_speed_m_s, impact_m, pivot_m)
    m, k, lam = law.mass_kg, law.stiffness, law.lambda_s_m
    n = bm.count
    wx = bm.deflection(x_i)[:, 0]
    omega2 = bm.omega_rad_s ** 2
    cmat = bm.modal_damping()

    def rhs(_, y):
        q, qd = y[2:2 + n], y[2 + n:2 + 2 * n]
        d, dd = y[0] - wx @ q, y[1] - wx @ qd
        elastic = k * d ** 1.5 if d > 0 else 0.0
        f = max(elastic * (1.0 + lam * dd), 0.0)
        out = np.empty_like(y)
        out[0], out[1] = y[1], -f / m
        out[2:2 + n] = qd
        out[2 + n:2 + 2 * n] = wx * f - cmat @ qd - omega2 * q
        out[-2] = (f - elastic) * dd
        out[-1] = qd @ cmat @ qd
        return out

    def gap(_, y):
        return y[0] - wx @ y[2:2 + n]
    apart = lambda t, y: gap(t, y)  # noqa: E731 - the same function, another direction
    gap.terminal, gap.direction = True, -1
    apart.terminal, apart.direction = True, 1

    y = np.zeros(2 * n + 4)
    y[1] = v
    y[2 + n:2 + 2 * n] = _swing(bm, x_i, V, pivot_m)
    flex = bm.frequencies_hz[2 if bm.support == "free" else 1:]
    f_high = max(bm.frequencies_hz.max(), 1.0)
    t_est = 3.2 * (m / k) ** 0.4 * (v + V) ** -0.2  # Hertz contact time, for the step limits
    if after_s is None:
        after_s = max(2.0 / flex[0] if flex.size else 0.0, 3.0 * t_est)
    after_s = check_range("after_s", after_s, 0.0, low_open=True, unit="s")
    t0, pieces, contacts = 0.0, [], []
    for _ in range(MAX_CONTACTS):
        sol = solve_ivp(rhs, (t0, t0 + 20.0 * t_est), y, method="DOP853", events=gap,
                        dense_output=True, rtol=RTOL, atol=1e-13, max_step=t_est / 20.0)
        if sol.status != 1:
            raise SimulationError(f"ball on {spec.name} at x = {x_i:g} m: no separation within "
                                  f"{20 * t_est:.3g} s")
        t1, y = float(sol.t_events[0][0]), sol.y_events[0][0]
        pieces.append(sol.sol)
        contacts.append((t0, t1))
        y_sep = y.copy()
        sol = solve_ivp(rhs, (t1, t1 + after_s), y, method="DOP853", events=apart,
                        dense_output=True, rtol=RTOL, atol=1e-13,
                        max_step=1.0 / (4.0 * f_high))
        pieces.append(sol.sol)
        if sol.status != 1:
            t_end = t1 + after_s
            break
        t0, y = float(sol.t_events[0][0]), sol.y_events[0][0]
    else:
        raise SimulationError(f"ball on {spec.name} at x = {x_i:g} m: more than {MAX_CONTACTS} "
                              "contacts")
    bounds = [p.t_min for p in pieces[1:]] + [np.inf]

    def state(t):
        t = np.atleast_1d(t)
        out = np.empty((y.size, t.size))
        which = np.searchsorted(bounds, t, side="left")
        for i in np.unique(which):
            out[:, which == i] = pieces[i](t[which == i])
        return out

    # histories: contacts at CONTACT_SAMPLES each, the whole run for the stress and hands
    tc = np.concatenate([np.linspace(a, b, CONTACT_SAMPLES) for a, b in contacts])
    sc = state(tc)
    fc = law.force(sc[0] - wx @ sc[2:2 + n], sc[1] - wx @ sc[2 + n:2 + 2 * n])
    steps = int(np.ceil(t_end * f_high * STRESS_SAMPLES_PER_PERIOD)) + 1
    th = np.unique(np.concatenate([np.linspace(0.0, t_end, min(steps, 200001)), tc]))
    sh = state(th)

    def energy(s):
        q, qd = s[2:2 + n], s[2 + n:2 + 2 * n]
        return (0.5 * m * s[1] ** 2 + law.stored_energy_j(s[0] - wx @ q) + s[-2]
                + 0.5 * np.sum(qd ** 2 + omega2[:, None] * q ** 2, axis=0) + s[-1])
    e_hist = energy(sh)
    e0 = float(e_hist[0])
    props = bat_properties(spec)
    momentum = None
    p_modes = modal_momentum(bm)
    if p_modes is not None:
        p_hist = m * sh[1] + p_modes @ sh[2 + n:2 + 2 * n]
        momentum = float(np.max(np.abs(p_hist - p_hist[0])) / (m * (v + V)))
    stress = largest_bending_stress(bm, sh[2:2 + n], th)
    hands, hands_v = hands_history(bm, sh[2:2 + n], sh[2 + n:2 + 2 * n])
    q_s, qd_s = y_sep[2:2 + n], y_sep[2 + n:2 + 2 * n]
    modal_energy = 0.5 * (qd_s ** 2 + omega2 * q_s ** 2)
    rigid = 2 if bm.support == "free" else 1  # on a grip's springs too: the rigid modes on them
    end = state(t_end)[:, 0]
    e_a = -(end[1] + V) / (v + V)
    e_rigid, m_eff = rigid_efficiency(bm, x_i, pivot_m, m, law.rigid_plane(v + V).cor)
    return BatImpactResult(
        spec.name, law.summary(), v, V, x_i, bm.support, pivot_m, float(e_a),
        float(e_a * v + (1.0 + e_a) * V), e_rigid, m_eff,
        props.mass_kg, props.centre_of_mass_m,
        {"knob": props.moi_knob_kg_m2, "centre_of_mass": props.moi_cm_kg_m2},
        bm.frequencies_hz.copy(), float(end[-2]), modal_energy[rigid:],
        float(modal_energy[:rigid].sum()), float(y_sep[-1]), e0,
        float(np.max(np.abs(e_hist - e0)) / e0), momentum, *stress,
        float(sum(b_ - a for a, b_ in contacts)),
        float(fc.max()), len(contacts), spec.length_m, tc, fc, th, hands,
        hands_velocity_m_s=hands_v, max_contact_rotation_rad=contact_rotation(
            bm, x_i, sh[2:2 + n], np.any([(th >= a) & (th <= b_) for a, b_ in contacts], axis=0)))
