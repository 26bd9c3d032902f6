"""How a bad number is refused, everywhere: one message shape,
"NAME = VALUE: allowed range [LOW, HIGH] UNIT" (an open end in parentheses; "NAME = VALUE:
expected a finite number in ..." for text, NaN or infinity), with the value shown as the user
would write it (`shown`), and the checks of specification objects (`check_keys`,
`spec_number`)."""

from __future__ import annotations

import math
import numbers
from typing import Any

from .errors import InputError


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


def check_range(name: str, value: Any, low: float = -math.inf, high: float = math.inf, *,
                low_open: bool = False, high_open: bool = False, unit: str = "") -> float:
    """`value` as a float when it is a finite real number (not a bool) in the range, else
    `InputError` "name = value: allowed range [low, high] unit" ("expected a finite number (in
    [low, high] unit)" for what is not one)."""
    allowed = allowed_range(low, high, low_open, high_open, unit)
    if not (isinstance(value, numbers.Real) and not isinstance(value, bool)
            and math.isfinite(value)):
        bounded = low > -math.inf or high < math.inf
        raise InputError(f"{name} = {shown(value)}: expected a finite number"
                         + (f" in {allowed}" if bounded else ""))
    if not ((value > low if low_open else value >= low)
            and (value < high if high_open else value <= high)):
        raise InputError(f"{name} = {shown(value)}: allowed range {allowed}")
    return float(value)


def check_fraction(name: str, value: Any, high: float = 1.0, *, high_open: bool = False) -> float:
    """`value` as a fraction in (0, `high`] ((0, `high`) with `high_open`), else `check_range`'s
    `InputError`; a value up to 100 times `high`, a percentage typed for the fraction, is named
    as one ("3 looks like a percentage: use 0.03")."""
    if (isinstance(value, numbers.Real) and not isinstance(value, bool)
            and high < value <= 100 * high):
        raise InputError(f"{name} = {value:g}: allowed range "
                         f"{allowed_range(0.0, high, True, high_open, '')}; {value:g} looks like a "
                         f"percentage: use {value / 100:g}")
    return check_range(name, value, 0.0, high, low_open=True, high_open=high_open)


def check_positive(name: str, value: Any, *, allow_zero: bool = False) -> float:
    """`value` as a float > 0 (>= 0 with `allow_zero`): anything `float()` takes, a number read
    from a file as text too; else `check_range`'s `InputError`."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        pass  # refused below, shown as given
    return check_range(name, value, 0.0, low_open=not allow_zero)


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
