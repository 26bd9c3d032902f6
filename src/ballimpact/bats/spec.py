"""A bat's specification (`BatSpec`) and `load_bat` (a preset name, a JSON or TOML file, or a
dict); docs/equipment.md, "The bat".

All values SI, x measured along the axis from the knob end. Keys:

- `name`, `length_m`, optional `description` and `source` (free text, kept);
- `profile`: [[x_m, outer_radius_m], ...], x strictly increasing from 0 to `length_m` (to the
  blade's first x for a cricket bat), the radius linear between points;
- `wall_thickness_m`: null or absent for a solid bat, a number for a hollow tube (constant wall);
- `material`: `youngs_modulus_pa`, `density_kg_m3` and `poissons_ratio` and/or
  `shear_modulus_pa` (wood: give G, much softer than E/2(1+nu)); optional `name`;
- `loss_factor`: optional, >= 0 (each flexural mode's damping ratio is half of it);
- `section`: "round" (default) or {"blade": {"width_m", "profile_thickness": [[x_m, t_m], ...]}}:
  a rectangular blade (width x thickness) from the blade's first x to `length_m`, the handle
  round (`profile`) before it.

Every refusal is an `InputError` of one line naming the key's path ("bat.profile[2][0] = ...").
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..checks import (check_keys, check_metres, check_range, is_finite_number, shown,
                      spec_number)
from ..fileio import packaged_json_files, read_spec_file
from ..errors import InputError

_TOP_KEYS = {"name", "description", "source", "length_m", "profile", "wall_thickness_m",
             "material", "loss_factor", "section"}
_MATERIAL_KEYS = {"name", "youngs_modulus_pa", "density_kg_m3", "poissons_ratio",
                  "shear_modulus_pa"}
_BLADE_KEYS = {"width_m", "profile_thickness"}
#: largest length (m) and radius, thickness or width (m) taken; a figure up to 1000 times more
#: is named as millimetres
MAX_LENGTH_M = 2.0
MAX_SECTION_M = 0.2
#: points of a profile closer than this to an end count as the end (m)
_END_TOL_M = 1e-6


@dataclass(frozen=True)
class BatMaterial:
    """An isotropic (or, for wood, along-the-grain) material: E, density, G; nu as given (None
    for wood given by G alone; the shear coefficient then takes nu = 0.3)."""

    youngs_modulus_pa: float
    density_kg_m3: float
    shear_modulus_pa: float
    poissons_ratio: float | None = None
    name: str = ""


@dataclass(frozen=True)
class Blade:
    """A cricket bat's blade: a rectangle `width_m` wide, `profile_thickness` ((x_m, t_m), ...)
    thick (linear between points), from its first x to the bat's length."""

    width_m: float
    profile_thickness: tuple[tuple[float, float], ...]

    @property
    def start_m(self) -> float:
        return self.profile_thickness[0][0]


@dataclass(frozen=True)
class BatSpec:
    """A bat: length, outer profile (round part), wall, material, damping, optional blade."""

    name: str
    length_m: float
    profile: tuple[tuple[float, float], ...]
    material: BatMaterial
    wall_thickness_m: float | None = None
    loss_factor: float = 0.0
    blade: Blade | None = None
    description: str = field(default="", compare=False)
    source: str = field(default="", compare=False)

    @property
    def round_end_m(self) -> float:
        """Where the round part ends: the length, or the blade's first x (the shoulder)."""
        return self.blade.start_m if self.blade is not None else self.length_m

    def breakpoints_m(self) -> tuple[float, ...]:
        """Every x where the section's taper changes (profile and blade points, ends)."""
        points = {x for x, _ in self.profile} | {0.0, self.length_m}
        if self.blade is not None:
            points |= {x for x, _ in self.blade.profile_thickness}
        return tuple(sorted(points))

    def to_dict(self) -> dict[str, Any]:
        m = self.material
        material = {"youngs_modulus_pa": m.youngs_modulus_pa, "density_kg_m3": m.density_kg_m3,
                    "shear_modulus_pa": m.shear_modulus_pa}
        if m.poissons_ratio is not None:
            material["poissons_ratio"] = m.poissons_ratio
        if m.name:
            material["name"] = m.name
        out: dict[str, Any] = {"name": self.name, "length_m": self.length_m,
                               "profile": [list(p) for p in self.profile],
                               "wall_thickness_m": self.wall_thickness_m, "material": material,
                               "loss_factor": self.loss_factor}
        if self.blade is not None:
            out["section"] = {"blade": {"width_m": self.blade.width_m, "profile_thickness": [
                list(p) for p in self.blade.profile_thickness]}}
        out.update({k: getattr(self, k) for k in ("description", "source") if getattr(self, k)})
        return out


def _text(d: dict, key: str, where: str, default: str = "") -> str:
    value = d.get(key, default)
    if not isinstance(value, str):
        raise InputError(f"{where}.{key}: expected a string, got {type(value).__name__}")
    return value


def _points(raw: Any, where: str, what: str, start: float, end: float, end_name: str
            ) -> tuple[tuple[float, float], ...]:
    """[[x_m, value_m], ...]: x strictly increasing from `start` to `end`, values in metres."""
    if not isinstance(raw, list) or len(raw) < 2:
        raise InputError(f"{where}: expected a list of at least 2 [x_m, {what}] points")
    out: list[tuple[float, float]] = []
    for i, point in enumerate(raw):
        if not isinstance(point, (list, tuple)) or len(point) != 2:
            raise InputError(f"{where}[{i}] = {shown(point)}: expected a pair [x_m, {what}]")
        x = check_range(f"{where}[{i}][0]", point[0], 0.0, MAX_LENGTH_M, unit="m")
        if out and x <= out[-1][0]:
            raise InputError(f"{where}[{i}][0] = {shown(x)}: x must be strictly increasing "
                             f"(the previous point's x is {shown(out[-1][0])} m)")
        out.append((x, check_metres(f"{where}[{i}][1]", point[1], MAX_SECTION_M)))
    for i, target, label in ((0, start, "start at"), (-1, end, "end at")):
        if abs(out[i][0] - target) > _END_TOL_M:
            index = 0 if i == 0 else len(out) - 1
            raise InputError(f"{where}[{index}][0] = {shown(out[i][0])}: the points must cover "
                             f"[{start:g}, {end:g}] m, so {label} {end_name if i else 'x'} = "
                             f"{target:g} (x from the knob end)")
    first, last = (start, out[0][1]), (end, out[-1][1])
    return (first, *out[1:-1], last)


def _material(d: Any, where: str) -> BatMaterial:
    check_keys(d, _MATERIAL_KEYS, where)
    e = spec_number(d, "youngs_modulus_pa", where, 0.0, low_open=True)
    rho = spec_number(d, "density_kg_m3", where, 0.0, 25000.0, low_open=True)
    if "poissons_ratio" not in d and "shear_modulus_pa" not in d:
        raise InputError(f"{where}: missing key 'poissons_ratio' or 'shear_modulus_pa' (give "
                         "one; wood: the shear modulus)")
    nu = spec_number(d, "poissons_ratio", where, -1.0, 0.5, True, True) \
        if "poissons_ratio" in d else None
    g = spec_number(d, "shear_modulus_pa", where, 0.0, low_open=True) \
        if "shear_modulus_pa" in d else e / (2.0 * (1.0 + nu))
    return BatMaterial(e, rho, g, nu, _text(d, "name", where))


def _blade(d: Any, where: str, length: float) -> Blade:
    check_keys(d, _BLADE_KEYS, where)
    if "width_m" not in d or "profile_thickness" not in d:
        missing = "width_m" if "width_m" not in d else "profile_thickness"
        raise InputError(f"{where}: missing key '{missing}'")
    width = check_metres(f"{where}.width_m", d["width_m"], MAX_SECTION_M)
    raw = d["profile_thickness"]
    start = raw[0][0] if (isinstance(raw, list) and raw and isinstance(raw[0], (list, tuple))
                          and raw[0] and is_finite_number(raw[0][0])) else 0.0
    if not 0.0 < start < length:
        raise InputError(f"{where}.profile_thickness[0][0] = {shown(start)}: the blade must "
                         f"start after the handle, allowed range (0, {length:g}) m")
    return Blade(width, _points(raw, f"{where}.profile_thickness", "thickness_m", start, length,
                                "length_m"))


def bat_from_dict(d: Any, where: str = "bat", default_name: str = "bat") -> BatSpec:
    """A bat from its specification; every error names the key's path from `where`."""
    check_keys(d, _TOP_KEYS, where)
    name = _text(d, "name", where, default_name)
    if not name.strip():
        raise InputError(f"{where}.name = {name!r}: expected a non-empty string")
    if "length_m" not in d:
        raise InputError(f"{where}: missing key 'length_m'")
    length = check_metres(f"{where}.length_m", d["length_m"], MAX_LENGTH_M)
    blade = None
    section = d.get("section", "round")
    if isinstance(section, dict):
        check_keys(section, {"blade"}, f"{where}.section")
        if "blade" not in section:
            raise InputError(f"{where}.section: missing key 'blade'")
        blade = _blade(section["blade"], f"{where}.section.blade", length)
    elif section != "round":
        raise InputError(f"{where}.section = {shown(section)}: expected \"round\" or "
                         "{\"blade\": {\"width_m\": ..., \"profile_thickness\": [...]}}")
    if "profile" not in d:
        raise InputError(f"{where}: missing key 'profile'")
    end, end_name = (length, "length_m") if blade is None else (blade.start_m, "the blade's start")
    profile = _points(d["profile"], f"{where}.profile", "outer_radius_m", 0.0, end, end_name)
    wall = d.get("wall_thickness_m")
    if wall is not None:
        wall = check_metres(f"{where}.wall_thickness_m", wall, MAX_SECTION_M)
        i, smallest = min(enumerate(r for _, r in profile), key=lambda item: item[1])
        if wall >= smallest:
            raise InputError(f"{where}.wall_thickness_m = {shown(wall)}: must be less than the "
                             f"smallest outer radius, {smallest:g} m at profile[{i}] (null for "
                             "a solid bat)")
    if "material" not in d:
        raise InputError(f"{where}: missing key 'material'")
    material = _material(d["material"], f"{where}.material")
    loss = check_range(f"{where}.loss_factor", d.get("loss_factor", 0.0), 0.0, 1.0,
                       high_open=True, note="damping loss factor, each mode's ratio is half")
    return BatSpec(name=name, length_m=length, profile=profile, material=material,
                   wall_thickness_m=wall, loss_factor=loss, blade=blade,
                   description=_text(d, "description", where),
                   source=_text(d, "source", where))


# ---- presets and files -------------------------------------------------------------------
_PRESET_FILES = packaged_json_files("data/bats")
#: the bats shipped in data/bats/ (name -> file name without .json)
PRESETS: tuple[str, ...] = tuple(_PRESET_FILES)


def preset_data(name: str) -> dict[str, Any]:
    """A preset's specification as stored (with its `source` and `description`)."""
    if name not in _PRESET_FILES:
        raise InputError(f"bat = {name!r}: not a preset ({', '.join(PRESETS)})")
    return json.loads(_PRESET_FILES[name].read_text(encoding="utf-8"))


def load_bat(spec: str | Path | dict | BatSpec) -> BatSpec:
    """A bat from a preset name (`PRESETS`), a JSON or TOML file (by suffix), a dict, or a
    `BatSpec` (returned as is)."""
    if isinstance(spec, BatSpec):
        return spec
    if isinstance(spec, dict):
        return bat_from_dict(spec)
    if isinstance(spec, str) and spec in PRESETS:
        return bat_from_dict(preset_data(spec), where=spec)
    if not isinstance(spec, (str, Path)):
        raise InputError(f"bat: expected a preset name, a file or a dict, got "
                         f"{type(spec).__name__}")
    path = Path(spec)
    if not path.is_file():
        raise InputError(f"bat = {str(spec)!r}: neither a preset ({', '.join(PRESETS)}) nor an "
                         "existing file")
    data = read_spec_file(path, "bat")
    try:
        return bat_from_dict(data, default_name=path.stem)
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None

