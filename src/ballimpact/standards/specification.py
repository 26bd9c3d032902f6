"""A ball model from a specification's two numbers: its COR off a rigid wall (ASTM F1887) and its
quasi-static compression force at a platen displacement (ASTM F1888), with its size and mass.

The model is a homogeneous universal ball (one Mooney-Rivlin layer, D1 = 0, one Prony term:
`balls.ball.universal_spec`) meshed as `standard --ball` meshes it (`on_model`), so that
`standard cor` and `standard compression` on the ball file give its two numbers back. The two
numbers decouple:

1. The compression is the long-term (fully relaxed) curve, and with C01 / C10, g1 and K / mu0
   held, the stress at a given deformation is proportional to the moduli: the force at the
   displacement is proportional to C10 (exactly: the FE curve is linear in the moduli, tested).
   One compression gives C10; K follows the instantaneous modulus (D1 = 0), so g1 moves it a
   little, and a compression of the ball found checks it.
2. The COR at the standard speed then depends on the Prony term alone. With tau1 held (the
   universal model's choice: the geometric middle of table 6-2's 10-100 us on the 72 mm ball,
   scaled by R / 36 mm), it falls monotonically with g1: one batched FE run over a grid of g1
   brackets the target, and secant steps on FE runs close it to `COR_TOLERANCE`.

A COR that no g1 reaches at that compression stiffness is refused by name: one homogeneous layer
cannot match both numbers, and a layered ball (core and cover, `calibrate`) is the path
(docs/balls.md, "Presets from a specification").
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..balls.ball import UNIVERSAL_RADIUS_M, universal_spec
from ..balls.checks import (check_ball_diameter, check_ball_mass,
                            check_ball_values, check_force_units)
from ..checks import check_metres, check_range
from ..errors import InputError
from ..records.features import dynamic_stiffness
from .methods import QUARTER_INCH_M, SIXTY_MPH_M_S, checked_speed
from .model import method_options

#: The tau1 (s) of a specification ball on the 72 mm reference ball: the geometric middle of the
#: universal model's range (thesis table 6-2, 10-100 us); scaled by R / 36 mm to the ball.
TAU1_REFERENCE_S = math.sqrt(1e-5 * 1e-4)
#: The g1 grid of the bracketing batch (g1 = 0: elastic; 0.95: the instantaneous modulus 20
#: times the long-term one).
G1_GRID = tuple(np.linspace(0.0, 0.95, 8))
#: The COR is matched to this (the presets quote it to 3-4 decimals).
COR_TOLERANCE = 5e-4
#: Secant steps after the bracket, at most.
MAX_SECANT_STEPS = 4
#: The compression force is matched to this fraction ...
FORCE_TOLERANCE = 1e-3
#: ... in this many rounds of C10 and g1 at most.
MAX_ROUNDS = 4
#: g1 of the trial compression.
G1_GUESS = 0.5
#: C10 (Pa) of the trial compression (any value: the force is proportional to it).
TRIAL_C10_PA = 2.0e6
#: Compression forces accepted (N): 1 N to 100 kN, a ball's force at a few mm.
FORCE_RANGE_N = (1.0, 1.0e5)
#: The ball found must give the specification back within these (COR, compression relative):
#: the calibration closes to `COR_TOLERANCE` and `FORCE_TOLERANCE`, so a miss means it did not
#: converge.
CHECK_COR = 0.005
CHECK_COMPRESSION = 0.01


@dataclass(frozen=True)
class Specification:
    """A ball's published numbers (SI): `diameter_m`, `mass_kg`; the `cor` off a rigid wall at
    `impact_speed_m_s` (F1887: 60 mph); the quasi-static `compression_force_n` at the platens'
    approach `compression_deflection_m` (F1888: 0.25 in)."""

    diameter_m: float
    mass_kg: float
    cor: float
    compression_force_n: float
    compression_deflection_m: float = QUARTER_INCH_M
    impact_speed_m_s: float = SIXTY_MPH_M_S

    def checked(self) -> Specification:
        """The specification with every number checked (`InputError` naming it and its range;
        a diameter in mm and a mass in g named as such)."""
        diameter = check_ball_diameter(self.diameter_m, "diameter_m (--diameter-m)")
        mass = check_ball_mass(self.mass_kg, "mass_kg (--mass-kg)")
        radius = 0.5 * diameter
        check_ball_values(f"ball of diameter {diameter:g} m and mass {mass:g} kg",
                          {"density": mass / (4.0 / 3.0 * math.pi * radius ** 3)})
        force = check_range("compression_force_n (--compression-n)", self.compression_force_n,
                            *FORCE_RANGE_N, unit="N")
        deflection = check_metres("compression_deflection_m (--deflection-m)",
                                  self.compression_deflection_m, 0.5 * radius, 1e-4)
        check_force_units(force, deflection, radius,
                          "compression_force_n (--compression-n)")
        return Specification(
            diameter, mass,
            check_range("cor (--cor)", self.cor, 0.0, 1.0, low_open=True, high_open=True),
            force, deflection, checked_speed(self.impact_speed_m_s))


#: Relaxation times accepted (s).
TAU1_RANGE_S = (1e-7, 1e-2)


def check_tau1(tau1_s: float) -> float:
    """A Prony relaxation time (s) in `TAU1_RANGE_S`; one in microseconds or milliseconds is
    named as such."""
    low, high = TAU1_RANGE_S
    if isinstance(tau1_s, (int, float)) and high < tau1_s <= 1e6 * high:
        unit, factor = ("ms", 1e-3) if tau1_s <= 1e3 * high else ("us", 1e-6)
        if low <= tau1_s * factor <= high:
            raise InputError(f"tau1_s (--tau1-s) = {tau1_s:g} s: allowed range "
                             f"[{low:g}, {high:g}] s; looks like {unit}: use {tau1_s * factor:g}")
    return check_range("tau1_s (--tau1-s)", tau1_s, low, high, unit="s")


def ball_for_specification(spec: Specification, name: str = "specification-ball", *,
                           tau1_s: float | None = None, options=None,
                           progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """The homogeneous universal ball meeting `spec` (see the module): C10 from the compression,
    g1 from the COR, C01 = 0, tau1 `tau1_s` (s; default `TAU1_REFERENCE_S` x R / 36 mm).
    `progress(text)` hears each stage. Returns {"ball": the ball specification (JSON form),
    "params": c10_pa, c01_pa, g1, tau1_s, "specification": `spec` as a dict, "check": the FE
    figures of the ball found (cor, compression_force_n, dynamic_stiffness_n_m, peak_force_n,
    contact_time_s, the misses cor_error and compression_relative_error, and "missed": what
    misses `CHECK_COR` or `CHECK_COMPRESSION`, named), "runs": FE
    impacts and compressions made, "wall_time_s"}. `InputError` when no g1 in `G1_GRID`'s span
    reaches the COR."""
    from ..fe import compress, load_ball, simulate_batch

    spec = spec.checked()
    radius = 0.5 * spec.diameter_m
    density = spec.mass_kg / (4.0 / 3.0 * math.pi * radius ** 3)
    tau1 = TAU1_REFERENCE_S * radius / UNIVERSAL_RADIUS_M if tau1_s is None else \
        check_tau1(tau1_s)
    options = method_options(radius) if options is None else options
    say = progress or (lambda text: None)
    started = time.perf_counter()

    def ball(c10: float, g1: float):
        return load_ball(universal_spec({"c10_pa": c10, "c01_pa": 0.0, "g1": g1, "tau1_s": tau1},
                                        radius, density, name=name))

    def force(c10: float, g1: float) -> float:
        curve = compress(ball(c10, g1), spec.compression_deflection_m, options=options)
        counts["compressions"] += 1
        return float(curve.force_at(spec.compression_deflection_m))

    def impacts(c10: float, g1s) -> list:
        counts["impacts"] += len(g1s)
        return simulate_batch([ball(c10, g) for g in g1s], [spec.impact_speed_m_s] * len(g1s),
                              options)

    def match_cor(c10: float, g1: float, slope: float):
        """g1 whose COR is the target's at `c10`, by secant steps from `g1` (the first along
        `slope`, dCOR/dg1), and that impact."""
        points = []
        for step in range(MAX_SECANT_STEPS):
            say(f"impact at g1 {g1:.4f} (C10 {c10 / 1e6:.4g} MPa)")
            run = impacts(c10, [g1])[0]
            if abs(run.cor - spec.cor) <= COR_TOLERANCE or step == MAX_SECANT_STEPS - 1:
                break
            points.append((g1, float(run.cor)))
            if len(points) > 1:
                (g_a, e_a), (g_b, e_b) = points[-2:]
                slope = (e_b - e_a) / (g_b - g_a) if g_b != g_a and e_b != e_a else slope
            g1 = min(max(g1 + (spec.cor - run.cor) / slope, G1_GRID[0]), G1_GRID[-1])
        return g1, run

    counts = {"impacts": 0, "compressions": 0}
    say(f"compression of a trial ball to {spec.compression_deflection_m * 1e3:.3g} mm")
    g1 = G1_GUESS
    c10 = TRIAL_C10_PA * spec.compression_force_n / force(TRIAL_C10_PA, g1)
    say(f"{len(G1_GRID)} impacts at {spec.impact_speed_m_s:.4g} m/s over g1 "
        f"{G1_GRID[0]:g}-{G1_GRID[-1]:g} (one batch)")
    grid = np.array(G1_GRID)
    values = np.array([float(r.cor) for r in impacts(c10, grid)])
    if not values.min() <= spec.cor <= values.max():
        raise InputError(
            f"cor = {spec.cor:g}: a homogeneous ball of {spec.compression_force_n:.4g} N at "
            f"{spec.compression_deflection_m * 1e3:.3g} mm reaches COR {values.min():.3f} to "
            f"{values.max():.3f} at {spec.impact_speed_m_s:.4g} m/s (g1 {grid[0]:g}-"
            f"{grid[-1]:g}, tau1 {tau1 * 1e6:.3g} us): one layer cannot match both numbers; "
            "calibrate a layered ball (core and cover) against both tests (`ballimpact "
            "calibrate`, docs/calibrate.md, 'Layered balls from tests')")
    # the bracket: neighbouring grid points around the target (COR falls with g1)
    above = int(np.flatnonzero(values >= spec.cor).max())
    below = min(above + 1, grid.size - 1)
    slope = (values[below] - values[above]) / (grid[below] - grid[above])
    g1 = float(np.interp(spec.cor, [values[below], values[above]], [grid[below], grid[above]]))
    # D1 = 0 stands for K = 20 times the instantaneous mu0 / (1 - g1), so the long-term ball
    # grows less compressible with g1 and its compression moves a little (+4.6% from g1 0.5 to
    # 0.84): C10 and g1 in turn until both hold
    for _ in range(MAX_ROUNDS):
        g1, run = match_cor(c10, g1, slope)
        say(f"compression at C10 {c10 / 1e6:.4g} MPa, g1 {g1:.4f}")
        check_force = force(c10, g1)
        if abs(check_force / spec.compression_force_n - 1) <= FORCE_TOLERANCE:
            break
        c10 *= spec.compression_force_n / check_force
    params = {"c10_pa": c10, "c01_pa": 0.0, "g1": g1, "tau1_s": tau1}
    check = {"cor": float(run.cor), "cor_error": float(run.cor) - spec.cor,
             "compression_force_n": check_force,
             "compression_relative_error": check_force / spec.compression_force_n - 1,
             "dynamic_stiffness_n_m": dynamic_stiffness(float(run.peak_force_n),
                                                        float(run.mass_kg),
                                                        spec.impact_speed_m_s),
             "peak_force_n": float(run.peak_force_n),
             "contact_time_s": float(run.contact_time_s)}
    check["missed"] = [text for text, miss in (
        (f"COR {check['cor']:.4f} against {spec.cor:g}", abs(check["cor_error"]) > CHECK_COR),
        (f"compression {check_force:.4g} N against {spec.compression_force_n:.4g} N",
         abs(check["compression_relative_error"]) > CHECK_COMPRESSION)) if miss]
    return {"ball": universal_spec(params, radius, density, name=name), "params": params,
            "specification": asdict(spec), "check": check,
            "runs": counts,
            "element_size_m": options.element_size_m,
            "wall_time_s": time.perf_counter() - started}


def write_specified_ball(out: str | Path, diameter_m: float, mass_kg: float, cor: float,
                         compression_force_n: float, *,
                         compression_deflection_m: float | None = None,
                         impact_speed_m_s: float | None = None, tau1_s: float | None = None,
                         name: str | None = None, element_size_m: float | None = None,
                         progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """`ball_for_specification` of a `Specification` (SI; `compression_deflection_m` default
    F1888's 0.25 in, `impact_speed_m_s` F1887's 60 mph), the ball named `name` (default the
    stem of `out`), its mesh's element size `element_size_m` (m; default `method_options`');
    the ball file written to `out` (JSON) only when the FE check holds. Returns
    `ball_for_specification`'s dict, with "out" (the path) when written; a non-empty
    `check["missed"]`: not written. Raises `InputError` for an `out` that is no .json file in an
    existing folder, a number out of its range (naming its flag) or a COR one homogeneous layer
    cannot reach."""
    from ..fe import SolverOptions
    from ..fileio import check_output_folder, write_atomic

    out = Path(out)
    if out.suffix.lower() != ".json":
        raise InputError(f"--out: {out} must be a .json ball file")
    check_output_folder(out, "--out")
    spec = Specification(
        diameter_m, mass_kg, cor, compression_force_n,
        QUARTER_INCH_M if compression_deflection_m is None else compression_deflection_m,
        SIXTY_MPH_M_S if impact_speed_m_s is None else impact_speed_m_s).checked()
    options = None if element_size_m is None else SolverOptions(element_size_m=element_size_m)
    result = ball_for_specification(spec, name or out.stem, tau1_s=tau1_s, options=options,
                                    progress=progress)
    if not result["check"]["missed"]:
        write_atomic(out, json.dumps(result["ball"], indent=2) + "\n")
        result["out"] = str(out)
    return result
