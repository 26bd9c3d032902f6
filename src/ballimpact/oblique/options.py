"""Settings of the 3D solver and the impact condition (SI), validated on construction."""

from __future__ import annotations

from dataclasses import dataclass

from ..checks import check_range, shown
from ..errors import InputError
from ..fe.options import INTEGRATIONS, PRECISIONS
from .mesh import GRADING_RANGE


@dataclass(frozen=True)
class ImpactCondition:
    """An oblique impact on a flat surface.

    - `speed_m_s`: speed of the ball's centre before impact (m/s).
    - `angle_deg`: angle of the incoming velocity from the surface normal (0: normal impact).
    - `spin_rad_s`: spin about the axis parallel to the surface and normal to the incoming
      tangential velocity; positive is topspin, the sense of a ball rolling forward (its bottom
      moving backward relative to its centre: a ball rolling at v_x has spin v_x / R).
    - `friction`: Coulomb coefficient between ball and surface.
    - `spin_x_rad_s`, `spin_z_rad_s`: out-of-plane spin, about the direction of the incoming
      tangential velocity (x) and about the surface normal (z, upward), right-handed. Either
      needs the full model (the half model's symmetry holds only without them).

    Axes: x along the incoming tangential velocity, z the surface normal (up), y = z x x; the
    in-plane spin `spin_rad_s` is about +y.
    """

    speed_m_s: float
    angle_deg: float = 0.0
    spin_rad_s: float = 0.0
    friction: float = 0.0
    spin_x_rad_s: float = 0.0
    spin_z_rad_s: float = 0.0

    def __post_init__(self) -> None:
        check_range("speed_m_s", self.speed_m_s, 0.0, 1e3, low_open=True)
        check_range("angle_deg", self.angle_deg, 0.0, 89.0)
        for name in ("spin_rad_s", "spin_x_rad_s", "spin_z_rad_s"):
            check_range(name, getattr(self, name), -1e4, 1e4)
        check_range("friction", self.friction, 0.0, 10.0)
        for name in ("speed_m_s", "angle_deg", "spin_rad_s", "friction", "spin_x_rad_s",
                     "spin_z_rad_s"):  # plain floats: no np.float64(...) in reprs and messages
            object.__setattr__(self, name, float(getattr(self, name)))

    @property
    def symmetric(self) -> bool:
        """Symmetric about the plane of incidence (a half model serves)."""
        return self.spin_x_rad_s == 0.0 and self.spin_z_rad_s == 0.0

    @property
    def spin_vector_rad_s(self) -> tuple[float, float, float]:
        return (self.spin_x_rad_s, self.spin_rad_s, self.spin_z_rad_s)


@dataclass(frozen=True)
class Options3D:
    """Numerical settings of the 3D solver (SI); the shared ones as `fe.SolverOptions`.

    - `divisions`: elements along each edge of the O-grid's cube (90 degrees of arc); even.
    - `pole_grading`: largest over smallest arc spacing (finer toward the contact pole).
    - `half`: a half model on the plane of incidence (symmetric: no out-of-plane spin). None:
      half when every condition allows it, the full model otherwise.
    - `integration`: "reduced" (one point with hourglass control, the default) or "full"
      (2x2x2 points with F-bar), as the axisymmetric engine.
    - `contact_elements`: when set, the pole grading is chosen for the impact so that this many
      elements span the Hertz contact radius expected at the smallest normal speed of a run
      (`oblique.contact_grading`; `pole_grading` is then ignored).
    - `stick_scale`: stick-spring stiffness of friction over the normal penalty stiffness.
    - `slab_depth_growth`: a target slab's cells. None: through the depth uniform, 4 pole
      spacings thick (in plane graded toward the centre, see `solver._slab_layout`). A growth
      factor in (1, 2]: a slab matched to the contact: cells of the ball's pole spacing at the
      centre of its surface, growing in plane as the ball's cells grow from its pole (at least
      1.15 a cell) and by this factor a cell down to at most 4 pole spacings; it resolves a small contact's stresses in the slab (a light
      foam's finer surface cells may chatter against the ball).
    - `frames`: keep the displacements every this many chunks for VTK output and animation
      (0: none).
    """

    divisions: int = 16
    pole_grading: float = 2.0
    contact_elements: float | None = None
    half: bool | None = None
    integration: str = "reduced"
    hourglass_scale: float = 0.05
    bulk_viscosity_linear: float = 0.06
    bulk_viscosity_quadratic: float = 1.2
    penalty_scale: float = 1.0
    stick_scale: float = 8.0
    slab_depth_growth: float | None = None
    contact_damping: float = 0.0
    time_step_scale: float = 0.8
    energy_error_limit: float = 0.05
    precision: str = "float64"
    end_margin: float = 0.25
    time_limit_s: float | None = None
    chunk_steps: int = 200
    frames: int = 0

    def __post_init__(self) -> None:
        if not (isinstance(self.divisions, int) and self.divisions >= 4
                and self.divisions % 2 == 0 and self.divisions <= 64):
            raise InputError(f"divisions = {shown(self.divisions)}: must be an even integer in [4, 64]")
        check_range("pole_grading", self.pole_grading, *GRADING_RANGE)
        if self.contact_elements is not None:
            check_range("contact_elements", self.contact_elements, 0.5, 50.0)
        check_range("hourglass_scale", self.hourglass_scale, 0.0, 1.0, low_open=True)
        check_range("bulk_viscosity_linear", self.bulk_viscosity_linear, 0.0, 10.0)
        check_range("bulk_viscosity_quadratic", self.bulk_viscosity_quadratic, 0.0, 10.0)
        check_range("penalty_scale", self.penalty_scale, 0.0, 100.0, low_open=True)
        check_range("stick_scale", self.stick_scale, 0.0, 100.0, low_open=True)
        if self.slab_depth_growth is not None:
            check_range("slab_depth_growth", self.slab_depth_growth, 1.0, 2.0, low_open=True)
        check_range("contact_damping", self.contact_damping, 0.0, 1.0)
        check_range("time_step_scale", self.time_step_scale, 0.0, 1.0, low_open=True)
        check_range("energy_error_limit", self.energy_error_limit, 0.0, 1.0, low_open=True)
        check_range("end_margin", self.end_margin, 0.0, 10.0)
        if self.integration not in INTEGRATIONS:
            raise InputError(f"integration = {self.integration!r}: allowed "
                             f"{', '.join(INTEGRATIONS)}")
        if self.precision not in PRECISIONS:
            raise InputError(f"precision = {self.precision!r}: allowed {', '.join(PRECISIONS)}")
        if self.time_limit_s is not None:
            check_range("time_limit_s", self.time_limit_s, 0.0, 10.0, low_open=True)
        for name in ("chunk_steps", "frames"):
            value = getattr(self, name)
            if not (isinstance(value, int) and value >= (1 if name == "chunk_steps" else 0)):
                raise InputError(f"{name} = {shown(value)}: must be an integer >= "
                                 f"{1 if name == 'chunk_steps' else 0}")
