"""Deformable targets: a flat layered slab (pads, pitches, plates) with a fixed base, or a base
carried by a free rigid mass (protective equipment: a helmet's shell and liner on a headform, a
glove on a hand, a pad on a leg).

Specification (JSON), layers from the top down:

    {"name": "pad", "half_width_m": 0.1,
     "layers": [{"name": "foam", "thickness_m": 0.02, "density_kg_m3": 100,
                 "material": {...as in a ball file...}}, ...],
     "backing": {"mass_kg": 5.0, "spring_n_m": 0.0, "damper_n_s_m": 0.0}}

`backing` (optional; without it the base is fixed): the slab's base nodes move together along z
only (their x and y stay fixed) as one rigid body of mass `mass_kg` plus their own lumped mass,
tied to the ground by a spring `spring_n_m` and a damper `damper_n_s_m` (default 0: free):
(M + m_base) z'' = -F_t - k z - c z', with F_t the force the slab puts on the base, positive
pushing it down (-z). The kernel's histories then gain the backing's z (m), velocity (m/s),
acceleration (m/s^2), F_t (`transmitted_force_n`), its energies and the target's momentum
(`fe.hex.kernel.BACKING_HISTORY`).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ...errors import InputError
from ...fileio import packaged_json_files
from ...constitutive import Material, material_from_dict
from ...checks import (check_keys, check_range, is_finite_number, range_text, shown,
                       spec_metres, spec_number)


@dataclass(frozen=True)
class TargetLayer:
    name: str
    thickness_m: float
    density_kg_m3: float
    material: Material


#: the largest backing mass (kg); above it a value looks like grams
MAX_BACKING_KG = 1000.0


@dataclass(frozen=True)
class Backing:
    """A free rigid mass under a slab's base (kg), with a spring (N/m) and a damper (N s/m) to
    the ground. Checked by `from_dict` only: the dataclass itself takes any value (a test's
    1e6 kg backing, standing in for the fixed base)."""

    mass_kg: float
    spring_n_m: float = 0.0
    damper_n_s_m: float = 0.0

    @classmethod
    def from_dict(cls, d: Any, where: str = "target.backing") -> Backing:
        check_keys(d, {"mass_kg", "spring_n_m", "damper_n_s_m"}, where)
        if "mass_kg" not in d:
            raise InputError(f"{where}: missing key 'mass_kg' (the backing's mass, kg)")
        mass = d["mass_kg"]
        if is_finite_number(mass) and MAX_BACKING_KG < mass <= 1e6 * MAX_BACKING_KG:
            raise InputError(range_text(f"{where}.mass_kg", mass, "allowed range", 0.0,
                                        MAX_BACKING_KG, low_open=True, unit="kg")
                             + f"; {shown(mass)} looks like grams: use {mass / 1000:g} for "
                               f"{shown(mass)} g")
        return cls(mass_kg=check_range(f"{where}.mass_kg", mass, 0.0, MAX_BACKING_KG,
                                       low_open=True, unit="kg"),
                   spring_n_m=check_range(f"{where}.spring_n_m", d.get("spring_n_m", 0.0), 0.0,
                                          unit="N/m"),
                   damper_n_s_m=check_range(f"{where}.damper_n_s_m", d.get("damper_n_s_m", 0.0),
                                            0.0, unit="N s/m"))

    def to_dict(self) -> dict[str, Any]:
        return {"mass_kg": self.mass_kg, "spring_n_m": self.spring_n_m,
                "damper_n_s_m": self.damper_n_s_m}


@dataclass(frozen=True)
class Target:
    """A flat slab under z = 0, layers from the top down, base fixed (or carried by a free
    rigid `backing`)."""

    name: str
    half_width_m: float
    layers: tuple[TargetLayer, ...]
    backing: Backing | None = None
    sphere_radius_m: float | None = None
    description: str = ""
    source: str = ""

    @property
    def thickness_m(self) -> float:
        return sum(layer.thickness_m for layer in self.layers)

    @classmethod
    def from_dict(cls, d: Any, where: str = "target") -> Target:
        check_keys(d, {"name", "half_width_m", "layers", "backing", "sphere_radius_m",
                       "description", "source"}, where)
        name = d.get("name", "target")
        width = spec_metres(d, "half_width_m", where, 10.0)
        radius = d.get("sphere_radius_m")
        if radius is not None:
            # the cap's edge at most 90 degrees from its top (half_width_m is an arc length)
            radius = spec_metres(d, "sphere_radius_m", where, 10.0, low=2.0 * width / math.pi)
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
                thickness_m=spec_metres(layer, "thickness_m", w, 10.0),
                density_kg_m3=spec_number(layer, "density_kg_m3", w, 0.0, 1e5, low_open=True),
                material=material_from_dict(layer["material"], f"{w}.material")))
        backing = (Backing.from_dict(d["backing"], f"{where}.backing") if "backing" in d
                   else None)
        if radius is not None and radius <= sum(layer.thickness_m for layer in layers):
            raise InputError(f"{where}.sphere_radius_m = {radius:g}: must exceed the layers' "
                             "total thickness (the cap's inner surface)")
        return cls(name=str(name), half_width_m=width, layers=tuple(layers), backing=backing,
                   sphere_radius_m=radius, description=str(d.get("description", "")),
                   source=str(d.get("source", "")))

    def to_dict(self) -> dict[str, Any]:
        out = {"name": self.name, "half_width_m": self.half_width_m,
               "layers": [{"name": layer.name, "thickness_m": layer.thickness_m,
                           "density_kg_m3": layer.density_kg_m3,
                           "material": layer.material.to_dict()} for layer in self.layers]}
        if self.backing is not None:
            out["backing"] = self.backing.to_dict()
        if self.sphere_radius_m is not None:
            out["sphere_radius_m"] = self.sphere_radius_m
        out.update({k: getattr(self, k) for k in ("description", "source") if getattr(self, k)})
        return out


_PRESET_FILES = packaged_json_files("data/targets")
#: the targets shipped in data/targets/ (name -> file name without .json)
PRESETS: tuple[str, ...] = tuple(_PRESET_FILES)


def load_target(path) -> Target:
    """A target from a preset name (`PRESETS`) or a JSON file (errors name the file and the
    key)."""
    if isinstance(path, str) and path in PRESETS:
        data = json.loads(_PRESET_FILES[path].read_text(encoding="utf-8"))
        return Target.from_dict(data, where=path)
    path = Path(path)
    if path.is_dir():
        raise InputError(f"--target {path}: a folder, not a target file (JSON)")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"--target {path}: neither a preset ({', '.join(PRESETS)}) nor an "
                         "existing file") from None
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
