"""The `ball-units` plausibility check: a ball's radius, mass, density and moduli within the ranges
of solid sports balls (`BALL_RANGES`), a value far outside named as the unit slip it most likely
is (mm for m, g/cm^3 for kg/m^3, MPa for Pa). docs/balls.md lists the ranges."""

from __future__ import annotations

import math
from collections.abc import Collection

import numpy as np

from ..checks import flag
from ..errors import InputError

#: Ranges (SI) of the solid sports balls the FE solvers model, generous at both ends: from a
#: marble-sized ball (5 mm radius) past a bowling ball (0.11 m) and a shot (7.26 kg, 7800 kg/m^3),
#: from soft foam (a foam ball: 20-30 kg/m^3, shear modulus ~1e4 Pa) to hard resin and steel.
#: A unit slip lands far outside: a radius in mm (36.6 for 0.0366 m), a density in g/cm^3 (1.13
#: for 1130 kg/m^3) or T/mm^3 (8.65e-10), moduli in MPa (4.72 for 4.72e6 Pa), D1 in 1/MPa.
BALL_RANGES: dict[str, tuple[float, float, str]] = {
    "outer radius": (0.005, 0.2, "m"),
    "mass": (0.001, 30.0, "kg"),
    "density": (10.0, 20000.0, "kg/m^3"),
    "shear modulus": (1e4, 1e10, "Pa"),
    "bulk modulus": (1e4, 1e12, "Pa"),
}

#: The slips that bring a value far outside its range: factor to SI -> how the value was given.
#: A value is read as a slip when value x factor falls inside the range (the nearest to the
#: range's typical value is named).
_BALL_SLIPS: dict[str, dict[float, str]] = {
    "outer radius": {1e-3: "millimetres", 1e-2: "centimetres", 0.0254: "inches"},
    "mass": {},  # follows from the radii and densities, which are checked first
    "density": {1e3: "g/cm^3", 1e12: "T/mm^3 (the mm-tonne-s unit)", 1e-3: "g/m^3"},
    "shear modulus": {1e6: "MPa", 1e3: "kPa", 1e9: "GPa"},
    "bulk modulus": {1e6: "MPa", 1e9: "GPa"},
}
#: A typical value of each (a cricket ball's), to pick the likeliest of several slips.
_BALL_TYPICAL = {"outer radius": 0.036, "mass": 0.16, "density": 1000.0,
                 "shear modulus": 1e7, "bulk modulus": 1e9}


def check_ball_diameter(diameter_m: float, name: str) -> float:
    """A ball diameter (m) within those of solid sports balls (`BALL_RANGES`' outer radii); a
    diameter in millimetres or centimetres is named as such (`ball_unit_slip`)."""
    if isinstance(diameter_m, bool) or not (isinstance(diameter_m, (int, float))
                                            and math.isfinite(diameter_m) and diameter_m > 0):
        raise InputError(f"{name} = {diameter_m!r}: expected a positive diameter in m")
    low, high, _ = BALL_RANGES["outer radius"]
    if not 2 * low <= diameter_m <= 2 * high:
        slip = ball_unit_slip("outer radius", diameter_m / 2)
        hint = f": looks like {slip[1]}; use {diameter_m * slip[0]:g}" if slip else ""
        raise InputError(f"{name} = {diameter_m:g} m is outside {2 * low:g}..{2 * high:g} m, "
                         f"the diameters of solid sports balls{hint}")
    return float(diameter_m)


def check_ball_mass(mass_kg: float, where: str) -> float:
    """A ball mass inside `BALL_RANGES` (kg); outside it an `InputError` naming `where` and the
    range, and grams given as kilograms when that fits."""
    low, high, _ = BALL_RANGES["mass"]
    number = isinstance(mass_kg, (int, float)) and not isinstance(mass_kg, bool)
    if not (number and np.isfinite(mass_kg) and low <= mass_kg <= high):
        hint = (f": it looks like grams given as kg (use {mass_kg * 1e-3:g})"
                if number and low <= mass_kg * 1e-3 <= high else "")
        raise InputError(f"{where} = {mass_kg!r} kg: the mass is outside {low:g}..{high:g} kg, "
                         f"the range of solid sports balls{hint}")
    return float(mass_kg)


def ball_unit_slip(quantity: str, value: float) -> tuple[float, str] | None:
    """(factor, unit) of the likeliest unit slip that brings `value` (SI) of `quantity` (a key of
    `BALL_RANGES`) inside its range, or None."""
    low, high, _ = BALL_RANGES[quantity]
    fits = [(factor, unit) for factor, unit in _BALL_SLIPS[quantity].items()
            if low <= value * factor <= high]
    if not fits:
        return None
    typical = _BALL_TYPICAL[quantity]
    return min(fits, key=lambda fit: abs(np.log(value * fit[0] / typical)))


def _ball_range_message(what: str, quantity: str, value: float, fix: str, hint: str,
                        diagnosis: str = "") -> str:
    """'<what> = value unit: the <quantity> is outside low..high unit, the range of solid sports
    balls: it looks like <unit> given as <SI unit> (<fix>: value -> corrected)' for
    `check_ball_values`; `fix` is the remedy with '{factor}' for the slip's factor, `diagnosis`
    (with '{unit}') replaces 'it looks like ...', `hint` is what to say when no slip fits."""
    low, high, unit = BALL_RANGES[quantity]
    message = (f"{what} = {value:g} {unit}: the {quantity} is outside {low:g}..{high:g} {unit}, "
               "the range of solid sports balls")
    slip = ball_unit_slip(quantity, value)
    if slip is not None:
        factor, given = slip
        said = (diagnosis or "it looks like {unit} given as " + unit).format(unit=given)
        message += (f": {said} ({fix.format(factor=f'{factor:g}')}: {value:g} -> "
                    f"{value * factor:g} {unit})")
    elif hint:
        message += f": {hint}"
    return message


#: What each quantity's check says: (name of the value, remedy for a slip, hint without one)
_BALL_FIXES = {
    "outer radius": ("{where}.outer_radius_m", "use outer_radius_m x {factor}",
                     "outer_radius_m is the radius (not the diameter) in metres"),
    "mass": ("{where} mass", "", "check the radii (m) and the densities (kg/m^3)"),
    "density": ("{where}.density_kg_m3", "use density_kg_m3 x {factor}", ""),
    "shear modulus": ("{where}.material shear modulus", "multiply {keys} by {factor}", ""),
    "bulk modulus": ("{where}.material bulk modulus", "multiply {keys} by {factor}", ""),
}


def check_force_units(force_n: float, deflection_m: float, radius_m: float, name: str) -> None:
    """A compression force whose sphere would be no sports ball's is a unit slip (kN typed for N):
    the shear modulus it implies by Hertz between two platens (each approaching D / 2, F = 4/3 E*
    sqrt(R) (D/2)^1.5, nearly incompressible: mu = E* / 4) must lie in `BALL_RANGES`' shear
    moduli. `InputError` starting with `name` (the force's field or flag), naming the slip."""
    e_star = 0.75 * force_n / (math.sqrt(radius_m) * (0.5 * deflection_m) ** 1.5)
    low, high, _ = BALL_RANGES["shear modulus"]
    mu = 0.25 * e_star
    if low <= mu <= high:
        return
    factor = next((f for f in (1e3, 1e-3) if low <= mu * f <= high), None)
    hint = ("" if factor is None else
            f"; looks like {'kN' if factor > 1 else 'mN'}: use {force_n * factor:g} N")
    raise InputError(f"{name} = {force_n:g} N at {deflection_m * 1e3:.3g} mm implies a shear "
                     f"modulus of about {mu:.3g} Pa (Hertz), outside the {low:g}..{high:g} Pa "
                     f"of sports balls{hint}")


def check_ball_values(where: str, values: dict[str, float], keys: dict | None = None,
                      allow: Collection[str] = ()) -> None:
    """The `ball-units` check of `values` (quantity of `BALL_RANGES` -> value in SI): each value
    outside its range fails it, with the likeliest unit slip named (`ball_unit_slip`). `where`
    names the ball or layer ("ball.layers[0]"); `keys` (quantity -> text) names the keys a
    modulus comes from ("c10_pa, c01_pa"), or is a (diagnosis, remedy) pair for a slip (with
    '{unit}' and '{factor}', as for D1: `_moduli_keys`)."""
    for quantity, value in values.items():
        low, high, _ = BALL_RANGES[quantity]
        if low <= value <= high:
            continue
        what, fix, hint = _BALL_FIXES[quantity]
        source = (keys or {}).get(quantity, "the moduli")
        diagnosis = ""
        if isinstance(source, tuple):
            diagnosis, fix = source
        else:
            fix = fix.replace("{keys}", source)
        flag("ball-units", _ball_range_message(what.format(where=where), quantity, float(value),
                                               fix, hint, diagnosis), allow)


def _moduli_keys(material) -> dict:
    """The keys a material's shear and bulk moduli come from, as a user wrote them."""
    spec = material.to_dict()
    shear = [key for key in spec if key.endswith("_pa") and not key.endswith("_per_pa")] + (
        ["terms[].mu_pa"] if "terms" in spec else [])
    keys = {"shear modulus": ", ".join(shear) or "the moduli",
            "bulk modulus": ", ".join(shear) or "the moduli"}
    if spec.get("d1_per_pa"):  # K = 2 / D1: D1 in 1/MPa reads a million times too soft
        keys["bulk modulus"] = ("d1_per_pa looks like 1/{unit} given as 1/Pa",
                                "divide d1_per_pa by {factor}")
    return keys


def check_ball(ball, allow: Collection[str] = (), where: str = "ball") -> None:
    """The `ball-units` check of a ball (`fe.BallModel`): outer radius, each layer's density and
    shear and bulk moduli (as given, `Material.given_moduli_pa`), and the mass inside
    `BALL_RANGES`. Run by `fe.load_ball` on every ball it loads (preset, file, dict). Prony
    times are not checked: series fitted to master curves span 1e-10 to 1e6 s."""
    check_ball_values(f"{where}.layers[{len(ball.layers) - 1}]",
                      {"outer radius": ball.outer_radius_m}, allow=allow)
    for i, layer in enumerate(ball.layers):
        _check_material(f"{where}.layers[{i}]", layer.density_kg_m3, layer.material, allow)
    if _inside("outer radius", ball.outer_radius_m) and all(
            _inside("density", layer.density_kg_m3) for layer in ball.layers):
        # (else the mass is off because of a value already flagged: one slip, one message)
        check_ball_values(where, {"mass": ball.mass_kg}, allow=allow)


def _inside(quantity: str, value: float) -> bool:
    low, high, _ = BALL_RANGES[quantity]
    return low <= value <= high


def check_material_values(name: str, density_kg_m3: float | None, material,
                          allow: Collection[str] = ()) -> None:
    """The `ball-units` check of one material (`import-material`): its density (if known) and
    moduli inside `BALL_RANGES` (a deck read in the wrong unit system lands far outside)."""
    _check_material(f"material {name!r}", density_kg_m3, material, allow)


def _check_material(where: str, density_kg_m3: float | None, material, allow) -> None:
    shear, bulk = material.given_moduli_pa()
    values = {"shear modulus": shear}
    if density_kg_m3 is not None:
        values = {"density": density_kg_m3, **values}
    low, high, _ = BALL_RANGES["shear modulus"]
    if low <= shear <= high:  # (a bulk modulus from a mis-scaled shear modulus fails with it)
        values["bulk modulus"] = bulk
    check_ball_values(where, values, _moduli_keys(material), allow)
