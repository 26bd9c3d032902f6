"""Numerical settings of the explicit FE solver (SI), validated on construction."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from ..checks import check_integer, check_metres, check_range, shown
from ..errors import InputError, InputWarning
from .hex.mesh import GRADING_RANGE

INTEGRATIONS = ("reduced", "full")
PRECISIONS = ("float64", "float32")


@dataclass(frozen=True)
class ImpactCondition:
    """An impact on a flat surface, accepted by both engines (the axisymmetric one takes normal
    impacts: angle 0, no spin; it models no friction).

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
    def normal(self) -> bool:
        """A normal impact without spin (what the axisymmetric engine runs)."""
        return self.angle_deg == 0.0 and self.spin_vector_rad_s == (0.0, 0.0, 0.0)

    @property
    def spin_vector_rad_s(self) -> tuple[float, float, float]:
        return (self.spin_x_rad_s, self.spin_rad_s, self.spin_z_rad_s)


@dataclass(frozen=True)
class ExplicitOptions:
    """The settings both explicit engines share (SI), checked one way. Defaults follow
    ABAQUS/Explicit where it has one.

    - `integration`: "reduced" (one point per element with stiffness hourglass control, as
      CAX4R and C3D8R; the default) or "full" (2x2 or 2x2x2 points with F-bar).
    - `time_step_scale`: safety factor on the stable increment 2 / omega_max of the assembled
      system (found by Lanczos at the instantaneous moduli, contact springs included). Above 1
      the run is unstable in theory and is stopped by the energy check.
    - `energy_error_limit`: a run whose energy balance error exceeds this fraction of the initial
      kinetic energy stops with `SimulationError` (an unstable increment grows it exponentially).
    - `precision`: "float64" or "float32" arithmetic in the step.
    - `end_margin`: simulated after separation, as a fraction of the contact time.
    - `time_limit_s`: a run not separated by then fails (default: 6 times a Hertz estimate of
      the contact time).
    - `chunk_steps`: steps between the increment's re-estimates (and progress reports).
    """

    integration: str = "reduced"
    hourglass_scale: float = 0.05     # k_e = scale mu V_e (dN/dX : dN/dX), reduced integration
    bulk_viscosity_linear: float = 0.06
    bulk_viscosity_quadratic: float = 1.2
    penalty_scale: float = 1.0        # contact frequency sqrt(k/m) = sqrt(scale) c_d / L
    contact_damping: float = 0.0      # fraction of critical damping of each contact spring
    time_step_scale: float = 0.8      # safety factor on the assembled system's stable increment
    energy_error_limit: float = 0.05
    precision: str = "float64"
    end_margin: float = 0.25          # simulated after separation, as a fraction of contact time
    time_limit_s: float | None = None  # default: 6 times a Hertz estimate of the contact time
    chunk_steps: int = 200
    #: settings a geometry may leave None, to be chosen from the expected contact
    CHOSEN_FROM_CONTACT = ()

    def __post_init__(self) -> None:
        for name, high, zero_ok in (("hourglass_scale", 1.0, False),
                                    ("bulk_viscosity_linear", 10.0, True),
                                    ("bulk_viscosity_quadratic", 10.0, True),
                                    ("penalty_scale", 100.0, False),
                                    ("contact_damping", 1.0, True),
                                    ("time_step_scale", 2.0, False),
                                    ("energy_error_limit", 1.0, False),
                                    ("end_margin", 10.0, True)):
            if getattr(self, name) is None and name in self.CHOSEN_FROM_CONTACT:
                continue
            check_range(name, getattr(self, name), 0.0, high, low_open=not zero_ok)
        for name, value, allowed in (("integration", self.integration, INTEGRATIONS),
                                     ("precision", self.precision, PRECISIONS)):
            if value not in allowed:
                raise InputError(f"{name} = {shown(value)}: allowed {', '.join(allowed)}")
        if self.time_step_scale > 1.0:
            warnings.warn(f"time_step_scale = {self.time_step_scale:g} is above the stability "
                          "limit of the assembled system (1): expect the run to be stopped",
                          InputWarning, stacklevel=4)
        if self.time_limit_s is not None:
            check_range("time_limit_s", self.time_limit_s, 0.0, 10.0, low_open=True)
        object.__setattr__(self, "chunk_steps", check_integer("chunk_steps", self.chunk_steps, 1))


#: `fe.compress`'s platen penalty over the impact solver's: a static solve has no stability
#: limit, and the impact's springs let a compressible ball (nu 0.3) sink into the platens by
#: enough to read 4% soft at D / 2R = 2% (a 100x penalty moves it 0.3% further). Here, not in
#: `fe.compression`, so that the command line's help needs no JAX import.
COMPRESSION_PENALTY_SCALE = 30.0


@dataclass(frozen=True)
class SolverOptions(ExplicitOptions):
    """Settings of the axisymmetric engine (SI): the shared ones (`ExplicitOptions`) and its
    mesh's.

    - `element_size_m`: the outer surface's element length (the mean element side is ~1.2 mm
      at the default 1.5 mm).
    - `pole_element_size_m`, `pole_zone_deg`: a finer element size toward the contact pole,
      within this angle of it; `both_poles`: at the north pole too (a ball between two
      platens, `fe.compress`).
    - `mesh_radii_m`: extra node circles (e.g. to mesh like another ball).
    """

    element_size_m: float = 1.5e-3
    pole_element_size_m: float | None = None
    pole_zone_deg: float = 30.0
    both_poles: bool = False
    mesh_radii_m: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        check_range("element_size_m", self.element_size_m, 0.0, math.inf, low_open=True)
        super().__post_init__()


@dataclass(frozen=True)
class Options3D(ExplicitOptions):
    """Settings of the 3D engine (SI): the shared ones (`ExplicitOptions`) and its
    mesh's, friction's, targets' and output's.

    - `divisions`: elements along each edge of the O-grid's cube (90 degrees of arc); even.
    - `pole_grading`: largest over smallest arc spacing (finer toward the contact pole). None
      (default): chosen from the Hertz contact radius a expected at the smallest normal speed
      of a run, 2 or finer until 3 elements span a (`fe.hex.contact_grading.contact_settings`).
    - `penalty_scale` (the shared setting): None (default) chooses 3 where fewer than 4
      elements of the mesh span a (a small contact: the gripping regime's balance,
      docs/oblique.md), 1 otherwise (ball impacts).
    - `half`: a half model on the plane of incidence (symmetric: no out-of-plane spin). None:
      half when every condition allows it, the full model otherwise.
    - `contact_elements`: when set, the pole grading is chosen for the impact so that this many
      elements span the Hertz contact radius expected at the smallest normal speed of a run
      (`fe.hex.contact_grading`; `pole_grading` is then ignored).
    - `stick_scale`: stick-spring stiffness of friction over the normal penalty stiffness.
    - `slab_depth_growth`: a target slab's cells. None: through the depth uniform, 4 pole
      spacings thick (in plane graded toward the centre, see `fe.hex.geometry.slab_layout`). A growth
      factor in (1, 2]: a slab matched to the contact: cells of the ball's pole spacing at the
      centre of its surface, growing in plane as the ball's cells grow from its pole (at least
      1.15 a cell) and by this factor a cell down to at most 4 pole spacings; it resolves a small contact's stresses in the slab (a light
      foam's finer surface cells may chatter against the ball).
    - `slab_depth_cell_m`: with the default slab layout, its cells' size through the depth (m;
      None: about 4 pole spacings, at least 2 cells a layer). Finer cells resolve a thick
      liner's compression under a stiff shell (docs/equipment.md, "Protective equipment").
    - `frames`: keep the displacements every this many chunks for VTK output and animation
      (0: none).
    """

    divisions: int = 16
    pole_grading: float | None = None
    contact_elements: float | None = None
    half: bool | None = None
    stick_scale: float = 8.0
    slab_depth_growth: float | None = None
    slab_depth_cell_m: float | None = None
    frames: int = 0
    penalty_scale: float | None = None
    CHOSEN_FROM_CONTACT = ("penalty_scale",)

    def __post_init__(self) -> None:
        object.__setattr__(self, "divisions",
                           check_integer("divisions", self.divisions, 4, 64, even=True))
        if self.pole_grading is not None:
            check_range("pole_grading", self.pole_grading, *GRADING_RANGE)
        if self.contact_elements is not None:
            check_range("contact_elements", self.contact_elements, 0.5, 50.0)
        check_range("stick_scale", self.stick_scale, 0.0, 100.0, low_open=True)
        if self.slab_depth_growth is not None:
            check_range("slab_depth_growth", self.slab_depth_growth, 1.0, 2.0, low_open=True)
        if self.slab_depth_cell_m is not None:
            check_metres("slab_depth_cell_m", self.slab_depth_cell_m, 0.1, low=1e-4)
            if self.slab_depth_growth is not None:
                raise InputError("slab_depth_cell_m: applies to the default slab layout; give "
                                 "it or slab_depth_growth, not both")
        object.__setattr__(self, "frames", check_integer("frames", self.frames, 0))
        super().__post_init__()
