"""Similarity of homogeneous balls: one study on a reference ball serves every size, mass and speed.

A homogeneous ball of radius R, density rho and the universal materials (Mooney-Rivlin C10, C01
with K = 20 mu0, one Prony term g1, tau1) hitting a rigid plane at speed v has no other length,
mass or time in it. Its dimensionless pulse F R / (m v^2) against t v / R is fixed by four groups:

- `rho_v2_over_mu0` = rho v^2 / mu0 (mu0 = 2 (C10 + C01), long-term): inertia against stiffness,
- `c01_over_c10` = C01 / C10: the shape of the strain energy,
- `g1`: the relaxing fraction of the modulus,
- `tau1_v_over_r` = tau1 v / R: relaxation time against the time to cross the ball.

(the FE mesh scales with R too: the element size is a fixed fraction of it). So a test of any
such ball maps exactly onto a test of the reference ball of a study at the same speed: times
scale by R0 / R, forces by (m0 / R0) / (m / R), speeds not at all; and the constants found for
the reference ball map back: moduli by rho / rho0, tau1 by R / R0, g1 and C01 / C10 unchanged.
`tests/universal/test_similarity.py` runs a ball and its scaled copy through the FE engine and asserts
their dimensionless pulses equal to 1e-6 (measured: 2e-12).
"""

from __future__ import annotations

import math
from collections.abc import Collection
from dataclasses import dataclass

from ..balls.checks import check_ball_diameter, check_ball_mass, check_ball_values

GROUPS = ("rho_v2_over_mu0", "c01_over_c10", "g1", "tau1_v_over_r")

#: the dimension of each feature (thesis table 6-1, `features.FEATURE_NAMES`): how it scales
FEATURE_KIND = {**{f"P{i}": "time" for i in range(1, 6)}, "P6": "force",
                **{f"P{i}": "force_rate" for i in range(7, 11)},
                **{f"P{i}": "ratio" for i in (11, 12, 13, 14, 17)},
                "P15": "speed", "P16": "speed", "P18": "acceleration", "P19": "acceleration"}


@dataclass(frozen=True)
class BallSize:
    """A homogeneous ball's radius (m) and mass (kg), and the scales of its impacts."""

    radius_m: float
    mass_kg: float

    @property
    def density_kg_m3(self) -> float:
        return self.mass_kg / (4.0 / 3.0 * math.pi * self.radius_m ** 3)

    def scale(self, kind: str, speed_m_s: float) -> float:
        """The unit of a quantity of `kind` in an impact at `speed_m_s`: times R / v, forces
        m v^2 / R, force rates m v^3 / R^2, speeds v, accelerations v^2 / R, ratios 1."""
        r, m, v = self.radius_m, self.mass_kg, speed_m_s
        return {"time": r / v, "force": m * v * v / r, "force_rate": m * v ** 3 / r ** 2,
                "speed": v, "acceleration": v * v / r, "ratio": 1.0}[kind]


def groups(params: dict[str, float], size: BallSize, speed_m_s: float) -> dict[str, float]:
    """The four groups of universal-ball constants (c10_pa, c01_pa, g1, tau1_s) on a ball of
    `size` at `speed_m_s` (m/s)."""
    mu0 = 2.0 * (params["c10_pa"] + params["c01_pa"])
    return {"rho_v2_over_mu0": size.density_kg_m3 * speed_m_s ** 2 / mu0,
            "c01_over_c10": params["c01_pa"] / params["c10_pa"],
            "g1": params["g1"],
            "tau1_v_over_r": params["tau1_s"] * speed_m_s / size.radius_m}


def constants_of_groups(groups: dict, radius_m: float, density_kg_m3: float, speed_m_s
                        ) -> dict:
    """`groups` inverted: the universal-ball constants (c10_pa, c01_pa, g1, tau1_s, mu0_pa; SI)
    of a ball of `radius_m` and `density_kg_m3` at `speed_m_s` (m/s) with the four groups
    (numbers, or arrays of one shape)."""
    mu0 = density_kg_m3 * speed_m_s ** 2 / groups["rho_v2_over_mu0"]
    c10 = mu0 / (2.0 * (1.0 + groups["c01_over_c10"]))
    return {"c10_pa": c10, "c01_pa": groups["c01_over_c10"] * c10, "g1": groups["g1"],
            "tau1_s": groups["tau1_v_over_r"] * radius_m / speed_m_s, "mu0_pa": mu0}


def map_features(values: dict[str, float], source: BallSize, target: BallSize
                 ) -> dict[str, float]:
    """Features (P1..P19, SI) of an impact of a `source` ball mapped to the similar impact of a
    `target` ball at the same speed (P15): each scaled by its kind's unit. Keys other than P1..P19
    are left out."""
    speed = values["P15"]
    return {key: value * target.scale(FEATURE_KIND[key], speed)
            / source.scale(FEATURE_KIND[key], speed)
            for key, value in values.items() if key in FEATURE_KIND}


def map_params(params: dict[str, float], source: BallSize, target: BallSize
               ) -> dict[str, float]:
    """Universal-ball constants of a `source` ball mapped to those of the similar `target` ball
    at the same speed: moduli (keys ending `_pa`) by the density ratio, tau1 by the radius ratio,
    g1 (and any other ratio) unchanged."""
    density = target.density_kg_m3 / source.density_kg_m3
    out = {}
    for key, value in params.items():
        if key.endswith("_pa"):
            out[key] = value * density
        elif key == "tau1_s":
            out[key] = value * target.radius_m / source.radius_m
        else:
            out[key] = value
    return out


def map_ranges(ranges: dict[str, list[float]], source: BallSize, target: BallSize
               ) -> dict[str, list[float]]:
    """`map_params` of each end of each range (name -> [low, high]): intervals and training
    ranges of a `source` ball's constants as the `target` ball's (the factors are positive, so
    the ends stay in order)."""
    return {k: [map_params({k: end}, source, target)[k] for end in ends]
            for k, ends in ranges.items()}


def check_diameter(diameter_m: float, flag: str = "--ball-diameter-m") -> float:
    """A ball diameter (m) within those of solid sports balls (`balls.checks.check_ball_diameter`;
    one in millimetres is named as such)."""
    return check_ball_diameter(diameter_m, f"ball_diameter_m ({flag})")


def check_size(diameter_m: float, mass_kg: float, allow: Collection[str] = (),
               flag: str = "--ball-diameter-m") -> BallSize:
    """A ball of `diameter_m` (m) and `mass_kg` (kg), checked as sports balls are
    (`balls.checks.BALL_RANGES`: a diameter in mm or a mass in g is named as such; the density
    they give must be a ball's too, the `ball-units` check)."""
    size = BallSize(0.5 * check_diameter(diameter_m, flag),
                    check_ball_mass(mass_kg, "mass_kg (--mass-kg)"))
    check_ball_values(f"ball of diameter {diameter_m:g} m and mass {mass_kg:g} kg",
                      {"density": size.density_kg_m3}, allow=allow)
    return size
