"""A method run on a lab's records: impact records (as `ballimpact features` reads them) and
compression curves (as `calibrate --compression` reads them), one value per shot."""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError, InputWarning
from ..records.loaders import LBF_N
from ..records.options import RecordOptions
from ..balls.checks import check_ball_mass
from .methods import (INCH_M, Method, ball_id_function, checked_speed, get_method,
                      speed_note)
from .results import summarise


def from_records(method: str | Method, paths: list[Path], *, mass_kg: float | None = None,
                 ball_of: str | Callable[[Path], str] | None = None,
                 nominal: float | None = None, options: RecordOptions = RecordOptions()
                 ) -> dict[str, Any]:
    """The method's quantities from a lab's records: `paths` are files or folders (folders give
    their *.csv / *.wav records, `repeats.expand_records`).

    - `mass_kg`: the ball mass (kg) for every impact record, over its side file's; needed by the
      impact methods when a side file lacks it; refused by `compression` (which does not use it).
    - `ball_of`: the ball id of a file (`ball_id_function`: None, a regex or a callable).
    - `nominal`: another inbound speed (m/s) for the impact methods (reported as such), or None
      for the method's.
    - `options`: how an impact record is loaded and processed (`records.RecordOptions`; its
      `mass_kg` replaced by `mass_kg` when given).

    Returns {"method", ..., "source": "records", "shots": [...], "balls": [...], "overall"}.
    """
    from ..records.repeats import expand_records

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
        speed = method.nominal if nominal is None else checked_speed(nominal)
        if mass_kg is not None:
            options = replace(options, mass_kg=mass_kg)
        shots = [_impact_shot(method, path, ball_id(path), speed, options) for path in files]
    out = method.to_dict()
    if method.kind == "impact" and nominal is not None:
        out["nominal_speed_m_s"] = float(nominal)
        out["nominal_speed_note"] = (f"run at {nominal:g} m/s, not the method's "
                                     f"{method.nominal:g} m/s")
    out["source"] = "records"
    out["shots"] = shots
    out.update(summarise(method, shots))
    return out


def _impact_shot(method: Method, path: Path, ball: str, nominal_m_s: float,
                 options: RecordOptions) -> dict[str, Any]:
    """One impact record's quantities (its features through `pipeline.process`)."""
    record = options.load(path)
    if record.mass_kg is None:
        raise InputError(f"{path}: no ball mass; give --mass-kg or mass_kg in its side file "
                         f"{path.with_suffix('.json').name}")
    check_ball_mass(record.mass_kg, f"{path}: mass_kg")
    if record.impact_speed_m_s is None:
        raise InputError(f"{path}: no inbound speed; give impact_speed_m_s in its side file "
                         f"{path.with_suffix('.json').name}")
    features = options.process(record).features
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
    from ..calibrate.compression import read_compression_csv

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
