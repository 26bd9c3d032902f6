"""What a calibration is: a template ball, the tests it is calibrated against, and the free
parameters addressed by path in the ball specification, with their bounds.

Paths: dot-separated keys of the ball specification (docs/balls.md), with layers named or
numbered and list entries numbered: `layers.core.material.c10_pa`,
`layers.core.material.prony.0.g`, `layers.1.material.terms.0.mu_pa`, `layers.cover.density_kg_m3`.
Parameters not listed keep the template's value. Geometry (radii) cannot be free: a calibration
runs one mesh.

The search works on unit coordinates u in [0, 1] per parameter: linear between the bounds, or
logarithmic for relaxation times (`..._tau_s` paths, bounds > 0), whose plausible values span
decades.
"""

from __future__ import annotations

import copy
import difflib
import math
import warnings
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from ..errors import InputError, InputWarning

OBJECTIVES = ("nrmse", "cor", "contact_time", "peak_force", "compression")
#: the objectives of each kind of test: impact tests (a force pulse) and compression tests (a
#: force-deflection curve, `compression.CompressionTest`)
IMPACT_OBJECTIVES = ("nrmse", "cor", "contact_time", "peak_force")
COMPRESSION_OBJECTIVES = ("compression",)
#: the default objectives of a stage: those of the kinds of test it has
DEFAULT_IMPACT_OBJECTIVES = ("nrmse", "cor", "contact_time")


def kind_of(test) -> str:
    """"compression" for a compression test, else "impact"."""
    return test.kind


def applies(objective: str, test) -> bool:
    """Whether an objective is computed for a test (`compression` for compression tests, the
    others for impact tests)."""
    return (objective in COMPRESSION_OBJECTIVES) == (kind_of(test) == "compression")


def default_objectives(tests) -> tuple[str, ...]:
    """The objectives of a stage that names none: nrmse, cor, contact_time for impact tests,
    compression for compression tests (both where it has both)."""
    kinds = {kind_of(t) for t in tests}
    return (DEFAULT_IMPACT_OBJECTIVES if "impact" in kinds else ()) + \
        (COMPRESSION_OBJECTIVES if "compression" in kinds else ())


def check_objectives_apply(objectives, tests, where: str) -> None:
    """`InputError` (naming `where`, e.g. "--stage core") when an objective applies to none of
    the tests, or a test has none of the objectives."""
    for o in objectives:
        if not any(applies(o, t) for t in tests):
            kind = "compression" if o in COMPRESSION_OBJECTIVES else "impact"
            have = ", ".join(f"{t.name} ({kind_of(t)})" for t in tests)
            raise InputError(f"{where}: objective {o} applies to {kind} tests only, and the "
                             f"stage has none (tests: {have}); give objectives="
                             f"{','.join(default_objectives(tests))} or other tests")
    for t in tests:
        if not any(applies(o, t) for o in objectives):
            allowed = COMPRESSION_OBJECTIVES if kind_of(t) == "compression" \
                else IMPACT_OBJECTIVES
            raise InputError(f"{where}: objectives {','.join(objectives)} do not apply to the "
                             f"{kind_of(t)} test {t.name} (its objectives: "
                             f"{', '.join(allowed)}); add one, or leave the test out of the "
                             "stage (tests=...)")


@dataclass(frozen=True)
class FreeParameter:
    """A parameter of the ball specification, its bounds (SI) and its scale ("linear"/"log")."""

    path: str
    low: float
    high: float
    scale: str = "linear"

    def to_unit(self, value):
        if self.scale == "log":
            return np.log(value / self.low) / np.log(self.high / self.low)
        return (np.asarray(value) - self.low) / (self.high - self.low)

    def from_unit(self, u):
        if self.scale == "log":
            return self.low * (self.high / self.low) ** np.asarray(u)
        return self.low + np.asarray(u) * (self.high - self.low)

    def to_dict(self) -> dict[str, Any]:
        return {"path": self.path, "low": self.low, "high": self.high, "scale": self.scale}


def _resolve(spec: dict, path: str) -> tuple[Any, Any]:
    """(container, key) of a path in a ball specification; InputError naming the path."""
    parts = path.split(".")
    node: Any = spec
    for depth, part in enumerate(parts):
        where = ".".join(parts[:depth]) or "ball"
        if isinstance(node, list):
            index = None
            if part.isdigit() and int(part) < len(node):
                index = int(part)
            elif where == "layers":
                index = next((i for i, layer in enumerate(node) if layer.get("name") == part), None)
            if index is None:
                names = [layer.get("name", str(i)) for i, layer in enumerate(node)] \
                    if where == "layers" else list(range(len(node)))
                raise InputError(f"--free {path}: no entry {part!r} in {where} (have: "
                                 f"{', '.join(map(str, names))}){_nearest(spec, path)}")
            key = index
        elif isinstance(node, dict):
            if part not in node:
                raise InputError(f"--free {path}: unknown parameter path: {where} has no key "
                                 f"{part!r} (keys: {', '.join(sorted(map(str, node)))})"
                                 f"{_nearest(spec, path)}")
            key = part
        else:
            raise InputError(f"--free {path}: unknown parameter path: {where} is a number")
        if depth == len(parts) - 1:
            break
        node = node[key]
    return node, key


def parameter_paths(spec: Any, prefix: str = "") -> list[str]:
    """Every path of a number in a ball specification, layers by name (for suggestions)."""
    if isinstance(spec, dict):
        items = spec.items()
    elif isinstance(spec, list):
        items = ((item.get("name", i) if isinstance(item, dict) and prefix == "layers." else i,
                  item) for i, item in enumerate(spec))
    else:
        return [prefix[:-1]] if isinstance(spec, (int, float)) and not isinstance(spec, bool) \
            else []
    return [path for key, item in items for path in parameter_paths(item, f"{prefix}{key}.")]


def _nearest(spec: dict, path: str) -> str:
    """'; did you mean X?' for the parameter path nearest to `path` (difflib), else ''."""
    nearest = difflib.get_close_matches(path, parameter_paths(spec), n=1, cutoff=0.6)
    return f"; did you mean {nearest[0]}?" if nearest else ""


def get_value(spec: dict, path: str) -> float:
    container, key = _resolve(spec, path)
    value = container[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"--free {path}: not a number in the ball specification "
                         f"(it holds {type(value).__name__})")
    return float(value)


def with_values(spec: dict, values: dict[str, float]) -> dict:
    """A copy of `spec` with the parameters at `values` (path -> SI value)."""
    out = copy.deepcopy(spec)
    for path, value in values.items():
        container, key = _resolve(out, path)
        container[key] = float(value)
    return out


def free_parameter(spec: dict, path: str, low: float, high: float, allow=()) -> FreeParameter:
    """A checked free parameter: the path exists and holds a number, not a radius; the bounds are
    finite, ordered, in the template value's unit (`check_scale`), and give a valid ball at both
    ends (`allow`: plausibility checks that only warn, such as "ball-units" or "unit-slip")."""
    from ..fe import load_ball

    if path.endswith("outer_radius_m"):
        raise InputError(f"--free {path}: radii are fixed in a calibration (one mesh)")
    if path.endswith(".k") and low <= 0.0:
        raise InputError(f"--free {path}={low:g}:{high:g}: a bulk Prony term k must stay above 0 "
                         "over the bounds (k = 0 drops its states from the compiled program)")
    value = get_value(spec, path)
    if not (math.isfinite(low) and math.isfinite(high)):
        raise InputError(f"--free {path}={low:g}:{high:g}: bounds must be finite")
    if not low < high:
        raise InputError(f"--free {path}={low:g}:{high:g}: bounds reversed or equal "
                         "(expected LOW < HIGH)")
    check_scale(path, low, high, value, allow)
    for bound in (low, high):
        try:
            load_ball(with_values(spec, {path: bound}), allow=allow)
        except InputError as error:
            raise InputError(f"--free {path}={low:g}:{high:g}: the bound {bound:g} is outside "
                             f"the material's valid range ({error})") from None
    scale = "log" if path.endswith("tau_s") and low > 0 else "linear"
    return FreeParameter(path, float(low), float(high), scale)


#: bounds that leave out the template's value and whose larger magnitude differs from it by
#: more than this factor (either way) are a unit slip, not a search range
SCALE_SLIP_FACTOR = 100.0
#: units by the path's ending: the SI unit, and the usual slips as (factor to SI, unit typed)
_UNITS = {"_pa": ("Pa", ((1e3, "kPa"), (1e6, "MPa"), (1e9, "GPa"))),
          "tau_s": ("s", ((1e-3, "ms"), (1e-6, "us"))),
          "_kg_m3": ("kg/m3", ((1e3, "g/cm3"),)),
          ".g": ("", ((0.01, "percent"),))}


def check_scale(path: str, low: float, high: float, value: float, allow=(), *,
                option: str = "--free", reference: str = "the template's value",
                units: tuple | None = None) -> None:
    """The `unit-slip` plausibility check (an `InputError`, or a warning if `allow` holds it) of
    bounds that look like another unit than the template's value: they leave the value out and
    their larger magnitude differs from |value| by more than `SCALE_SLIP_FACTOR` either way
    (c10_pa=1:4, MPa typed, against 3.5e6 Pa). Bounds that merely miss a value nearby are a
    search away from the template (the problem warns). Where a usual slip of the unit, or a power
    of 1000, brings the bounds around the value (or within half of it), the message gives them.
    `option` (the flag), `reference` (what `value` is) and `units` ((SI unit, slips), else from
    the path's ending) let other flags share the check (`fit --bound`)."""
    from ..checks import flag

    size = max(abs(low), abs(high))
    if low <= value <= high or value == 0.0:
        return
    ratio = abs(value) / size if size > 0 else math.inf
    if 1.0 / SCALE_SLIP_FACTOR <= ratio <= SCALE_SLIP_FACTOR:
        return
    si, slips = units if units is not None else next(
        (units for end, units in _UNITS.items() if path.endswith(end)), ("", ()))
    message = (f"{option} {path}={low:g}:{high:g}: {reference} is {value:g}"
               f"{' ' + si if si else ''}, more than {SCALE_SLIP_FACTOR:g}x from the bounds")
    flag("unit-slip", f"{message}{_slip_fix(low, high, value, ratio, slips, si)}", allow)


def _slip_fix(low: float, high: float, value: float, ratio: float, slips, si: str) -> str:
    """'; 1:4 looks like MPa; use 1e+06:4e+06' where a usual slip of the unit (`slips`), or a
    power of 1000, brings the bounds around `value` or within half of it; else where to give
    them."""
    if math.isfinite(ratio):
        for factor, unit in list(slips) + [(1000.0 ** round(math.log10(ratio) / 3), None)]:
            scaled = (low * factor, high * factor)
            if scaled[0] <= value <= scaled[1] or min(abs(value - b) for b in scaled) <= 0.5 * abs(
                    value):
                slip = (f"looks like {unit}" if unit else f"looks {factor:g}x too small"
                        if factor > 1 else f"looks {1 / factor:g}x too large")
                return f"; {low:g}:{high:g} {slip}; use {scaled[0]:g}:{scaled[1]:g}"
    return f": give them in {si or 'SI'} around the value"


@dataclass(frozen=True)
class CalibrationTest:
    """A measured (or synthetic) impact the ball is calibrated against.

    `features`: the processed test (`ImpactFeatures`, with t = 0 at contact start); `layers`: the
    name of the outermost layer of the ball that was tested (e.g. "core" for a test of the core
    alone), None for the whole ball.
    """

    name: str
    features: Any
    layers: str | None = None
    #: the kind of test (`kind_of`; `compression.CompressionTest`'s is "compression")
    kind: ClassVar[str] = "impact"

    def fe_run(self, ball, options, allow=()):
        """The FE impact (`fe.simulate`, axisymmetric `options`) of `ball` at the test's speed."""
        from ..fe import simulate

        return simulate(ball, self.impact_speed_m_s, options, allow=allow)

    @property
    def impact_speed_m_s(self) -> float:
        return float(self.features.values["P15"])

    @property
    def pulse(self) -> tuple[np.ndarray, np.ndarray]:
        """(time_s from contact start, force_n) of the contact pulse."""
        from ..comparison import features_pulse

        return features_pulse(self.features)


def sub_ball(spec: dict, outer_layer: str | None) -> dict:
    """The ball of the layers up to `outer_layer` (by name), or the whole ball."""
    if outer_layer is None:
        return spec
    names = [layer.get("name") for layer in spec["layers"]]
    if outer_layer not in names:
        raise InputError(f"test layers = {outer_layer!r}: no such layer (have: "
                         f"{', '.join(map(str, names))})")
    return {**spec, "layers": spec["layers"][:names.index(outer_layer) + 1]}


@dataclass
class CalibrationProblem:
    """Template ball specification, tests, free parameters and objectives."""

    template: dict
    tests: list[CalibrationTest]
    free: list[FreeParameter]
    #: None: those of the tests' kinds (`default_objectives`)
    objectives: tuple[str, ...] | None = None
    start: dict[str, float] = field(default_factory=dict)  # path -> value; default template
    #: plausibility checks turned into warnings (`checks.CHECKS`; e.g. "speed-range" for
    #: tests outside the FE solver's checked speeds)
    allow: frozenset = frozenset()

    def __post_init__(self) -> None:
        from ..fe import load_ball
        from ..checks import check_allow

        self.start = dict(self.start)  # the caller's dict is left alone
        self.allow = check_allow(self.allow)
        if not self.tests:
            raise InputError("tests: need at least one test")
        if not self.free:
            raise InputError("--free: need at least one free parameter")
        paths = [p.path for p in self.free]
        if len(set(paths)) != len(paths):
            raise InputError(f"--free: a parameter is listed twice ({paths})")
        if self.objectives is None:
            self.objectives = default_objectives(self.tests)
        bad = [o for o in self.objectives if o not in OBJECTIVES]
        if bad or not self.objectives:
            raise InputError(f"--objectives {','.join(self.objectives)}: allowed any of "
                             f"{', '.join(OBJECTIVES)}")
        check_objectives_apply(self.objectives, self.tests, "--objectives")
        # the tests' speeds: `calibrate` checks them before any run, and every FE run does
        for test in self.tests:
            ball = load_ball(sub_ball(self.template, test.layers), allow=self.allow)
            if kind_of(test) == "compression":
                test.check_against(ball)
                continue
            mass = test.features.mass_kg
            if mass and abs(mass / ball.mass_kg - 1.0) > 0.02:
                warnings.warn(f"test {test.name}: mass_kg = {mass:g} differs from the ball's "
                              f"{ball.mass_kg:.4g} kg by more than 2%; the ball keeps its own "
                              "density", InputWarning, stacklevel=2)
        for p in self.free:
            value = self.start.get(p.path, get_value(self.template, p.path))
            if not p.low <= value <= p.high:
                warnings.warn(f"--free {p.path}: the start value {value:g} is outside the "
                              f"bounds; clipped to them", InputWarning, stacklevel=2)
            self.start[p.path] = float(np.clip(value, p.low, p.high))

    @property
    def names(self) -> list[str]:
        return [p.path for p in self.free]

    def values(self, u: np.ndarray) -> dict[str, float]:
        """Parameter values (SI) at unit coordinates u (n_free,)."""
        return {p.path: float(p.from_unit(x)) for p, x in zip(self.free, u)}

    def unit(self, values: dict[str, float]) -> np.ndarray:
        return np.array([float(p.to_unit(values[p.path])) for p in self.free])

    def start_unit(self) -> np.ndarray:
        return self.unit(self.start)

    def spec(self, u: np.ndarray, name: str = "calibrated") -> dict:
        """The ball specification at unit coordinates u."""
        return {**with_values(self.template, self.values(u)), "name": name}
