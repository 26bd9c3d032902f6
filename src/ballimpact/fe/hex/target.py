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

from ...errors import InputError
from ...constitutive import Material, material_from_dict
from ...checks import check_keys, spec_number


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
        check_keys(d, {"name", "half_width_m", "layers"}, where)
        name = d.get("name", "target")
        width = spec_number(d, "half_width_m", where, 0.0, 10.0, low_open=True)
        raw = d.get("layers")
        if not isinstance(raw, list) or not raw:
            raise InputError(f"{where}.layers: expected a non-empty list of layers")
        layers = []
        for i, layer in enumerate(raw):
            w = f"{where}.layers[{i}]"
            check_keys(layer, {"name", "thickness_m", "density_kg_m3", "material"}, w)
            if "material" not in layer:
                raise InputError(f"{w}: missing key 'material'")
            layers.append(TargetLayer(
                name=str(layer.get("name", f"layer{i}")),
                thickness_m=spec_number(layer, "thickness_m", w, 0.0, 10.0, low_open=True),
                density_kg_m3=spec_number(layer, "density_kg_m3", w, 0.0, 1e5, low_open=True),
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
    if path.is_dir():
        raise InputError(f"--target {path}: a folder, not a target file (JSON)")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"--target {path}: no such file") from None
    except OSError as error:
        raise InputError(f"--target {path}: cannot read ({error.strerror or error})") from None
    except (ValueError, UnicodeDecodeError) as error:  # JSONDecodeError is a ValueError
        raise InputError(f"--target {path}: not valid JSON ({error})") from None
    return Target.from_dict(data, where=str(path))


def check_target_width(target: Target, ball) -> None:
    """A slab narrower than the ball: its contact nodes would lie beyond the slab's edge, where
    the contact has no surface to find (`InputError`)."""
    if target.half_width_m < ball.outer_radius_m:
        raise InputError(f"target {target.name!r}: half_width_m = {target.half_width_m:g} m is "
                         f"less than the ball's radius {ball.outer_radius_m:g} m; the slab must "
                         "reach beyond the contact patch (e.g. 3 ball radii)")
