"""The published methods, described by their facts only (speeds, quantities, formulas:
`METHODS`), the ball id of a record file, and the note on a record off the method's speed."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..records.loaders import LBF_N


INCH_M = 0.0254
#: 60 mph in m/s (exact: 60 x 1609.344 m / 3600 s), the inbound speed of F1887 and F2845
SIXTY_MPH_M_S = 26.8224
#: Our choice (not the methods'): an impact record whose inbound speed differs from the method's
#: by more than this (m/s, about 2% or 1.3 mph) gets a warning naming the file. Air cannons hold
#: their speed to a few tenths of a m/s; more means another setting or a slip.
SPEED_TOLERANCE_M_S = 0.6
#: 0.25 in in m, the platen displacement of F1888
QUARTER_INCH_M = 0.25 * INCH_M
#: equal increments of the FE compression up to the method's displacement (as `compress`)
COMPRESSION_STEPS = 20


@dataclass(frozen=True)
class Quantity:
    """A reported quantity: its JSON key (with its unit), the unit as printed, and the factor
    from the SI value it is computed from (the key's unit = SI value / `si_per_unit`)."""

    key: str
    unit: str
    label: str
    si_per_unit: float = 1.0


@dataclass(frozen=True)
class Method:
    """A published test method: `kind` "impact" (a shot at `nominal` m/s on a rigid wall) or
    "compression" (platens to `nominal` m of displacement)."""

    name: str
    designation: str
    description: str
    kind: str
    nominal: float
    quantities: tuple[Quantity, ...]

    @property
    def nominal_text(self) -> str:
        if self.kind == "impact":
            return f"{self.nominal:.4g} m/s ({self.nominal / SIXTY_MPH_M_S * 60:.3g} mph)"
        return f"{self.nominal * 1e3:.3g} mm ({self.nominal / INCH_M:.3g} in)"

    def to_dict(self) -> dict[str, Any]:
        out = {"method": self.name, "designation": self.designation,
               "description": self.description, "kind": self.kind,
               "quantities": {q.key: q.unit for q in self.quantities}}
        if self.kind == "impact":
            out.update(nominal_speed_m_s=self.nominal, speed_tolerance_m_s=SPEED_TOLERANCE_M_S)
        else:
            out["nominal_displacement_m"] = self.nominal
        return out


METHODS: dict[str, Method] = {
    "cor": Method(
        "cor", "ASTM F1887",
        "coefficient of restitution: rebound / inbound speed off a rigid flat wall at 60 mph",
        "impact", SIXTY_MPH_M_S, (Quantity("cor", "", "COR"),)),
    "dynamic-stiffness": Method(
        "dynamic-stiffness", "ASTM F2845",
        "dynamic stiffness (F_peak / v_in)^2 / m from the load-cell peak force (F2845's "
        "quantity; here against a flat rigid plane, at 60 mph unless --impact-speed-m-s)",
        "impact", SIXTY_MPH_M_S,
        (Quantity("dynamic_stiffness_n_m", "N/m", "DS"),
         Quantity("dynamic_stiffness_lbf_in", "lbf/in", "DS", LBF_N / INCH_M),
         Quantity("peak_force_n", "N", "peak force"))),
    "compression": Method(
        "compression", "ASTM F1888",
        "force to squeeze the ball by 6.35 mm (0.25 in) between two flat rigid platens, slowly",
        "compression", QUARTER_INCH_M,
        (Quantity("force_at_6_35_mm_n", "N", "force at 6.35 mm"),
         Quantity("force_at_6_35_mm_lbf", "lbf", "force at 6.35 mm", LBF_N))),
}
#: other names a method is known by (the designations), lower case
ALIASES = {m.designation.split()[-1].lower(): name for name, m in METHODS.items()}
ALIASES.update({"f2845-ds": "dynamic-stiffness", "ds": "dynamic-stiffness"})


def get_method(name: str | Method) -> Method:
    """The method named `name` (or its designation, e.g. "F1887"); `InputError` listing the
    allowed ones otherwise."""
    if isinstance(name, Method):
        return name
    key = str(name).strip().lower()
    key = ALIASES.get(key.replace("astm", "").strip(), key)
    if key not in METHODS:
        allowed = ", ".join(f"{n} ({m.designation})" for n, m in METHODS.items())
        raise InputError(f"method {name!r}: unknown; allowed: {allowed}")
    return METHODS[key]


def describe_methods() -> list[dict[str, Any]]:
    """Every method, JSON-able (`ballimpact standard --list`)."""
    return [m.to_dict() for m in METHODS.values()]


# --------------------------------------------------------------------------- ball ids

#: the default ball id: the file name's stem up to its last '_' or '-' (ballA_01 -> ballA,
#: ball-7-3 -> ball-7); a stem without either is the ball id itself (one file per ball)
DEFAULT_BALL_PATTERN = r"^(?P<ball>.+)[_-][^_-]*$"


def ball_id_function(pattern: str | Callable[[Path], str] | None = None
                     ) -> Callable[[Path], str]:
    """path -> ball id. `pattern`: None (the default rule, `DEFAULT_BALL_PATTERN`), a callable,
    or a regular expression searched in the file name's stem: its group `ball` if it has one,
    else its first group, else the whole match. A stem it does not match is an `InputError`
    naming the file (the default rule falls back to the whole stem instead)."""
    if callable(pattern):
        return pattern
    if pattern is None:
        default = re.compile(DEFAULT_BALL_PATTERN)

        def by_default(path: Path) -> str:
            match = default.match(Path(path).stem)
            return match.group("ball") if match else Path(path).stem

        return by_default
    try:
        regex = re.compile(pattern)
    except re.error as error:
        raise InputError(f"--ball-id-pattern {pattern!r}: not a regular expression ({error})") \
            from None

    def by_pattern(path: Path) -> str:
        match = regex.search(Path(path).stem)
        if match is None:
            raise InputError(f"{path}: --ball-id-pattern {pattern!r} does not match the file "
                             f"name {Path(path).stem!r}; give a pattern every record's name "
                             "matches")
        if "ball" in regex.groupindex:
            found = match.group("ball")
        else:
            found = match.group(1) if regex.groups else match.group(0)
        if not found:
            raise InputError(f"{path}: --ball-id-pattern {pattern!r} gives an empty ball id")
        return found

    return by_pattern


# --------------------------------------------------------------------------- checks


def speed_note(method: Method, speed_m_s: float, where: str, nominal_m_s: float) -> str | None:
    """The warning for an inbound speed off the method's (None when within the tolerance)."""
    off = speed_m_s - nominal_m_s
    if abs(off) <= SPEED_TOLERANCE_M_S * (1 + 1e-9):  # a speed written as 0.6 off is inside
        return None
    return (f"{where}: inbound speed {speed_m_s:.4g} m/s is {off:+.3g} m/s from the nominal "
            f"{nominal_m_s:.4g} m/s of the {method.name} method (tolerance "
            f"+-{SPEED_TOLERANCE_M_S:g} m/s)")


def checked_speed(value: float) -> float:
    """An inbound speed (m/s) given for the impact methods; the methods' 60 mph typed in mph
    (60 for 26.82) is named as such."""
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"impact speed {value:g} m/s: must be a positive number (m/s)")
    mph_m_s = SIXTY_MPH_M_S / 60
    if abs(value * mph_m_s - SIXTY_MPH_M_S) <= SPEED_TOLERANCE_M_S < abs(value - SIXTY_MPH_M_S):
        raise InputError(f"--impact-speed-m-s {value:g}: looks like mph given as m/s "
                         f"({value:g} mph = {value * mph_m_s:.4g} m/s); give the speed in m/s")
    return float(value)
