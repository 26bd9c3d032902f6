"""How a bad number is refused, everywhere: one message shape,
"NAME = VALUE: allowed range [LOW, HIGH] UNIT" (an open end in parentheses; "NAME = VALUE:
expected a finite number in ..." for text, NaN or infinity; "expected an integer in ..." for a
count that is not a whole number, `check_integer`), with the value shown as the user would write
it (`shown`); the same shape for a value only warned about,
"NAME = VALUE: outside the RANGE [LOW, HIGH] UNIT: CONSEQUENCE" (`warn_outside_range`); and the
checks of specification objects (`check_keys`, `spec_number`)."""

from __future__ import annotations

import math
import numbers
import warnings
from collections.abc import Collection, Iterable
from typing import Any

from .errors import InputError, InputWarning


def shown(value: Any) -> str:
    """`value` for an error message: numbers (NumPy scalars included) as plain numbers (`:g`),
    sequences and arrays element by element, anything else by its repr. Never `np.float64(...)`."""
    if hasattr(value, "tolist"):
        value = value.tolist()  # NumPy (and JAX) arrays and scalars -> Python numbers and lists
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return str(int(value))
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return f"{float(value):g}"
    if isinstance(value, (list, tuple)):
        return f"[{', '.join(shown(v) for v in value)}]"
    return repr(value)


def allowed_range(low: float, high: float, low_open: bool = False, high_open: bool = False,
                  unit: str = "") -> str:
    """"[low, high]" with parentheses at open ends (and infinite ones), then the unit."""
    opening = "(" if low_open or low == -math.inf else "["
    closing = ")" if high_open or high == math.inf else "]"
    return f"{opening}{low:g}, {high:g}{closing}" + (f" {unit}" if unit else "")


def is_finite_number(value: Any) -> bool:
    """Whether `value` is a finite real number (NumPy scalars included; not a bool)."""
    return (isinstance(value, numbers.Real) and not isinstance(value, bool)
            and math.isfinite(value))


def in_range(value: float, low: float, high: float, low_open: bool = False,
             high_open: bool = False) -> bool:
    """Whether the number `value` lies in [low, high] (an end excluded where it is open)."""
    return ((value > low if low_open else value >= low)
            and (value < high if high_open else value <= high))


def range_text(name: str, value: Any, label: str, low: float, high: float,
               low_open: bool = False, high_open: bool = False, unit: str = "",
               note: str = "") -> str:
    """The one message shape of a value and its range: "name = value: label [low, high] unit",
    then " (note)" if a note is given; `label` is "allowed range" for an error."""
    allowed = allowed_range(low, high, low_open, high_open, unit)
    return f"{name} = {shown(value)}: {label} {allowed}" + (f" ({note})" if note else "")


def check_range(name: str, value: Any, low: float = -math.inf, high: float = math.inf, *,
                low_open: bool = False, high_open: bool = False, unit: str = "",
                note: str = "") -> float:
    """`value` as a float when it is a finite real number (not a bool) in the range, else
    `InputError` "name = value: allowed range [low, high] unit" ("expected a finite number (in
    [low, high] unit)" for what is not one), then " (note)" if a note is given (what the value
    means)."""
    if not is_finite_number(value):
        bounded = low > -math.inf or high < math.inf
        allowed = allowed_range(low, high, low_open, high_open, unit)
        raise InputError(f"{name} = {shown(value)}: expected a finite number"
                         + (f" in {allowed}" if bounded else "") + (f" ({note})" if note else ""))
    if not in_range(value, low, high, low_open, high_open):
        raise InputError(range_text(name, value, "allowed range", low, high, low_open,
                                    high_open, unit, note))
    return float(value)


def check_integer(name: str, value: Any, low: float, high: float = math.inf, *,
                  note: str = "", even: bool = False) -> int:
    """`value` as an int when it is a whole number (an integer, NumPy's too, or a float with no
    fraction; not a bool, not text) in [low, high] (even with `even`), else `InputError`
    "name = value: allowed range [low, high]" ("expected an (even) integer in [low, high]" for
    what is not one), then " (note)" if a note is given (what the count means; "even" leads it
    for an even count out of range)."""
    whole = (isinstance(value, numbers.Integral) and not isinstance(value, bool)) or (
        is_finite_number(value) and float(value).is_integer())
    if not whole or (even and int(value) % 2):
        kind = "an even integer" if even else "an integer"
        raise InputError(f"{name} = {shown(value)}: expected {kind} in "
                         f"{allowed_range(low, high)}" + (f" ({note})" if note else ""))
    if not in_range(value, low, high):
        even_note = "even" + (f"; {note}" if note else "") if even else note
        raise InputError(range_text(name, value, "allowed range", low, high, note=even_note))
    return int(value)


def warn_outside_range(name: str, value: float, label: str, low: float, high: float, *,
                       unit: str = "", consequence: str = "", stacklevel: int = 2) -> bool:
    """An `InputWarning` "name = value: outside the label [low, high] unit: consequence" when the
    number `value` lies outside the closed range (the shape of `check_range`'s error, for a value
    that is only doubtful: `label` "model's training range"). Returns whether it warned;
    `stacklevel` counts from the caller."""
    if in_range(value, low, high):
        return False
    message = range_text(name, value, f"outside the {label}", low, high, unit=unit)
    warnings.warn(message + (f": {consequence}" if consequence else ""), InputWarning,
                  stacklevel=stacklevel + 1)
    return True


def check_fraction(name: str, value: Any, high: float = 1.0, *, high_open: bool = False,
                   allow_zero: bool = False, note: str = "") -> float:
    """`value` as a fraction in (0, `high`] ((0, `high`) with `high_open`; from 0 with
    `allow_zero`), else `check_range`'s `InputError` (with `note`); a value up to 100 times
    `high`, a percentage typed for the fraction, is named as one ("3 looks like a percentage:
    use 0.03")."""
    if is_finite_number(value) and high < value <= 100 * high:
        raise InputError(range_text(name, value, "allowed range", 0.0, high, not allow_zero,
                                    high_open, note=note)
                         + f"; {shown(value)} looks like a percentage: use {value / 100:g}")
    return check_range(name, value, 0.0, high, low_open=not allow_zero, high_open=high_open,
                       note=note)


def check_positive(name: str, value: Any, *, allow_zero: bool = False) -> float:
    """`value` as a float > 0 (>= 0 with `allow_zero`): anything `float()` takes, a number read
    from a file as text too; else `check_range`'s `InputError`."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        pass  # refused below, shown as given
    return check_range(name, value, 0.0, low_open=not allow_zero)


def check_metres(name: str, value: Any, high: float, low: float = 0.0) -> float:
    """A length in (low, high] m; a value up to 1000 times `high` is named as millimetres
    (`InputError` of one line, "... looks like millimetres: use ...")."""
    if is_finite_number(value) and high < value <= 1000 * high:
        raise InputError(range_text(name, value, "allowed range", low, high, low_open=True,
                                    unit="m") + f"; {shown(value)} looks like millimetres: "
                         f"use {value / 1000:g}")
    return check_range(name, value, low, high, low_open=True, unit="m")


def spec_metres(d: dict, key: str, where: str, high: float, low: float = 0.0) -> float:
    """`d[key]` of a specification, a length checked by `check_metres` (millimetres named)."""
    if key not in d:
        raise InputError(f"{where}: missing key '{key}'")
    return check_metres(f"{where}.{key}", d[key], high, low)


def spec_number(d: dict, key: str, where: str, low: float = -math.inf, high: float = math.inf,
                low_open: bool = False, high_open: bool = False) -> float:
    """`d[key]` of a specification (JSON/TOML object at `where`), checked by `check_range`."""
    if key not in d:
        raise InputError(f"{where}: missing key '{key}'")
    return check_range(f"{where}.{key}", d[key], low, high, low_open=low_open,
                       high_open=high_open)


def check_keys(d: Any, allowed: set[str], where: str) -> None:
    """`d` is an object (dict) with no key outside `allowed`; `InputError` naming `where`."""
    if not isinstance(d, dict):
        raise InputError(f"{where}: expected an object, got {type(d).__name__}")
    unknown = sorted(set(d) - allowed)
    if unknown:
        raise InputError(f"{where}: unknown key '{unknown[0]}' (allowed: {', '.join(sorted(allowed))})")


# --------------------------------------------------------------------------- overridable checks

#: Overridable checks: name -> what it catches (for help texts and error messages).
CHECKS: dict[str, str] = {
    "clipping": "samples stuck at the recorder's full scale (a flat top at the extreme value)",
    "unit-slip": "impulse and m (v_in + v_out) differ by more than UNIT_SLIP_FACTOR, or "
                 "calibrate bounds more than 100x from the template value (a unit slip such as "
                 "MPa typed for Pa)",
    "cor-above-one": "rebound speed above impact speed (COR > 1 for a passive ball)",
    "speed-range": "FE impact speed outside the speeds the FE solver was checked at "
                   "(FE_SPEED_RANGE_M_S, 3D: FE_3D_SPEED_RANGE_M_S), or, for identify, outside "
                   "the universal model's training speeds",
    "ball-units": "ball radius, mass, density or moduli outside the ranges of solid sports balls "
                  "(BALL_RANGES; a unit slip: mm for m, g/cm^3 for kg/m^3, MPa for Pa)",
    "large-run": "FE run or export whose memory estimate, made before meshing, exceeds the "
                 "memory available",
}

def check_allow(allow: Iterable[str] | None) -> frozenset[str]:
    """The names in `allow`, each one of `CHECKS`; `InputError` naming an unknown one."""
    names = frozenset(allow or ())
    unknown = sorted(names - set(CHECKS))
    if unknown:
        raise InputError(f"allow: unknown check {unknown[0]!r}; allowed: {', '.join(CHECKS)}")
    return names


def flag(name: str, message: str, allow: Collection[str]) -> None:
    """Raise `InputError` for the failed check `name`, or warn if the user allowed it."""
    if name not in CHECKS:
        raise ValueError(f"flag: unknown check {name!r}")
    if name in allow:
        warnings.warn(f"{name}: {message}", InputWarning, stacklevel=3)
        return
    raise InputError(f"{message} (to go on anyway: --allow {name}, or allow={{'{name}'}})")
