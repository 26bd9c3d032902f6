"""Bats: a bat's specification and presets (`spec`), its cross-sections (`section`), rigid-body
properties (`properties`), the Timoshenko beam model (`beam`) and its normal modes (`modes`);
docs/equipment.md, "The bat". NumPy and SciPy only (no JAX)."""

from .beam import DEFAULT_ELEMENTS, BeamModel, beam_model
from .modes import SUPPORTS, BatModes, Grip, modes
from .properties import BatProperties, bat_properties
from .section import Sections, sections
from .spec import PRESETS, BatMaterial, BatSpec, Blade, bat_from_dict, load_bat

__all__ = ["DEFAULT_ELEMENTS", "PRESETS", "SUPPORTS", "BatMaterial", "BatModes", "BatProperties",
           "BatSpec", "BeamModel", "Blade", "Grip", "Sections", "bat_from_dict", "bat_properties",
           "beam_model", "load_bat", "modes", "sections"]
