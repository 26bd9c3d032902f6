"""The ball, for the ball-bat collision, as a nonlinear contact law (docs/equipment.md, "Ball on
bat"): Hunt-Crossley, F = k d^1.5 (1 + 1.5 c d'), d >= 0 the ball's compression, F >= 0 (no
adhesion), `HuntCrossleyBall(mass_kg, stiffness, damping_s_m)` with k = `stiffness`
(N/m^1.5) and c = `damping_s_m`; in the form of `lumped.hunt_crossley`, F = k d^1.5 (1 + lambda
d'), lambda = 1.5 c (so c -> (1 - e) / v for a COR e near 1).

`ball_law(ball, speed_m_s)` takes (k, c) from the FE ball's own impact on a rigid plane at that
speed: c from its COR (`hunt_crossley_lambda`: a Hunt-Crossley impact's COR depends on lambda v
alone), k so that the law's contact time on the rigid plane equals the FE run's. With d = D x,
t = T s, D = (m v^2 / k)^(2/5), T = D / v the rigid-plane impact is x'' = -x^1.5 (1 + z x'),
x(0) = 0, x'(0) = 1 with z = lambda v: its contact time is T s_c(z), so the root of
T(k) s_c(z) = t_FE is k = m v^2 (v t_FE / s_c(z))^(-5/2) (found once s_c(z) is integrated).
The law then reproduces the FE COR (checked within `COR_TOLERANCE`); its peak force is what
the law makes of it (reported next to the FE one in `calibration`).

The FE ball coupled directly to the bat inside the explicit kernel is a later step: the law
leaves out the ball's contact on a curved, moving surface (a bat's barrel is not a plane) and
its rate dependence beyond the Hunt-Crossley form.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from ..checks import check_positive, check_range, shown
from ..balls.checks import check_ball_mass
from ..errors import InputError, SimulationError

#: largest relative difference allowed between the law's COR on the rigid plane and the FE one
COR_TOLERANCE = 0.005


@dataclass(frozen=True)
class RigidPlaneImpact:
    """The law's impact on a rigid plane at `speed_m_s`: COR (integrated), contact time (s),
    peak force (N) and the largest compression (m)."""

    speed_m_s: float
    cor: float
    contact_time_s: float
    peak_force_n: float
    max_compression_m: float


def _unit_impact(z: float) -> tuple[float, float, float, float]:
    """x'' = -x^1.5 (1 + z x')+, x(0) = 0, x'(0) = 1 until x returns to 0: (contact time s_c,
    rebound speed, peak force k D^1.5 units, largest x)."""
    def rhs(_, y):
        x = max(y[0], 0.0)
        return [y[1], -max(x ** 1.5 * (1.0 + z * y[1]), 0.0)]

    def back(_, y):
        return y[0]
    back.terminal, back.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 50.0), [0.0, 1.0], method="DOP853", events=back, rtol=1e-11,
                    atol=1e-14, dense_output=True)
    if sol.status != 1:
        raise SimulationError(f"Hunt-Crossley impact with lambda v = {z:g}: no separation")
    s_c = float(sol.t_events[0][0])
    s = np.linspace(0.0, s_c, 2001)
    x, xd = sol.sol(s)
    force = np.clip(np.clip(x, 0, None) ** 1.5 * (1.0 + z * xd), 0.0, None)
    return s_c, float(-sol.y_events[0][0][1]), float(force.max()), float(x.max())


@dataclass(frozen=True)
class HuntCrossleyBall:
    """A ball as a Hunt-Crossley contact law F = k d^1.5 (1 + 1.5 c d'), F >= 0: mass (kg),
    k = `stiffness` (N/m^1.5), c = `damping_s_m` (s/m). `calibration`: how it was made (the FE
    run's figures and the law's own), empty for a law given directly."""

    mass_kg: float
    stiffness: float
    damping_s_m: float
    name: str = "hunt-crossley"
    calibration: dict = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        check_ball_mass(self.mass_kg, "ball.mass_kg")  # grams typed as kg named as such
        check_positive("ball.stiffness", self.stiffness)
        check_range("ball.damping_s_m", self.damping_s_m, 0.0, unit="s/m")

    @property
    def lambda_s_m(self) -> float:
        """lambda of `lumped.hunt_crossley` (F = k d^1.5 (1 + lambda d')): 1.5 c."""
        return 1.5 * self.damping_s_m

    def force(self, d, d_rate):
        """Contact force (N) at compression d (m) and its rate (m/s); 0 where d <= 0 or where
        the damping term would pull (no adhesion)."""
        d = np.clip(d, 0.0, None)
        return np.clip(self.stiffness * d ** 1.5 * (1.0 + self.lambda_s_m * d_rate), 0.0, None)

    def stored_energy_j(self, d):
        """The law's elastic energy at compression d: k d^2.5 / 2.5 (J)."""
        return 0.4 * self.stiffness * np.clip(d, 0.0, None) ** 2.5

    def cor(self, speed_m_s: float) -> float:
        """The law's COR on a rigid plane at `speed_m_s` (closed form, `hunt_crossley_cor`)."""
        from ..lumped.hunt_crossley import hunt_crossley_cor  # JAX comes with lumped: when used

        return hunt_crossley_cor(self.lambda_s_m, speed_m_s)

    def rigid_plane(self, speed_m_s: float) -> RigidPlaneImpact:
        """The law's impact on a rigid plane (integrated), at `speed_m_s`."""
        v = check_positive("speed_m_s", speed_m_s)
        s_c, rebound, peak, x_max = _unit_impact(self.lambda_s_m * v)
        d = (self.mass_kg * v ** 2 / self.stiffness) ** 0.4
        return RigidPlaneImpact(v, rebound, s_c * d / v, self.stiffness * d ** 1.5 * peak,
                                x_max * d)

    @classmethod
    def from_cor_contact_time(cls, mass_kg: float, cor: float, contact_time_s: float,
                              speed_m_s: float, name: str = "hunt-crossley") -> HuntCrossleyBall:
        """The law of a ball of `mass_kg` whose impact on a rigid plane at `speed_m_s` has `cor`
        and `contact_time_s` (module docstring)."""
        m = check_positive("mass_kg", mass_kg)
        v = check_positive("speed_m_s", speed_m_s)
        t_c = check_positive("contact_time_s", contact_time_s)
        from ..lumped.hunt_crossley import hunt_crossley_lambda

        lam = hunt_crossley_lambda(cor, v)
        s_c = _unit_impact(lam * v)[0]
        k = m * v ** 2 * (v * t_c / s_c) ** -2.5
        return cls(m, k, lam / 1.5, name)

    def summary(self) -> dict[str, Any]:
        out = {"name": self.name, "law": "F = k d^1.5 (1 + 1.5 c d'), F >= 0",
               "mass_kg": self.mass_kg, "stiffness_n_m1_5": self.stiffness,
               "damping_s_m": self.damping_s_m}
        if self.calibration:
            out["calibration"] = dict(self.calibration)
        return out


_CACHE: dict[tuple[str, float], HuntCrossleyBall] = {}


def _key(ball) -> str:
    if isinstance(ball, dict):
        return json.dumps(ball, sort_keys=True, default=str)
    if isinstance(ball, Path):
        return str(ball.resolve())
    if isinstance(ball, str):
        return ball
    raise InputError(f"ball = {shown(ball)}: expected a preset name, a ball file or a dict")


def ball_law(ball, speed_m_s: float, *, allow=()) -> HuntCrossleyBall:
    """The Hunt-Crossley law of an FE ball (a preset name, a ball file or a dict; `fe.load_ball`)
    from one FE impact on the rigid plane at `speed_m_s` (module docstring); cached per
    (ball, speed) in this process. A `HuntCrossleyBall` is returned as it is. Its
    `calibration` holds the FE run's COR, contact time and peak force and the law's."""
    if isinstance(ball, HuntCrossleyBall):
        return ball
    speed = check_positive("speed_m_s", speed_m_s)
    key = (_key(ball), speed)
    if key in _CACHE:
        return _CACHE[key]
    from ..fe import load_ball, simulate

    model = load_ball(ball, impact_speed_m_s=speed, allow=allow)
    fe = simulate(model, speed, allow=allow)
    law = HuntCrossleyBall.from_cor_contact_time(fe.mass_kg, fe.cor, fe.contact_time_s, speed,
                                                 name=fe.ball_name)
    own = law.rigid_plane(speed)
    error = own.cor / fe.cor - 1.0
    if abs(error) > COR_TOLERANCE:
        raise SimulationError(f"ball law of {fe.ball_name} at {speed:g} m/s: its COR {own.cor:.4f}"
                              f" differs from the FE one {fe.cor:.4f} by {error:+.2%}")
    calibration = {"speed_m_s": speed, "fe_cor": fe.cor, "fe_contact_time_s": fe.contact_time_s,
                   "fe_peak_force_n": fe.peak_force_n, "law_cor": own.cor,
                   "law_contact_time_s": own.contact_time_s, "law_peak_force_n": own.peak_force_n,
                   "cor_error": error,
                   "peak_force_error": own.peak_force_n / fe.peak_force_n - 1.0}
    law = HuntCrossleyBall(law.mass_kg, law.stiffness, law.damping_s_m, law.name, calibration)
    _CACHE[key] = law
    return law
