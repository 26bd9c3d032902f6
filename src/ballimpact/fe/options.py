"""Numerical settings of the explicit FE solver (SI), validated on construction."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from ..checks import check_range, shown
from ..errors import InputError, InputWarning

INTEGRATIONS = ("reduced", "full")
PRECISIONS = ("float64", "float32")


@dataclass(frozen=True)
class SolverOptions:
    """Numerical settings (SI). Defaults follow ABAQUS/Explicit where it has one.

    - `integration`: "reduced" (one point per element with stiffness hourglass control, as
      CAX4R; the default) or "full" (2x2 points with F-bar).
    - `time_step_scale`: safety factor on the stable increment 2 / omega_max of the assembled
      system (found by power iteration at the instantaneous moduli, contact springs included).
      Above 1 the run is unstable in theory and is stopped by the energy check.
    - `energy_error_limit`: a run whose energy balance error exceeds this fraction of the initial
      kinetic energy stops with `SimulationError` (an unstable increment grows it exponentially).
    - `precision`: "float64" or "float32" arithmetic in the step.
    """

    element_size_m: float = 1.5e-3   # outer-surface element length; mean element side ~1.2 mm
    pole_element_size_m: float | None = None   # refinement toward the contact pole
    pole_zone_deg: float = 30.0
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
    mesh_radii_m: tuple[float, ...] = ()  # extra node circles (e.g. to mesh like another ball)

    def __post_init__(self) -> None:
        # (upper bound, zero allowed)
        checks = {"element_size_m": (math.inf, False), "hourglass_scale": (1.0, False),
                  "bulk_viscosity_linear": (10.0, True), "bulk_viscosity_quadratic": (10.0, True),
                  "penalty_scale": (100.0, False), "contact_damping": (1.0, True),
                  "time_step_scale": (2.0, False), "energy_error_limit": (1.0, False),
                  "end_margin": (10.0, True)}
        for name, (high, zero_ok) in checks.items():
            check_range(name, getattr(self, name), 0.0, high, low_open=not zero_ok)
        for name, value, allowed in (("integration", self.integration, INTEGRATIONS),
                                     ("precision", self.precision, PRECISIONS)):
            if value not in allowed:
                raise InputError(f"{name} = {shown(value)}: allowed {', '.join(allowed)}")
        if self.time_step_scale > 1.0:
            warnings.warn(f"time_step_scale = {self.time_step_scale:g} is above the stability "
                          "limit of the assembled system (1): expect the run to be stopped",
                          InputWarning, stacklevel=3)
        if self.time_limit_s is not None and not self.time_limit_s > 0:
            raise InputError(f"time_limit_s = {shown(self.time_limit_s)}: must be > 0")
        if not (isinstance(self.chunk_steps, int) and self.chunk_steps >= 1):
            raise InputError(f"chunk_steps = {shown(self.chunk_steps)}: must be an integer >= 1")
