"""What every lumped ball model has: its parameters (SI, with units), how a fit searches them, and
one batched run from first contact to separation.

Sign conventions: the compression y (m) is positive into the surface and y' (m/s) is its rate, so
a ball arriving at speed v_in starts with y = 0, y' = +v_in. The contact force is positive in
compression. A unit leaves the surface when its contact force returns to zero (see `engine`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from ..checks import check_positive, check_range
from ..errors import InputError


@dataclass(frozen=True)
class Parameter:
    """One model parameter.

    `search` says how a fit samples it: `linear` or `log` between its bounds; `stiffness` for the
    k of a power-law spring F = k y^a, searched (log) as the force k y_ref^a at a reference
    compression y_ref, because k's scale depends on the exponent (`exponent`: the name of the
    exponent parameter, or a fixed number); `mass_share` for a unit mass, searched as a share of the
    ball mass not yet given to the units before it; `mass_rest` for the last unit's mass (the rest,
    never searched). `fixed` parameters (geometry, constants) are not searched unless given bounds.
    """

    name: str
    unit: str
    description: str
    search: str = "linear"
    exponent: str | float | None = None
    default: float | None = None  # value used when the parameter is fixed

    @property
    def fixed(self) -> bool:
        return self.default is not None


@dataclass(frozen=True)
class Scale:
    """Scales of a measured impact, from which a model draws its default search bounds."""

    mass_kg: float
    impact_speed_m_s: float
    contact_time_s: float
    peak_force_n: float
    max_compression_m: float

    @property
    def force_per_speed_n_s_m(self) -> float:
        return self.peak_force_n / self.impact_speed_m_s

    @property
    def stiffness_force_bounds_n(self) -> tuple[float, float]:
        """Default search range of a single spring's force at the reference compression."""
        return 0.3 * self.peak_force_n, 3.0 * self.peak_force_n


@dataclass(frozen=True)
class BatchResult:
    """Runs of one model for B parameter sets on a common uniform time grid from first contact.

    `force_n` (B, n) is the total contact force (zero after separation); `velocity_m_s` (B, n) the
    centre-of-mass velocity, positive towards the surface; `contact_time_s` and
    `rebound_speed_m_s` (B,) are located at the separation event (NaN where a run did not
    separate within the grid, `separated` False).
    """

    time_s: np.ndarray
    force_n: np.ndarray
    velocity_m_s: np.ndarray
    contact_time_s: np.ndarray
    rebound_speed_m_s: np.ndarray
    separated: np.ndarray


class LumpedModel(ABC):
    """Base of the registry's models. A model has a `name`, a one-line `summary`, its
    `parameters`, `default_bounds(scale)` (name -> (low, high); for `stiffness` parameters the
    bounds of the force at the reference compression, N) and `run_batch`."""

    name: str
    summary: str
    parameters: tuple[Parameter, ...]
    reproduction: bool = False  # True for transcriptions of published code, not recommended

    @property
    def parameter_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    @property
    def units(self) -> dict[str, str]:
        return {p.name: p.unit for p in self.parameters}

    @abstractmethod
    def default_bounds(self, scale: Scale) -> dict[str, tuple[float, float]]:
        """Search bounds drawn from the scales of a measured impact."""

    def check(self, params: dict[str, float], mass_kg: float | None) -> None:
        """Validate a full parameter set (names, finiteness; model-specific ranges)."""
        unknown = sorted(set(params) - set(self.parameter_names))
        if unknown:
            raise InputError(
                f"params: unknown parameter(s) {', '.join(unknown)} for model {self.name!r}; "
                f"it has {', '.join(self.parameter_names)}"
            )
        for p in self.parameters:
            if p.name not in params and p.default is None:
                raise InputError(f"params: missing {p.name!r} ({p.unit}) for model {self.name!r}")
            value = params.get(p.name, p.default)
            try:
                value = float(value)
            except (TypeError, ValueError):
                pass  # refused below, shown as given
            check_range(f"params.{p.name}", value)

    def full(self, params: dict[str, float]) -> dict[str, float]:
        """`params` with fixed parameters filled in from their defaults."""
        return {p.name: float(params.get(p.name, p.default)) for p in self.parameters}

    def ball_mass_kg(self, params: dict[str, float], mass_kg: float | None) -> float:
        """The ball mass a run uses (models with unit masses derive it from them)."""
        if mass_kg is None:
            raise InputError(f"mass_kg: model {self.name!r} needs the ball mass (kg)")
        return check_positive("mass_kg", mass_kg)

    @abstractmethod
    def run_batch(
        self, params: np.ndarray, mass_kg: float, impact_speed_m_s: float, step_s: float, steps: int
    ) -> BatchResult:
        """Runs for parameter vectors (B, P) in `parameter_names` order, from first contact on a
        grid of `steps` steps of `step_s` seconds (a model with its own fixed step may ignore
        both)."""
