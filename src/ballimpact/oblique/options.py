"""Settings of the 3D solver: `fe.options.Options3D` (the impact condition and the settings both
engines share are `fe.options`' too)."""

from ..fe.options import ImpactCondition, Options3D

__all__ = ["ImpactCondition", "Options3D"]
