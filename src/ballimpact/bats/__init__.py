"""Bats: a bat's specification and presets (`spec`), its cross-sections (`section`), rigid-body
properties (`properties`), the Timoshenko beam model (`beam`) and its normal modes (`modes`);
the ball on the bat: the ball's contact law (`ball_law`), one collision (`impact`), a sweep
along the bat (`sweep`) and its plots (`plots`); the checked run of `ballimpact bat` (`study`);
docs/equipment.md, "The bat" and "Ball on bat".
NumPy and SciPy only (no JAX; `ball_law` runs the FE ball only when asked to)."""

from .ball_law import HuntCrossleyBall, ball_law
from .beam import DEFAULT_ELEMENTS, BeamModel, beam_model
from .impact import BatImpactResult, bat_impact, bat_model
from .modes import SUPPORTS, BatModes, Grip, modes
from .properties import BatProperties, bat_properties
from .section import Sections, sections
from .spec import PRESETS, BatMaterial, BatSpec, Blade, bat_from_dict, load_bat
from .study import ball_on_bat, collider
from .sweep import ImpactSweep, impact_sweep

__all__ = ["DEFAULT_ELEMENTS", "PRESETS", "SUPPORTS", "BatImpactResult", "BatMaterial",
           "BatModes", "BatProperties", "BatSpec", "BeamModel", "Blade", "Grip",
           "HuntCrossleyBall", "ImpactSweep", "Sections", "ball_law", "ball_on_bat",
           "bat_from_dict", "bat_impact", "bat_model", "bat_properties", "beam_model",
           "collider", "impact_sweep", "load_bat", "modes", "sections"]
