"""Layered ball models (docs/balls.md: the ball specification) and the built-in presets.

A ball is a stack of concentric spherical layers listed from the centre outwards; each has an outer
radius, a density and a material (`materials.material_from_dict`). Constants are SI throughout:
the thesis gives stresses in MPa and densities in T/mm^3 (1 T/mm^3 = 1e12 kg/m^3), converted here.

Presets (usable wherever a ball file is; `describe_presets()` lists them):

- `cricket-3layer`: thesis chapter 5. Radii and densities from table 5-1 (a Kookaburra ball:
  diameters 40, 62, 72 mm; 8.65, 6.68, 11.32 x 1e-10 T/mm^3), materials from sections 5.2.1-5.2.3.
  Its mass is 0.170 kg, as table 5-1's layer masses 29 + 61 + 80 g: heavier than the 0.160 kg of
  the universal model and of a regulation ball (155.9-163 g); the thesis does not comment on it.
- `cricket-universal`: thesis chapter 7, table 7-3. One homogeneous 72 mm layer whose density
  gives exactly 0.160 kg; Mooney-Rivlin (D1 = 0) with one Prony term, the four rows (5.5, 10, 20.8,
  25 m/s) interpolated linearly in impact speed. Outside 5.5-25 m/s the end row is held and an
  `InputWarning` is emitted. The thesis does not say whether its constants are long-term or
  instantaneous; `long_term` is the default here (`BallModel.with_moduli` switches).
- Balls of other sports (`SPORTS_PRESETS`: `baseball`, `softball-44-375`, `softball-47-375`,
  `softball-52-300`, `field-hockey`, `lacrosse`, `cricket-men`, `cricket-women`,
  `cricket-junior`): ball files in `data/presets/`, written once by
  `examples/make_sports_presets.py`. Each is a homogeneous universal ball at the middle of its
  rule's size and mass limits (`data/sports_balls.json`); its constants are calibrated by FE runs
  to a published COR and compression (`standards.specification`: the baseball and the softball
  classes), or identified by the universal model from a stated COR and dynamic stiffness at
  26.8 m/s (`universal.targets.constants_for`); stated values, not measured here. The file's
  `description` and `source` say which, and what the FE check of the written ball gave.
"""

from __future__ import annotations

import dataclasses
import json
import math
import numbers
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..fileio import packaged_json_files, read_spec_file
from ..errors import InputError, InputWarning
from ..checks import check_allow
from .checks import check_ball
from ..constitutive import MODULI, Material, material_from_dict
from ..checks import check_keys, spec_number
from ..checks import shown

_BALL_KEYS = {"name", "layers"}
_LAYER_KEYS = {"name", "outer_radius_m", "density_kg_m3", "material"}
#: free text kept with the ball (`BallModel.description`, `.source`); not used by the solver
_TEXT_KEYS = {"description", "source"}
#: figures that follow from the other keys, as `ballimpact balls --json` writes them: accepted in
#: a ball file if they agree with the ball (a check, never an input)
_DERIVED_BALL_KEYS = {"outer_radius_m", "mass_kg", "moduli", "needs_impact_speed"}
_DERIVED_LAYER_KEYS = {"mass_kg", "model"}
_DERIVED_TABLE_BALL_KEYS = _DERIVED_BALL_KEYS | {"speed_range_m_s"}


def _text(d: dict, key: str, where: str) -> str:
    value = d.get(key, "")
    if not isinstance(value, str):
        raise InputError(f"{where}.{key}: expected a string, got {type(value).__name__}")
    return value


def _check_derived(d: dict, where: str, actual: dict[str, Any]) -> None:
    """Each key of `actual` that `d` has must agree with the value that follows from the ball
    (numbers to 1e-6 relative)."""
    def agrees(given, value) -> bool:
        if isinstance(value, (bool, str)):
            return given == value and type(given) is type(value)
        if isinstance(value, (list, tuple)):
            return (isinstance(given, list) and len(given) == len(value)
                    and all(agrees(g, v) for g, v in zip(given, value)))
        return (isinstance(given, (int, float)) and not isinstance(given, bool)
                and math.isclose(given, value, rel_tol=1e-6))

    for key, value in actual.items():
        if key in d and not agrees(d[key], value):
            grams = (key == "mass_kg" and isinstance(d[key], (int, float)) and value > 0
                     and math.isclose(d[key] / value, 1e3, rel_tol=0.01))
            raise InputError(
                f"{where}.{key} = {shown(d[key])}: disagrees with {shown(value)}, which follows "
                "from the other keys" + (" (it looks like grams given as kg)" if grams else "")
                + "; it is only checked (as `ballimpact balls --json` writes it), never used: "
                "remove it or correct it")


def _shell_volume_m3(inner_m: float, outer_m: float) -> float:
    return 4.0 / 3.0 * math.pi * (outer_m ** 3 - inner_m ** 3)


@dataclass(frozen=True)
class Layer:
    """One spherical shell (or the central sphere): its outer radius, density and material."""

    name: str
    outer_radius_m: float
    density_kg_m3: float
    material: Material

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "outer_radius_m": self.outer_radius_m,
                "density_kg_m3": self.density_kg_m3, "material": self.material.to_dict()}

    @classmethod
    def from_dict(cls, d: Any, where: str = "layer", previous_radius_m: float = 0.0,
                  default_name: str = "layer") -> Layer:
        check_keys(d, _LAYER_KEYS | _DERIVED_LAYER_KEYS, where)
        name = d.get("name", default_name)
        if not isinstance(name, str) or not name.strip():
            raise InputError(f"{where}.name = {name!r}: expected a non-empty string")
        radius = spec_number(d, "outer_radius_m", where, 0.0, low_open=True)
        if radius <= previous_radius_m:
            raise InputError(f"{where}.outer_radius_m = {radius:g}: must be greater than the "
                             f"previous layer's {previous_radius_m:g}")
        density = spec_number(d, "density_kg_m3", where, 0.0, low_open=True)
        if "material" not in d:
            raise InputError(f"{where}: missing key 'material'")
        material = material_from_dict(d["material"], where=f"{where}.material")
        _check_derived(d, where, {"model": material.model, "mass_kg": density * _shell_volume_m3(
            previous_radius_m, radius)})
        return cls(name=name, outer_radius_m=radius, density_kg_m3=density, material=material)


@dataclass(frozen=True)
class BallModel:
    """A layered ball, layers from the centre outwards (bonded at the interfaces).

    `description` and `source` are free text carried along (ball files, `balls --json`); they
    take no part in comparisons: two balls with the same layers are equal."""

    name: str
    layers: tuple[Layer, ...]
    description: str = field(default="", compare=False)
    source: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "layers", tuple(self.layers))
        if not self.layers:
            raise InputError(f"ball {self.name!r}: at least one layer is needed")
        previous = 0.0
        names = set()
        for i, layer in enumerate(self.layers):
            where = f"{self.name}.layers[{i}]"
            if not isinstance(layer, Layer):
                raise InputError(f"{where}: expected a Layer, got {type(layer).__name__}")
            r, rho = layer.outer_radius_m, layer.density_kg_m3
            if not (math.isfinite(r) and r > previous):
                raise InputError(f"{where}.outer_radius_m = {r:g}: must be greater than the "
                                 f"previous layer's {previous:g}")
            if not (math.isfinite(rho) and rho > 0.0):
                raise InputError(f"{where}.density_kg_m3 = {rho:g}: allowed range (0, inf)")
            if layer.name in names:
                raise InputError(f"{where}.name = {layer.name!r}: layer names must be unique")
            names.add(layer.name)
            previous = r

    # ---- geometry and mass -----------------------------------------------------------------
    @property
    def outer_radius_m(self) -> float:
        return self.layers[-1].outer_radius_m

    @property
    def layer_radii_m(self) -> tuple[float, ...]:
        """Outer radius of each layer, from the centre out."""
        return tuple(layer.outer_radius_m for layer in self.layers)

    @property
    def layer_masses_kg(self) -> tuple[float, ...]:
        inner = (0.0, *self.layer_radii_m[:-1])
        return tuple(layer.density_kg_m3 * _shell_volume_m3(r0, layer.outer_radius_m)
                     for r0, layer in zip(inner, self.layers))

    @property
    def mass_kg(self) -> float:
        """Sum of density x shell volume over the layers (exact spheres, not a mesh)."""
        return float(sum(self.layer_masses_kg))

    @property
    def moduli(self) -> tuple[str, ...]:
        """The convention of each layer's constants (`long_term` or `instantaneous`)."""
        return tuple(layer.material.moduli for layer in self.layers)

    def homogeneous(self) -> bool:
        """True for one layer, or layers that all share the same density and material."""
        first = self.layers[0]
        return all(layer.density_kg_m3 == first.density_kg_m3
                   and layer.material == first.material for layer in self.layers[1:])

    # ---- variants ----------------------------------------------------------------------------
    def with_moduli(self, moduli: str) -> BallModel:
        """The same constants read in another convention (`long_term` or `instantaneous`)."""
        if moduli not in MODULI:
            raise InputError(f"moduli = {moduli!r}: allowed {', '.join(MODULI)}")
        layers = tuple(dataclasses.replace(layer, material=dataclasses.replace(
            layer.material, moduli=moduli)) for layer in self.layers)
        return dataclasses.replace(self, layers=layers)

    # ---- specification -----------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"name": self.name}
        out.update({key: getattr(self, key) for key in ("description", "source")
                    if getattr(self, key)})
        out["layers"] = [layer.to_dict() for layer in self.layers]
        return out

    @classmethod
    def from_dict(cls, d: Any, where: str = "ball", default_name: str = "ball") -> BallModel:
        """A ball from its specification; every error names the key's path from `where`.
        Besides `name` and `layers`: `description` and `source` (kept), and the figures that
        `ballimpact balls --json` adds (checked against the ball, see docs/balls.md)."""
        check_keys(d, _BALL_KEYS | _TEXT_KEYS | _DERIVED_BALL_KEYS, where)
        name = d.get("name", default_name)
        if not isinstance(name, str) or not name.strip():
            raise InputError(f"{where}.name = {name!r}: expected a non-empty string")
        if "layers" not in d:
            raise InputError(f"{where}: missing key 'layers'")
        raw = d["layers"]
        if not isinstance(raw, list) or not raw:
            raise InputError(f"{where}.layers: expected a non-empty list of layers "
                             f"({', '.join(sorted(_LAYER_KEYS))})")
        layers: list[Layer] = []
        previous = 0.0
        for i, item in enumerate(raw):
            w = f"{where}.layers[{i}]"
            layer = Layer.from_dict(item, w, previous_radius_m=previous, default_name=f"layer{i}")
            if any(layer.name == other.name for other in layers):
                raise InputError(f"{w}.name = {layer.name!r}: layer names must be unique")
            layers.append(layer)
            previous = layer.outer_radius_m
        ball = cls(name=name, layers=tuple(layers), description=_text(d, "description", where),
                   source=_text(d, "source", where))
        moduli = ball.moduli
        _check_derived(d, where, {
            "outer_radius_m": ball.outer_radius_m, "mass_kg": ball.mass_kg,
            "moduli": moduli[0] if len(set(moduli)) == 1 else list(moduli),
            "needs_impact_speed": False})
        return ball


# ---- presets ---------------------------------------------------------------------------------
_SPORTS_FILES = packaged_json_files("data/presets")
#: balls of other sports, each a ball file in `data/presets/` (see the module docstring)
SPORTS_PRESETS: tuple[str, ...] = tuple(_SPORTS_FILES)
PRESETS: tuple[str, ...] = ("cricket-3layer", "cricket-universal", *SPORTS_PRESETS)


def _sports_preset_data(name: str) -> dict[str, Any]:
    data = json.loads(_SPORTS_FILES[name].read_text(encoding="utf-8"))
    if data.get("name") != name:  # a renamed file would load under another name
        raise InputError(f"preset {name}: its file names the ball {data.get('name')!r}")
    return data

_MPA = 1e6
_T_PER_MM3 = 1e12  # kg/m^3

CRICKET_3LAYER_SPEC: dict[str, Any] = {
    "name": "cricket-3layer",
    "layers": [
        {"name": "core", "outer_radius_m": 0.020, "density_kg_m3": 8.65e-10 * _T_PER_MM3,
         "material": {"model": "mooney_rivlin", "c10_pa": 4.72 * _MPA, "c01_pa": -0.45 * _MPA,
                      "d1_per_pa": 0.0, "moduli": "long_term",
                      "prony": [{"g": 0.41, "k": 0.0, "tau_s": 7e-5}]}},
        {"name": "midsole", "outer_radius_m": 0.031, "density_kg_m3": 6.68e-10 * _T_PER_MM3,
         "material": {"model": "ogden_hyperfoam", "moduli": "long_term",
                      "terms": [{"mu_pa": 70.3 * _MPA, "alpha": 4.0, "nu": 0.0}],
                      "prony": [{"g": 0.0, "k": 0.0, "tau_s": 4.1e-4}]}},
        {"name": "cover", "outer_radius_m": 0.036, "density_kg_m3": 11.32e-10 * _T_PER_MM3,
         "material": {"model": "mooney_rivlin", "c10_pa": 4.5 * _MPA, "c01_pa": -0.5 * _MPA,
                      "d1_per_pa": 0.0, "moduli": "long_term"}},
    ],
}

UNIVERSAL_RADIUS_M = 0.036
UNIVERSAL_MASS_KG = 0.160
UNIVERSAL_DENSITY_KG_M3 = UNIVERSAL_MASS_KG / _shell_volume_m3(0.0, UNIVERSAL_RADIUS_M)

# Thesis table 7-3 (MPa converted to Pa): one row per impact speed.
TABLE_7_3: tuple[dict[str, float], ...] = (
    {"speed_m_s": 5.5, "c10_pa": 5.24e6, "c01_pa": -0.51e6, "g1": 0.75, "tau1_s": 7e-5},
    {"speed_m_s": 10.0, "c10_pa": 6.12e6, "c01_pa": -0.35e6, "g1": 0.78, "tau1_s": 7e-5},
    {"speed_m_s": 20.8, "c10_pa": 4.75e6, "c01_pa": -0.47e6, "g1": 0.78, "tau1_s": 7e-5},
    {"speed_m_s": 25.0, "c10_pa": 4.02e6, "c01_pa": -0.41e6, "g1": 0.79, "tau1_s": 8e-5},
)
_TABLE_KEYS = ("c10_pa", "c01_pa", "g1", "tau1_s")

_DESCRIPTIONS = {
    "cricket-3layer": (
        "Three-layer Kookaburra cricket ball (thesis chapter 5): cork-rubber core (Mooney-Rivlin "
        "with one Prony term), cork-and-twine midsole (one-term Ogden hyperfoam), leather cover "
        "(Mooney-Rivlin). Mass 0.170 kg, as table 5-1's layer masses 29 + 61 + 80 g."),
    "cricket-universal": (
        "Universal (homogeneous) cricket ball, 72 mm and 0.160 kg (thesis chapter 7): "
        "Mooney-Rivlin (D1 = 0) with one Prony term, table 7-3 interpolated linearly in impact "
        "speed between 5.5 and 25 m/s (end rows held outside, with a warning). Needs the impact "
        "speed."),
}
_SOURCES = {
    "cricket-3layer": "thesis table 5-1 (radii, densities); sections 5.2.1-5.2.3 (materials)",
    "cricket-universal": "thesis table 7-3 (material parameters against impact speed)",
}


def _speed(value: Any, what: str = "impact_speed_m_s") -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) \
            or not math.isfinite(value) or value <= 0.0:
        raise InputError(f"{what} = {shown(value)}: expected a finite number > 0 (m/s)")
    return float(value)


def universal_parameters(impact_speed_m_s: float, table=TABLE_7_3,
                         name: str = "cricket-universal") -> dict[str, float]:
    """A universal-ball table (default: thesis table 7-3) interpolated linearly at an impact
    speed (SI: Pa, s). Rows hold speed_m_s, c10_pa, c01_pa, g1, tau1_s, by increasing speed.

    Outside the table's speeds the end row is held and an `InputWarning` is emitted.
    Returns impact_speed_m_s, c10_pa, c01_pa, g1, tau1_s.
    """
    v = _speed(impact_speed_m_s)
    speeds = np.array([row["speed_m_s"] for row in table])
    if v < speeds[0] or v > speeds[-1]:
        source = " (thesis table 7-3)" if table is TABLE_7_3 else ""
        warnings.warn(f"{name}: impact speed {v:g} m/s is outside the table's "
                      f"{speeds[0]:g}-{speeds[-1]:g} m/s{source}; the end row is held",
                      InputWarning, stacklevel=2)
    out = {"impact_speed_m_s": v}
    for key in _TABLE_KEYS:
        out[key] = float(np.interp(v, speeds, [row[key] for row in table]))
    return out


def universal_spec(params: dict[str, float], radius_m: float, density_kg_m3: float,
                   moduli: str = "long_term", name: str = "universal") -> dict[str, Any]:
    """The ball specification of a universal ball: one homogeneous Mooney-Rivlin layer (D1 = 0)
    with one Prony term (`params`: c10_pa, c01_pa, g1, tau1_s)."""
    material = {"model": "mooney_rivlin", "c10_pa": float(params["c10_pa"]),
                "c01_pa": float(params["c01_pa"]), "d1_per_pa": 0.0, "moduli": moduli,
                "prony": [{"g": float(params["g1"]), "k": 0.0, "tau_s": float(params["tau1_s"])}]}
    return {"name": name, "layers": [{"name": "ball", "outer_radius_m": float(radius_m),
                                      "density_kg_m3": float(density_kg_m3),
                                      "material": material}]}


def _universal(impact_speed_m_s: float) -> BallModel:
    p = universal_parameters(impact_speed_m_s)
    spec = universal_spec(p, UNIVERSAL_RADIUS_M, UNIVERSAL_DENSITY_KG_M3,
                          name=f"cricket-universal@{float(p['impact_speed_m_s'])!r}m/s")  # @25.0m/s
    return BallModel.from_dict(spec, where="cricket-universal")


_SPEED_TABLE_KEYS = {"outer_radius_m", "density_kg_m3", "moduli", "rows"}


def _speed_table_ball(data: dict, name: str, impact_speed_m_s: float | None) -> BallModel:
    """A ball file holding a universal-ball table against speed (as `identify` writes it):
    {"name": ..., "speed_table": {"outer_radius_m", "density_kg_m3", "moduli", "rows": [{speed_m_s,
    c10_pa, c01_pa, g1, tau1_s}, ...]}}, interpolated at the impact speed as `cricket-universal`.
    `description` and `source` are kept; the figures `balls --json` adds are checked."""
    check_keys(data, {"name", "speed_table"} | _TEXT_KEYS | _DERIVED_TABLE_BALL_KEYS, name)
    description, source = _text(data, "description", name), _text(data, "source", name)
    table = data["speed_table"]
    where = f"{name}.speed_table"
    check_keys(table, _SPEED_TABLE_KEYS, where)
    for key in ("outer_radius_m", "density_kg_m3"):
        spec_number(table, key, where, 0.0, low_open=True)
    rows = table.get("rows")
    if not isinstance(rows, list) or not rows:
        raise InputError(f"{where}.rows: expected a non-empty list of rows")
    for i, row in enumerate(rows):  # each row's constants are checked again as a material
        check_keys(row, {"speed_m_s", *_TABLE_KEYS}, f"{where}.rows[{i}]")
        for key in ("speed_m_s", *_TABLE_KEYS):
            spec_number(row, key, f"{where}.rows[{i}]")
        _speed(row["speed_m_s"], f"{where}.rows[{i}].speed_m_s")
    rows = sorted(rows, key=lambda r: r["speed_m_s"])
    radius, density = table["outer_radius_m"], table["density_kg_m3"]
    _check_derived(data, name, {
        "outer_radius_m": radius, "mass_kg": density * _shell_volume_m3(0.0, radius),
        "moduli": table.get("moduli", "long_term"), "needs_impact_speed": True,
        "speed_range_m_s": [rows[0]["speed_m_s"], rows[-1]["speed_m_s"]]})
    if impact_speed_m_s is None:
        raise InputError(f"{name}: a ball with a speed table needs the impact speed "
                         "(impact_speed_m_s, e.g. --speed-m-s)")
    p = universal_parameters(impact_speed_m_s, rows, name)
    spec = universal_spec(p, table["outer_radius_m"], table["density_kg_m3"],
                          table.get("moduli", "long_term"),
                          name=f"{name}@{float(p['impact_speed_m_s'])!r}m/s")
    return dataclasses.replace(BallModel.from_dict(spec, where=where), description=description,
                               source=source)


_UNIVERSAL_AT = re.compile(r"^cricket-universal@(.+?)(?:m/s)?$")


def _preset(name: str, impact_speed_m_s: float | None) -> BallModel:
    if name in SPORTS_PRESETS:
        return BallModel.from_dict(_sports_preset_data(name), where=name)
    if name == "cricket-3layer":
        return BallModel.from_dict(CRICKET_3LAYER_SPEC, where="cricket-3layer")
    match = _UNIVERSAL_AT.match(name)
    if match:  # a name as recorded by a loaded universal model, e.g. "cricket-universal@25.0m/s"
        try:
            speed = float(match.group(1))
        except ValueError:
            raise InputError(f"ball = {name!r}: cannot read the impact speed after '@'") from None
        if impact_speed_m_s is not None and not math.isclose(speed, impact_speed_m_s):
            raise InputError(f"ball = {name!r}: the speed in the name disagrees with "
                             f"impact_speed_m_s = {impact_speed_m_s:g}")
        return _universal(speed)
    if impact_speed_m_s is None:
        raise InputError("cricket-universal needs the impact speed (impact_speed_m_s, "
                         "e.g. --speed-m-s)")
    return _universal(impact_speed_m_s)


def load_ball(spec: str | Path | dict, impact_speed_m_s: float | None = None, *,
              allow=()) -> BallModel:
    """A ball from a preset name, a JSON or TOML file (by suffix; JSON otherwise), or a dict.

    `impact_speed_m_s` is needed by speed-dependent presets (`cricket-universal`) and ignored by
    the others. A universal model's recorded name ("cricket-universal@25.0m/s") loads again.
    Errors are `InputError`s naming the key's path ("ball.layers[1].outer_radius_m ...").

    Every ball loaded passes the `ball-units` plausibility check (`balls.checks.check_ball`:
    radius, mass, densities and moduli inside the ranges of solid sports balls, so that a ball
    written in millimetres or MPa is caught before it is meshed); with "ball-units" in `allow`
    a failure is an `InputWarning` instead.
    """
    allow = check_allow(allow)
    if impact_speed_m_s is not None:
        impact_speed_m_s = _speed(impact_speed_m_s)
    if isinstance(spec, dict):
        if "speed_table" in spec:
            ball = _speed_table_ball(spec, str(spec.get("name", "ball")), impact_speed_m_s)
        else:
            ball = BallModel.from_dict(spec)
        check_ball(ball, allow, where="ball")
        return ball
    if isinstance(spec, str) and (spec in PRESETS or spec.startswith("cricket-universal@")):
        ball = _preset(spec, impact_speed_m_s)
        check_ball(ball, allow, where=spec)
        return ball
    if not isinstance(spec, (str, Path)):
        raise InputError(f"ball: expected a preset name, a file or a dict, got "
                         f"{type(spec).__name__}")
    path = Path(spec)
    if path.is_dir():
        raise InputError(f"ball = {str(spec)!r}: a folder, not a ball file (JSON or TOML)")
    if not path.is_file():
        raise InputError(f"ball = {str(spec)!r}: neither a preset ({', '.join(PRESETS)}) nor an "
                         f"existing file")
    data = read_spec_file(path, "ball")
    try:
        if isinstance(data, dict) and "speed_table" in data:
            ball = _speed_table_ball(data, str(data.get("name", path.stem)), impact_speed_m_s)
        elif not isinstance(data, dict):
            raise InputError(f"expected a ball specification (an object with 'layers', or "
                             f"'speed_table'; docs/balls.md), got a {_json_type(data)}")
        else:
            ball = BallModel.from_dict(data, default_name=path.stem)
        check_ball(ball, allow, where="ball")
    except InputError as exc:
        raise InputError(f"{path}: {exc}") from None
    return ball


def _json_type(value: Any) -> str:
    """The JSON name of a parsed value's type (a list is an 'array', a dict an 'object')."""
    names = {list: "JSON array", str: "string", bool: "boolean", type(None): "null",
             int: "number", float: "number"}
    return names.get(type(value), type(value).__name__)


def describe_presets() -> list[dict[str, Any]]:
    """The built-in balls, JSON-able (for `ballimpact balls --json`). Each entry, saved as a
    file, is a ball file that loads to the preset (`cricket-universal`'s as a speed table)."""
    out = []
    three = _preset("cricket-3layer", None)
    out.append({
        "name": "cricket-3layer", "description": _DESCRIPTIONS["cricket-3layer"],
        "source": _SOURCES["cricket-3layer"], "needs_impact_speed": False,
        "outer_radius_m": three.outer_radius_m, "mass_kg": three.mass_kg,
        "moduli": "long_term",
        "layers": [{"name": layer.name, "outer_radius_m": layer.outer_radius_m,
                    "density_kg_m3": layer.density_kg_m3, "mass_kg": m,
                    "model": layer.material.model, "material": layer.material.to_dict()}
                   for layer, m in zip(three.layers, three.layer_masses_kg)]})
    out.append({
        "name": "cricket-universal", "description": _DESCRIPTIONS["cricket-universal"],
        "source": _SOURCES["cricket-universal"], "needs_impact_speed": True,
        "outer_radius_m": UNIVERSAL_RADIUS_M, "mass_kg": UNIVERSAL_MASS_KG,
        "moduli": "long_term",
        "speed_range_m_s": [TABLE_7_3[0]["speed_m_s"], TABLE_7_3[-1]["speed_m_s"]],
        "speed_table": {"outer_radius_m": UNIVERSAL_RADIUS_M,
                        "density_kg_m3": UNIVERSAL_DENSITY_KG_M3, "moduli": "long_term",
                        "rows": [dict(row) for row in TABLE_7_3]}})
    for name in SPORTS_PRESETS:  # written as `balls --json` writes a layered ball: checks added
        ball = _preset(name, None)
        out.append({
            "name": name, "description": ball.description, "source": ball.source,
            "needs_impact_speed": False, "outer_radius_m": ball.outer_radius_m,
            "mass_kg": ball.mass_kg, "moduli": ball.moduli[0],
            "layers": [{"name": layer.name, "outer_radius_m": layer.outer_radius_m,
                        "density_kg_m3": layer.density_kg_m3, "mass_kg": m,
                        "model": layer.material.model, "material": layer.material.to_dict()}
                       for layer, m in zip(ball.layers, ball.layer_masses_kg)]})
    return out


__all__ = [
    "CRICKET_3LAYER_SPEC",
    "PRESETS",
    "SPORTS_PRESETS",
    "TABLE_7_3",
    "UNIVERSAL_DENSITY_KG_M3",
    "BallModel",
    "Layer",
    "describe_presets",
    "load_ball",
    "universal_parameters",
    "universal_spec",
]
