"""Material tests (uniaxial, biaxial, planar, volumetric, relaxation, creep, DMA) and the fits
that turn them into the constants of a ball's layer (docs: "Material tests and fits").
"""

from .data import MODES, MaterialTest, parse_spec, read_test
from .hyperelastic import HyperelasticFit, fit_hyperelastic
from .modes import material_stress

__all__ = ["MODES", "HyperelasticFit", "MaterialTest", "fit_hyperelastic", "material_stress",
           "parse_spec", "read_test"]
