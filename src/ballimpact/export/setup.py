"""What a complete deck simulates besides the ball: the impact on a rigid plane (SI)."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from ..errors import InputError
from ..balls.ball import BallModel
from ..fe.estimates import hertz_contact_time_s
from ..checks import check_range


@dataclass(frozen=True)
class ImpactSetup:
    """Impact speed (m/s), angle of the incoming velocity from the plane's normal (deg),
    Coulomb friction, and the step time (s; default 1.5 x a Hertz estimate of the contact time
    with the ball's softest long-term modulus, which is longer than the FE contact time)."""

    speed_m_s: float
    angle_deg: float = 0.0
    friction: float = 0.0
    step_time_s: float | None = None

    def __post_init__(self) -> None:
        check_range("speed_m_s", self.speed_m_s, 0.0, 1000.0, low_open=True)
        check_range("angle_deg", self.angle_deg, 0.0, 89.0)
        check_range("friction", self.friction, 0.0, 10.0)
        if self.step_time_s is not None:
            check_range("step_time_s", self.step_time_s, 0.0, 1.0, low_open=True)

    def velocity_m_s(self, dimension: int) -> tuple[float, ...]:
        """Initial velocity of the ball: tangential along +x, toward the plane along -y (2D) or
        -z (3D)."""
        if dimension == 2 and self.angle_deg != 0.0:
            raise InputError(f"angle_deg = {self.angle_deg:g}: an axisymmetric deck is a normal "
                             "impact; use --solver 3d for oblique impacts")
        a = math.radians(self.angle_deg)
        vt, vn = self.speed_m_s * math.sin(a), -self.speed_m_s * math.cos(a)
        return (0.0, vn) if dimension == 2 else (vt, 0.0, vn)

    def contact_time_estimate_s(self, ball: BallModel) -> float:
        normal_speed = self.speed_m_s * math.cos(math.radians(self.angle_deg))
        return hertz_contact_time_s(ball, normal_speed)

    def step_time(self, ball: BallModel) -> float:
        return self.step_time_s or 1.5 * self.contact_time_estimate_s(ball)


#: labels of the decks' own sets and surfaces, which a layer's label must not take
RESERVED_LABELS = {"BALL_NODES", "BALL_ELEMENTS", "BALL_SURFACE", "BALL_PLANE", "PLANE",
                   "PLANE_NODES", "PLANE_REF", "PLANE_SURFACE", "AXIS", "SYMMETRY"}


def layer_labels(ball: BallModel) -> list[str]:
    """Each layer's name as an ABAQUS label: upper case, [A-Z0-9_], starting with a letter, and
    distinct from the others and from the decks' own labels (suffixed by its index if not)."""
    labels: list[str] = []
    for k, layer in enumerate(ball.layers):
        label = re.sub(r"[^A-Za-z0-9_]", "_", layer.name).upper()
        label = label if label[:1].isalpha() else f"L_{label}"
        if label in RESERVED_LABELS or label in labels:
            label = f"{label}_{k}"
        labels.append(label)
    return labels
