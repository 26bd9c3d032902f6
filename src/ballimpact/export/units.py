"""Consistent unit systems of the exported decks (SI in the package;
exports convert and say so in the file header).

A system is fixed by its units of length, mass and time; force, stress, density, velocity and
energy follow. mm-tonne-s is what ABAQUS and LS-DYNA users usually work in: N, MPa, tonne/mm^3,
mm/s, mJ.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import InputError


@dataclass(frozen=True)
class UnitSystem:
    """A consistent unit system: how many metres, kilograms and seconds its base units are."""

    name: str
    length_m: float
    mass_kg: float
    time_s: float
    labels: tuple[str, ...]  # length, mass, time, force, stress, density, energy

    # factors that take an SI value into this system (value_here = value_si * factor)
    @property
    def length(self) -> float:
        return 1.0 / self.length_m

    @property
    def time(self) -> float:
        return 1.0 / self.time_s

    @property
    def velocity(self) -> float:
        return self.time_s / self.length_m

    @property
    def force(self) -> float:
        return self.time_s ** 2 / (self.mass_kg * self.length_m)

    @property
    def stress(self) -> float:
        return self.force * self.length_m ** 2

    @property
    def density(self) -> float:
        return self.length_m ** 3 / self.mass_kg

    @property
    def energy(self) -> float:
        return self.force / self.length_m

    @property
    def inverse_stress(self) -> float:  # D1 (1/Pa)
        return 1.0 / self.stress

    def header(self) -> str:
        length, mass, time, force, stress, density, energy = self.labels
        return (f"units {self.name}: length {length}, mass {mass}, time {time}, force {force}, "
                f"stress {stress}, density {density}, energy {energy}")


SI = UnitSystem("si", 1.0, 1.0, 1.0, ("m", "kg", "s", "N", "Pa", "kg/m^3", "J"))
MM_TONNE_S = UnitSystem("mm-tonne-s", 1e-3, 1e3, 1.0,
                        ("mm", "tonne", "s", "N", "MPa", "tonne/mm^3", "mJ"))
UNIT_SYSTEMS = {system.name: system for system in (SI, MM_TONNE_S)}


def unit_system(name: str) -> UnitSystem:
    if name not in UNIT_SYSTEMS:
        raise InputError(f"units = {name!r}: allowed {', '.join(UNIT_SYSTEMS)}")
    return UNIT_SYSTEMS[name]
