"""What a universal model learns from and predicts, by the design space of its study.

- "material" (thesis chapter 6): the 19 features of the pulse on the model's own ball (SI; a
  test of another ball is mapped onto it at the same speed, `similarity.map_features`) ->
  C10, C01, g1, tau1 and mu0 on that ball.
- "groups": the 18 features made dimensionless by the test's own ball and speed (times by
  R / v, forces by m v^2 / R, ...; the speed itself, P15, is then 1 and left out) -> the four
  dimensionless groups (`similarity.GROUPS`), which give the constants of any homogeneous ball
  at any speed. No mapping, no speed axis: the study's runs all go to the four groups.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..records.features import FEATURE_NAMES
from . import space
from .similarity import FEATURE_KIND, GROUPS, BallSize, constants_of_groups, groups

FEATURES = tuple(FEATURE_NAMES)  # P1..P19
SPEED_COLUMN = FEATURES.index("P15")
MATERIAL_TARGETS = (*space.MATERIAL_PARAMETERS, "mu0_pa")
#: the groups' features: P15 (the impact speed) is 1 once made dimensionless by it
GROUP_FEATURES = tuple(k for k in FEATURES if k != "P15")


@dataclass(frozen=True)
class Design:
    """A design space's inputs (`features`), inverse outputs (`targets`) and forward inputs
    (`forward_inputs`), with the transforms between SI study rows and them."""

    name: str
    features: tuple[str, ...]
    targets: tuple[str, ...]
    forward_inputs: tuple[str, ...]

    def target_ranges(self, ranges: dict) -> dict[str, tuple[float, float]]:
        """Each target's range from the study's ranges (material: mu0's from C10's and C01's)."""
        if self.name == "groups":
            return {k: tuple(ranges[k]) for k in self.targets}
        (c10_lo, c10_hi), (c01_lo, c01_hi) = ranges["c10_pa"], ranges["c01_pa"]
        return {**{k: tuple(v) for k, v in ranges.items()},
                "mu0_pa": (2 * (c10_lo + c01_lo), 2 * (c10_hi + c01_hi))}

    def inputs(self, features: np.ndarray, size: BallSize) -> np.ndarray:
        """Rows of the 19 features in SI (P1..P19, the speed P15 among them) of impacts of a
        ball of `size` -> the inverse's inputs (`features`)."""
        features = np.atleast_2d(np.asarray(features, np.float64))
        if self.name == "material":
            return features
        speed = features[:, SPEED_COLUMN]
        return np.column_stack([features[:, FEATURES.index(k)] / size.scale(FEATURE_KIND[k], speed)
                                for k in self.features])

    def truth(self, params: np.ndarray, size: BallSize) -> np.ndarray:
        """Study rows (c10_pa, c01_pa, g1, tau1_s, impact_speed_m_s; SI) of a ball of `size` ->
        the targets' true values."""
        c10, c01, g1, tau1, speed = np.atleast_2d(np.asarray(params, np.float64)).T
        if self.name == "material":
            return np.column_stack([c10, c01, g1, tau1, 2.0 * (c10 + c01)])
        found = groups({"c10_pa": c10, "c01_pa": c01, "g1": g1, "tau1_s": tau1}, size, speed)
        return np.column_stack([found[k] for k in GROUPS])

    def forward_rows(self, params: np.ndarray, size: BallSize) -> np.ndarray:
        """Study rows (SI) -> the rows the forward surrogate takes (`forward_inputs`, SI)."""
        params = np.atleast_2d(np.asarray(params, np.float64))
        return params if self.name == "material" else self.truth(params, size)


MATERIAL = Design("material", FEATURES, MATERIAL_TARGETS, tuple(space.PARAMETERS))
GROUPS_DESIGN = Design("groups", GROUP_FEATURES, GROUPS, GROUPS)
DESIGNS = {d.name: d for d in (MATERIAL, GROUPS_DESIGN)}


def params_from_groups(groups: dict[str, float], size: BallSize, speed_m_s: float
                       ) -> dict[str, float]:
    """Universal-ball constants (c10_pa, c01_pa, g1, tau1_s, mu0_pa; SI) of a ball of `size` at
    `speed_m_s` (m/s) with the four `groups` (`similarity.constants_of_groups`)."""
    return constants_of_groups(groups, size.radius_m, size.density_kg_m3, speed_m_s)


def param_ranges_from_groups(ranges: dict[str, list[float]], size: BallSize, speed_m_s: float
                             ) -> dict[str, list[float]]:
    """The range of each constant (c10_pa, c01_pa, g1, tau1_s, mu0_pa) over a box of the groups
    (name -> [low, high]) on a ball of `size` at `speed_m_s`: each constant is monotonic in each
    group, so its extremes are at the box's corners."""
    corners = [params_from_groups({"rho_v2_over_mu0": a, "c01_over_c10": b, "g1": g,
                                   "tau1_v_over_r": t}, size, speed_m_s)
               for a in ranges["rho_v2_over_mu0"] for b in ranges["c01_over_c10"]
               for g in ranges["g1"] for t in ranges["tau1_v_over_r"]]
    return {k: [float(min(c[k] for c in corners)), float(max(c[k] for c in corners))]
            for k in MATERIAL_TARGETS}
