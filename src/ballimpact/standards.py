"""Published ball test methods (docs/standards.md): the quantities a lab certifies balls by, from
a folder of its records or from a ball model.

Three methods, each described by its facts only (speeds, quantities, formulas):

- `cor` (ASTM F1887): the ball is fired at 60 mph (26.8224 m/s) at a massive, rigid, flat wall;
  COR = rebound speed / inbound speed, both measured near the wall.
- `dynamic-stiffness` (ASTM F2845's quantity): DS = (1/m) (F_peak / v_in)^2 from the load-cell
  peak force (N/m; also in lbf/in, 1 lbf/in = 175.1268 N/m), `features.extract_features`'
  `dynamic_stiffness_n_m` used as it is. F2845 itself fires the ball at a rigid cylindrical
  surface at a speed of its own; here the nominal speed is 60 mph against a flat rigid plane (a
  choice: the one the other impact method uses; `nominal=` / `--impact-speed-m-s` sets it).
- `compression` (ASTM F1888): the ball squeezed between two flat rigid platens by 0.25 in
  (6.35 mm), slowly; the force at that displacement (N, and lbf as the method quotes it).

Two paths per method:

- `from_records(method, paths, ...)`: a lab's records (impact records as `ballimpact features`
  reads them, with their JSON side files; compression curves as `calibrate --compression` reads
  them), one value of the method's quantities per shot, grouped by ball (the ball id comes from
  the file name, `ball_id`) into mean, standard deviation and count per ball, and over the balls
  into the mean and standard deviation of the ball means (each ball counts once, whatever its
  number of shots). Standard deviations are sample ones (n - 1 in the denominator); one value has
  none (NaN, null in JSON).
- `on_model(method, ball, ...)`: the method run on a ball model (`fe.simulate` at the method's
  speed on a rigid plane, or `fe.compress` to its displacement), with the model's cost.

An impact record whose inbound speed is more than `SPEED_TOLERANCE_M_S` from the method's speed
gets a warning naming its file (the record is still used: the methods allow other speeds if the
report says so, and the warning does).
"""

from __future__ import annotations

import math
import re
import statistics
import time
import warnings
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputError, InputWarning
from .features import dynamic_stiffness
from .fileio import write_table
from .loaders import LBF_N
from .plausibility import check_ball_mass

#: 1 in in m (exact); 1 lbf in N is the loaders' unit table's (`loaders.LBF_N`)
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


# --------------------------------------------------------------------------- statistics


def shot_stats(values: Iterable[float]) -> dict[str, float]:
    """{"mean", "sd", "count"}: the sample standard deviation (n - 1), NaN for one value."""
    values = [float(v) for v in values]
    sd = statistics.stdev(values) if len(values) > 1 else math.nan
    return {"mean": statistics.fmean(values), "sd": sd, "count": len(values)}


def summarise(method: Method, shots: list[dict[str, Any]]) -> dict[str, Any]:
    """Per ball (in order of first appearance) the mean, SD and count of each quantity (and of
    the inbound speed for impacts) over its shots; over all balls the mean and SD of the ball
    means (each ball once)."""
    keys = [q.key for q in method.quantities]
    if method.kind == "impact":
        keys = keys + ["impact_speed_m_s"]
    by_ball: dict[str, list[dict[str, Any]]] = {}
    for shot in shots:
        by_ball.setdefault(shot["ball"], []).append(shot)
    balls = []
    for ball, own in by_ball.items():
        entry: dict[str, Any] = {"ball": ball, "count": len(own)}
        for key in keys:
            entry[key] = shot_stats(shot[key] for shot in own)
        balls.append(entry)
    overall: dict[str, Any] = {"balls": len(balls), "shots": len(shots)}
    for key in keys:
        overall[key] = shot_stats(entry[key]["mean"] for entry in balls)
    return {"balls": balls, "overall": overall}


def stats_text(stats: dict[str, float], unit: str = "") -> str:
    """`shot_stats` as text: "mean +- SD unit" (5 and 3 significant digits; SD n/a for one
    value)."""
    sd = "n/a" if math.isnan(stats["sd"]) else f"{stats['sd']:.3g}"
    return f"{stats['mean']:.5g} +- {sd}" + (f" {unit}" if unit else "")


def table_rows(result: dict[str, Any]) -> tuple[list[str], list[list[Any]]]:
    """The table of a result of `from_records` or `on_model` as (columns, rows): `kind`
    shot|ball|all (model for `on_model`), ball, file, count, then each quantity (value or mean)
    and its SD (`_sd`); impact methods add the inbound speed."""
    keys = list(result["quantities"])
    if result["kind"] == "impact":
        keys.append("impact_speed_m_s")
    header = ["kind", "ball", "file", "count"] + [c for k in keys for c in (k, f"{k}_sd")]

    def cells(values: dict[str, Any]) -> list[Any]:
        out = []
        for key in keys:
            value = values.get(key)
            out += [value["mean"], value["sd"]] if isinstance(value, dict) else [value, None]
        return out

    if result["source"] == "model":
        return header, [["model", result["ball"], "", 1] + cells(result["result"])]
    rows = [["shot", shot["ball"], shot["file"], 1] + cells(shot) for shot in result["shots"]]
    rows += [["ball", entry["ball"], "", entry["count"]] + cells(entry)
             for entry in result["balls"]]
    overall = result["overall"]
    rows.append(["all", "", "", overall["balls"]] + cells(overall))
    return header, rows


def write_result_table(path: Path, result: dict[str, Any]) -> str:
    """`table_rows` as CSV (`fileio.write_table`, 12 significant digits); returns the path as
    text."""
    return write_table(path, *table_rows(result), ".12g")


# --------------------------------------------------------------------------- lab records


def from_records(method: str | Method, paths: list[Path], *, mass_kg: float | None = None,
                 ball_of: str | Callable[[Path], str] | None = None,
                 nominal: float | None = None, process_options: dict | None = None
                 ) -> dict[str, Any]:
    """The method's quantities from a lab's records: `paths` are files or folders (folders give
    their *.csv / *.wav records, `repeats.expand_records`).

    - `mass_kg`: the ball mass (kg) for every impact record, over its side file's; needed by the
      impact methods when a side file lacks it; refused by `compression` (which does not use it).
    - `ball_of`: the ball id of a file (`ball_id_function`: None, a regex or a callable).
    - `nominal`: another inbound speed (m/s) for the impact methods (reported as such), or None
      for the method's.
    - `process_options`: keyword arguments of `pipeline.process` (filter, window_s, ...).

    Returns {"method", ..., "source": "records", "shots": [...], "balls": [...], "overall"}.
    """
    from .repeats import expand_records

    method = get_method(method)
    ball_id = ball_id_function(ball_of)
    if mass_kg is not None:
        check_ball_mass(mass_kg, "--mass-kg")
    if method.kind == "compression":
        if mass_kg is not None:
            raise InputError("--mass-kg: the compression method does not use the ball mass; "
                             "leave it out")
        if nominal is not None:
            raise InputError("--impact-speed-m-s: the compression method has no impact speed; "
                             "leave it out")
    files = expand_records([Path(p) for p in paths])
    if method.kind == "compression":
        shots = [_compression_shot(method, path, ball_id(path)) for path in files]
    else:
        speed = method.nominal if nominal is None else _speed(nominal)
        shots = [_impact_shot(method, path, ball_id(path), mass_kg, speed, process_options or {})
                 for path in files]
    out = method.to_dict()
    if method.kind == "impact" and nominal is not None:
        out["nominal_speed_m_s"] = float(nominal)
        out["nominal_speed_note"] = (f"run at {nominal:g} m/s, not the method's "
                                     f"{method.nominal:g} m/s")
    out["source"] = "records"
    out["shots"] = shots
    out.update(summarise(method, shots))
    return out


def _speed(value: float) -> float:
    """An inbound speed (m/s) given for the impact methods; the methods' 60 mph typed in mph
    (60 for 26.82) is named as such."""
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"impact speed {value:g} m/s: must be a positive number (m/s)")
    mph_m_s = SIXTY_MPH_M_S / 60
    if abs(value * mph_m_s - SIXTY_MPH_M_S) <= SPEED_TOLERANCE_M_S < abs(value - SIXTY_MPH_M_S):
        raise InputError(f"--impact-speed-m-s {value:g}: looks like mph given as m/s "
                         f"({value:g} mph = {value * mph_m_s:.4g} m/s); give the speed in m/s")
    return float(value)


def _impact_shot(method: Method, path: Path, ball: str, mass_kg: float | None,
                 nominal_m_s: float, options: dict) -> dict[str, Any]:
    """One impact record's quantities (its features through `pipeline.process`)."""
    from .loaders import load_record
    from .pipeline import process

    record = load_record(path, mass_kg=mass_kg)
    if record.mass_kg is None:
        raise InputError(f"{path}: no ball mass; give --mass-kg or mass_kg in its side file "
                         f"{path.with_suffix('.json').name}")
    check_ball_mass(record.mass_kg, f"{path}: mass_kg")
    if record.impact_speed_m_s is None:
        raise InputError(f"{path}: no inbound speed; give impact_speed_m_s in its side file "
                         f"{path.with_suffix('.json').name}")
    features = process(record, **options).features
    v_in = features.values["P15"]
    note = speed_note(method, v_in, str(path), nominal_m_s)
    if note is not None:
        warnings.warn(note, InputWarning, stacklevel=3)
    shot = {"file": str(path), "ball": ball, "impact_speed_m_s": v_in,
            "rebound_speed_m_s": features.values["P16"],
            "rebound_speed_source": features.rebound_speed_source, "mass_kg": record.mass_kg}
    shot.update(impact_quantities(method, features.values["P17"],
                                  features.dynamic_stiffness_n_m, features.values["P6"]))
    # the record's own standard uncertainty of each quantity (docs/features.md, "Uncertainty"):
    # the quantities are linear in the features, so their uncertainties convert alike
    u = features.uncertainty
    shot["uncertainty"] = {} if not u else impact_quantities(
        method, u.get("P17", math.nan), u.get("dynamic_stiffness_n_m", math.nan),
        u.get("P6", math.nan))
    return shot


def impact_quantities(method: Method, cor: float, dynamic_stiffness_n_m: float,
                      peak_force_n: float) -> dict[str, float]:
    """The impact method's quantities from a shot's COR, dynamic stiffness (N/m) and peak
    force (N)."""
    if method.name == "cor":
        return {"cor": float(cor)}
    return {"dynamic_stiffness_n_m": float(dynamic_stiffness_n_m),
            "dynamic_stiffness_lbf_in": float(dynamic_stiffness_n_m) / (LBF_N / INCH_M),
            "peak_force_n": float(peak_force_n)}


def _compression_shot(method: Method, path: Path, ball: str) -> dict[str, Any]:
    """The force at the method's displacement of one compression curve (linear interpolation
    between the measured points; a curve that does not reach it is an error)."""
    from .calibrate.compression import read_compression_csv

    if path.suffix.lower() not in (".csv", ".txt"):
        raise InputError(f"{path}: a compression curve is a CSV file (deflection_m or "
                         "deflection_mm, force_n or force_kn), not a record of an impact")
    deflection, force = read_compression_csv(path)
    target = method.nominal
    if not deflection[0] <= target <= deflection[-1] * (1 + 1e-9):
        raise InputError(f"{path}: the curve spans {deflection[0] * 1e3:.4g}.."
                         f"{deflection[-1] * 1e3:.4g} mm; the {method.name} method reads the "
                         f"force at {target * 1e3:.4g} mm, inside it")
    at = float(np.interp(target, deflection, force))
    return {"file": str(path), "ball": ball, **compression_quantities(at),
            "max_deflection_m": float(deflection[-1])}


def compression_quantities(force_n: float) -> dict[str, float]:
    """The compression method's quantities from the force (N) at its displacement."""
    return {"force_at_6_35_mm_n": float(force_n), "force_at_6_35_mm_lbf": float(force_n) / LBF_N}


# --------------------------------------------------------------------------- ball models


def on_model(method: str | Method, ball_spec: Any, *, options=None, nominal: float | None = None,
             steps: int = COMPRESSION_STEPS, allow=(),
             element_size_m: float | None = None) -> dict[str, Any]:
    """The method run on a ball model: `ball_spec` a preset, a ball file or a dict
    (`fe.load_ball`). Impact methods: `fe.simulate` on a rigid plane at the method's speed
    (`nominal` m/s to run another, reported as such); the COR and the dynamic stiffness
    F_peak^2 / (m v^2) with m the mass of the run's mesh (`ImpactResult.mass_kg`). Compression:
    `fe.compress` (long-term curve: the method is slow) to 6.35 mm in `steps` increments; a ball whose constants depend on the
    impact speed (cricket-universal) takes them at the impact methods' speed.

    Returns the method's description, "ball", the quantities under "result", and the model's
    cost under "cost" (wall time s, steps or increments, elements). `options` default: the
    solver's, with the element size scaled to the ball (x R / 36 mm), the mesh the universal
    model's study and its identifications use (`universal.identify.scaled_options`);
    `element_size_m` (m), when given without `options`: the solver's with that element size."""
    from .fe import SolverOptions, compress, load_ball, simulate
    from .fe.ball import UNIVERSAL_RADIUS_M

    if options is None and element_size_m is not None:  # checked before the ball is loaded
        options = SolverOptions(element_size_m=element_size_m)
    method = get_method(method)
    if method.kind == "compression" and nominal is not None:
        raise InputError("--impact-speed-m-s: the compression method has no impact speed; "
                         "leave it out")
    speed = SIXTY_MPH_M_S if nominal is None else _speed(nominal)
    ball = load_ball(ball_spec, impact_speed_m_s=speed, allow=allow)
    if options is None:
        options = SolverOptions(element_size_m=SolverOptions().element_size_m
                                * ball.outer_radius_m / UNIVERSAL_RADIUS_M)
    out = method.to_dict()
    out["source"] = "model"
    out["ball"] = ball.name
    out["mass_kg"] = ball.mass_kg
    started = time.perf_counter()
    if method.kind == "impact":
        run = simulate(ball, speed, options, allow=allow)
        # the mass that moved: the mesh's (within ~0.2% of the ball's on a coarse mesh); with it
        # DS does not depend on how the mesh lumps the mass (a linear spring k gives DS = k)
        ds = dynamic_stiffness(run.peak_force_n, run.mass_kg, speed)
        result = {"impact_speed_m_s": speed, "rebound_speed_m_s": run.rebound_speed_m_s,
                  **impact_quantities(method, run.cor, ds, run.peak_force_n),
                  "contact_time_s": run.contact_time_s, "mesh_mass_kg": run.mass_kg}
        cost = {"wall_time_s": time.perf_counter() - started, "solver_wall_time_s":
                run.wall_time_s, "steps": run.steps, "elements": run.elements,
                "element_size_m": options.element_size_m}
        if nominal is not None:
            out["nominal_speed_m_s"] = speed
            out["nominal_speed_note"] = (f"run at {speed:g} m/s, not the method's "
                                         f"{method.nominal:g} m/s")
    else:
        curve = compress(ball, method.nominal, steps=steps, options=options)
        result = {"deflection_m": method.nominal,
                  **compression_quantities(curve.force_at(method.nominal))}
        cost = {"wall_time_s": time.perf_counter() - started, "solver_wall_time_s":
                curve.wall_time_s, "compile_time_s": curve.compile_time_s,
                "increments": curve.increments, "newton_iterations": curve.newton_iterations,
                "elements": curve.elements, "element_size_m": options.element_size_m}
    out["result"] = result
    out["cost"] = cost
    return out
