"""The ball-bat collision along the bat (`impact_sweep`): the collision efficiency and the
vibration energy left in the bat against the impact point, and the sweet spot; docs/equipment.md,
"Ball on bat"."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InputError
from .ball_law import HuntCrossleyBall
from .beam import DEFAULT_ELEMENTS
from .fe_impact import fe_bat_impacts
from .impact import DEFAULT_MODES, BatImpactResult, bat_impact, bat_model


def extremum_x(x: np.ndarray, y: np.ndarray, i: int, largest: bool = True) -> float:
    """The x of the largest (or smallest) y: the vertex of the parabola through the 3 points
    around index i, where it bends that way (x[i] at an end, or where it does not)."""
    if i == 0 or i == x.size - 1:
        return float(x[i])
    a, b, _ = np.polyfit(x[i - 1:i + 2], y[i - 1:i + 2], 2)
    if (a < 0) if largest else (a > 0):
        return float(np.clip(-b / (2 * a), x[i - 1], x[i + 1]))
    return float(x[i])


@dataclass(frozen=True)
class ImpactSweep:
    """`bat_impact` at each of `points_m` (from the knob end). The sweet spot as the largest
    collision efficiency (`max_efficiency_m`) and as the least vibration energy
    (`least_vibration_m`): the sweep's best point refined by a parabola through its neighbours."""

    results: tuple[BatImpactResult, ...]

    @property
    def points_m(self) -> np.ndarray:
        return np.array([r.impact_m for r in self.results])

    @property
    def bat_length_m(self) -> float:
        return self.results[0].bat_length_m

    @property
    def from_barrel_end_m(self) -> np.ndarray:
        return self.bat_length_m - self.points_m

    @property
    def collision_efficiency(self) -> np.ndarray:
        return np.array([r.collision_efficiency for r in self.results])

    @property
    def batted_ball_speed_m_s(self) -> np.ndarray:
        return np.array([r.batted_ball_speed_m_s for r in self.results])

    @property
    def vibration_energy_j(self) -> np.ndarray:
        """The bending modes' energy at the separation, summed (J)."""
        return np.array([r.bat_vibration_energy_j.sum() for r in self.results])

    @property
    def max_efficiency_m(self) -> float:
        e = self.collision_efficiency
        return extremum_x(self.points_m, e, int(np.argmax(e)))

    @property
    def least_vibration_m(self) -> float:
        e = self.vibration_energy_j
        return extremum_x(self.points_m, e, int(np.argmin(e)), largest=False)

    def summary(self) -> dict[str, Any]:
        first = self.results[0].summary(histories=False)
        common = {k: first[k] for k in ("bat", "ball", "speed_m_s", "bat_speed_m_s", "support",
                                        "pivot_m", "bat_mass_kg", "bat_centre_of_mass_m",
                                        "bat_moment_of_inertia_kg_m2", "mode_frequencies_hz")}
        keys = ("impact_m", "from_barrel_end_m", "collision_efficiency",
                "batted_ball_speed_m_s", "rigid_collision_efficiency",
                "bat_vibration_energy_total_j", "ball_energy_lost_j", "max_bending_stress_pa",
                "max_bending_stress_x_m", "max_contact_rotation_rad", "peak_force_n",
                "contact_duration_s", "contacts",
                "energy_balance_error")
        points = [{k: r.summary(histories=False)[k] for k in keys} for r in self.results]
        length = self.bat_length_m
        return {**common, "points": points,
                "sweet_spot": {"max_efficiency_m": self.max_efficiency_m,
                               "max_efficiency_from_barrel_end_m":
                                   length - self.max_efficiency_m,
                               "max_collision_efficiency": float(self.collision_efficiency.max()),
                               "least_vibration_m": self.least_vibration_m,
                               "least_vibration_from_barrel_end_m":
                                   length - self.least_vibration_m}}


def impact_sweep(bat, ball, speed_m_s: float, points_m, *,
                 bat_speed_m_s: float = 0.0, support: str = "free",
                 pivot_m: float | None = None, grip=None, modes: int = DEFAULT_MODES,
                 elements: int = DEFAULT_ELEMENTS, progress=None, options=None,
                 reference=None, allow=()) -> ImpactSweep:
    """The collision at each of `points_m` (the bat's modes computed once): `bat_impact` with
    `ball` a `HuntCrossleyBall` (`progress(i, n)` after each point if given), else
    `fe_impact.fe_bat_impacts` with the FE `ball` (a preset, file, dict or `fe.BallModel`;
    `options` its `fe.SolverOptions`): every point in one batched FE run, whose progress lines
    go to stderr when `progress` is given, and the ball's run on the rigid plane made once, or
    given as `reference`."""
    points = np.atleast_1d(np.asarray(points_m, dtype=float))
    if points.size < 1:
        raise InputError("points_m: no impact points")
    bm = bat_model(bat, support=support, pivot_m=pivot_m, grip=grip, modes=modes,
                   elements=elements)
    if not isinstance(ball, HuntCrossleyBall):
        return ImpactSweep(tuple(fe_bat_impacts(
            bm, ball, speed_m_s, points, bat_speed_m_s=bat_speed_m_s, pivot_m=pivot_m,
            options=options, reference=reference, progress=progress is not None, allow=allow)))
    results = []
    for i, x in enumerate(points):
        results.append(bat_impact(bm, ball, speed_m_s, float(x), bat_speed_m_s=bat_speed_m_s,
                                  pivot_m=pivot_m))
        if progress is not None:
            progress(i + 1, points.size)
    return ImpactSweep(tuple(results))
