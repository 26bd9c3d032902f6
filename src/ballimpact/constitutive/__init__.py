"""FE materials: hyperelastic strain energies with optional Prony viscoelasticity.

`material_from_dict` reads the `material` object of a ball specification (docs/balls.md).
"""

from __future__ import annotations

from ..errors import InputError
from .base import (MODULI, Material, MaterialConstants, PronyTerm, Sym, energy_and_stress,
                   stress_parts)
from .linear_elastic import LinearElastic
from .mooney_rivlin import MooneyRivlin
from .neo_hookean import NeoHookean
from .ogden import Ogden, OgdenTerm
from .ogden_hyperfoam import HyperfoamTerm, OgdenHyperfoam
from .viscoelastic import prony_update, relaxation_function
from .yeoh import Yeoh

MATERIALS: dict[str, type[Material]] = {
    m.model: m for m in (LinearElastic, NeoHookean, MooneyRivlin, Yeoh, Ogden, OgdenHyperfoam)}


def material_from_dict(d: dict, where: str = "material") -> Material:
    """A material from its specification; errors name the key (`where` prefixes them)."""
    if not isinstance(d, dict) or "model" not in d:
        raise InputError(f"{where}: missing key 'model' (one of {', '.join(MATERIALS)})")
    model = d["model"]
    if model not in MATERIALS:
        raise InputError(f"{where}.model = {model!r}: allowed {', '.join(MATERIALS)}")
    return MATERIALS[model].from_dict(d, where)


__all__ = ["MATERIALS", "MODULI", "HyperfoamTerm", "LinearElastic", "Material", "MaterialConstants",
           "MooneyRivlin",
           "NeoHookean", "Ogden", "OgdenHyperfoam", "OgdenTerm", "PronyTerm", "Sym", "Yeoh",
           "energy_and_stress", "material_from_dict", "prony_update", "relaxation_function",
           "stress_parts"]
