"""Deformable targets: a flat layered slab (pads, pitches, plates) with a fixed base.

Specification (JSON), layers from the top down:

    {"name": "pad", "half_width_m": 0.1,
     "layers": [{"name": "foam", "thickness_m": 0.02, "density_kg_m3": 100,
                 "material": {...as in a ball file...}}, ...]}
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..fe.materials import Material, material_from_dict
from ..fe.materials.base import _check_keys, _number


@dataclass(frozen=True)
class TargetLayer:
    name: str
    thickness_m: float
    density_kg_m3: float
    material: Material


@dataclass(frozen=True)
class Target:
    """A flat slab under z = 0, layers from the top down, base fixed."""

    name: str
    half_width_m: float
    layers: tuple[TargetLayer, ...]

    @property
    def thickness_m(self) -> float:
        return sum(layer.thickness_m for layer in self.layers)

    @classmethod
    def from_dict(cls, d: Any, where: str = "target") -> Target:
        _check_keys(d, {"name", "half_width_m", "layers"}, where)
        name = d.get("name", "target")
        width = _number(d, "half_width_m", where, 0.0, 10.0, low_open=True)
        raw = d.get("layers")
        if not isinstance(raw, list) or not raw:
            raise InputError(f"{where}.layers: expected a non-empty list of layers")
        layers = []
        for i, layer in enumerate(raw):
            w = f"{where}.layers[{i}]"
            _check_keys(layer, {"name", "thickness_m", "density_kg_m3", "material"}, w)
            if "material" not in layer:
                raise InputError(f"{w}: missing key 'material'")
            layers.append(TargetLayer(
                name=str(layer.get("name", f"layer{i}")),
                thickness_m=_number(layer, "thickness_m", w, 0.0, 10.0, low_open=True),
                density_kg_m3=_number(layer, "density_kg_m3", w, 0.0, 1e5, low_open=True),
                material=material_from_dict(layer["material"], f"{w}.material")))
        return cls(name=str(name), half_width_m=width, layers=tuple(layers))

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "half_width_m": self.half_width_m,
                "layers": [{"name": layer.name, "thickness_m": layer.thickness_m,
                            "density_kg_m3": layer.density_kg_m3,
                            "material": layer.material.to_dict()} for layer in self.layers]}


def load_target(path) -> Target:
    """A target from a JSON file (errors name the file and the key)."""
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise InputError(f"--target {path}: no such file") from None
    except json.JSONDecodeError as error:
        raise InputError(f"--target {path}: not valid JSON ({error})") from None
    return Target.from_dict(data, where=str(path))
