"""Angle sweeps of oblique impacts, as a library function: one ball at one speed, friction and
spin, several angles from the normal in one vmapped 3D run (`fe.simulate_batch` on
`fe.Hexahedral`), a row per angle in Maw, Barber & Fawcett's normalised axes, and, where it
applies, the elastic-sphere reference (`elastic_reference.normalised_curves`) with a note on
what it leaves out. `ballimpact simulate --solver 3d --angle-deg A,B,...` prints and plots it."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..fe.engine import Hexahedral, simulate_batch
from ..fe.estimates import hertz_contact_radius_m
from ..fe.options import ImpactCondition
from ..checks import allowed_range, check_range
from ..errors import InputError
from ..fe.output import RunFiles
from ..fe.runs import impact_inputs, started
from .elastic_reference import normalised_curves
from .rigid_body import normalised_incidence, normalised_spin

#: the reference's curves: points, and the smallest Psi
REFERENCE_POINTS = 200
REFERENCE_PSI_MIN = 0.05
#: a row's fields, in order (the --table columns)
ROW_FIELDS = ("angle_deg", "psi", "normal_cor", "tangential_cor", "contact_point_tangential_cor",
              "rebound_angle_deg", "rebound_spin_rad_s", "normalised_spin", "peak_force_n",
              "contact_time_s", "energy_balance_error", "steps")


#: the angles a sweep accepts (deg from the normal; `ImpactCondition.angle_deg`'s range)
ANGLE_RANGE_DEG = (0.0, 89.0)


def parse_angles(text: str) -> tuple[float, ...]:
    """Angles from the surface normal (deg) from a comma-separated list ("5,10,20"): each item a
    number in `ANGLE_RANGE_DEG` (`checks.check_range`), none empty, none given twice (a repeated
    angle would look like two points). Their order is kept. Raises `InputError` naming the item
    and the allowed range."""
    allowed = f"allowed range {allowed_range(*ANGLE_RANGE_DEG, unit='deg')}"
    angles: list[float] = []
    for k, item in enumerate(text.split(","), 1):
        where = f"item {k} of {text!r}"
        if not item.strip():
            raise InputError(f"{where}: empty; give angles separated by commas, e.g. 5,10,20 "
                             f"({allowed})")
        try:
            value = float(item)
        except ValueError:
            raise InputError(f"{where}: {item.strip()!r} is not a number ({allowed})") from None
        check_range(f"{where}: angle_deg", value, *ANGLE_RANGE_DEG, unit="deg")
        if value in angles:
            raise InputError(f"{where}: {value:g} deg is given twice; give each angle once "
                             f"({allowed})")
        angles.append(value)
    return tuple(angles)


def ball_k2(ball) -> float:
    """k^2 = I / (m R^2) of a layered ball at rest (concentric uniform shells; 0.4 for one
    layer): I = sum 8 pi rho (r_o^5 - r_i^5) / 15, m = sum 4 pi rho (r_o^3 - r_i^3) / 3."""
    inertia = mass = inner = 0.0
    for layer in ball.layers:
        outer, rho = layer.outer_radius_m, layer.density_kg_m3
        inertia += 8.0 * math.pi * rho * (outer ** 5 - inner ** 5) / 15.0
        mass += 4.0 * math.pi * rho * (outer ** 3 - inner ** 3) / 3.0
        inner = outer
    return inertia / (mass * ball.outer_radius_m ** 2)


def small_strain_poissons_ratio(material) -> float:
    """Poisson's ratio of a material's small-strain (instantaneous) moduli: from the shear modulus
    G and the P-wave modulus M = K + 4 G / 3, nu = (3 K - 2 G) / (2 (3 K + G))."""
    shear = material.shear_modulus_pa()
    bulk = material.wave_modulus_pa() - 4.0 * shear / 3.0
    return (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear))


def reference_obstacle(ball, target, condition) -> str | None:
    """Why the elastic-sphere reference (a homogeneous elastic sphere on a rigid plane, no initial
    spin, Coulomb friction) does not describe this sweep, or None when it does."""
    if len(ball.layers) != 1:
        return f"the ball has {len(ball.layers)} layers (the reference is a homogeneous sphere)"
    material = ball.layers[0].material
    if material.prony:
        terms = len(material.prony)
        return (f"the ball's {material.model} material is viscoelastic ({terms} Prony "
                f"term{'s' if terms > 1 else ''}; the reference is elastic)")
    if target is not None:
        return f"the target is a slab ({target.name}; the reference is the rigid plane)"
    if any(condition.spin_vector_rad_s):
        return "the ball spins before impact (the reference has no initial spin)"
    if condition.friction <= 0.0:
        return "there is no friction (the normalised axes divide by mu)"
    return None


def gripping_reference(ball, target, condition, psi_max: float,
                       fastest_normal_speed_m_s: float | None = None) -> tuple[dict | None, str]:
    """The elastic-sphere reference curves (Maw, Barber & Fawcett; `normalised_curves`) for the
    sweep, on `REFERENCE_POINTS` values of Psi from `REFERENCE_PSI_MIN` to max(12, 1.1 psi_max),
    at the ball's small-strain Poisson's ratio, with a note; or (None, why not)."""
    obstacle = reference_obstacle(ball, target, condition)
    if obstacle is not None:
        return None, f"no elastic-sphere reference: {obstacle}"
    nu = small_strain_poissons_ratio(ball.layers[0].material)
    top = max(12.0, 1.1 * psi_max) if math.isfinite(psi_max) else 12.0
    curves = normalised_curves(np.linspace(REFERENCE_PSI_MIN, top, REFERENCE_POINTS), nu)
    # the theory leaves out the normal-tangential coupling (Dundurs' beta on a rigid plane) and
    # the contact's finite size: say where this sweep stands (docs/oblique.md, gripping regime)
    beta = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu))
    speed = condition.speed_m_s if fastest_normal_speed_m_s is None else fastest_normal_speed_m_s
    a_over_r = hertz_contact_radius_m(ball, speed) / ball.outer_radius_m
    note = (f"elastic sphere on a rigid plane, Hertz normally and Mindlin-Deresiewicz "
            f"tangentially (Maw, Barber & Fawcett 1976, 1981), nu = {nu:.4g} from the ball's "
            f"small-strain moduli, k^2 = 0.4, no initial spin; it leaves out the coupling "
            f"(beta = {beta:.3g}) and the contact's size (a / R up to {a_over_r:.3g}); with "
            "mu >= 1.4 beta, a / R < 0.1 and the mesh and penalty the defaults choose for a "
            "small contact (3 elements across a, penalty 3) the FE was within 0.02 of its e_t "
            "from Psi 0.5 to 10; with penalty 1 it reverses too little below Psi 3 "
            "(docs/oblique.md, the gripping regime)")
    return {"poissons_ratio": nu, "curves": {k: v.tolist() for k, v in curves.items()},
            "note": note, "coupling_beta": beta, "contact_radius_over_radius": a_over_r}, note


def run_row(result) -> dict[str, Any]:
    """A run's row (SI): its angle, Psi and Omega (normalised with its own normal COR), CORs,
    rebound angle and spin, peak force, contact time, energy balance error and steps."""
    c = result.condition
    theta = math.radians(c.angle_deg)
    v_x, v_n = c.speed_m_s * math.sin(theta), c.speed_m_s * math.cos(theta)
    e_n, radius = result.normal_cor, result.outer_radius_m
    with_friction = c.friction > 0.0
    return {"angle_deg": c.angle_deg,
            "psi": float(normalised_incidence(v_x, v_n, c.spin_rad_s, radius, c.friction, e_n))
            if with_friction else math.nan,
            "normal_cor": result.normal_cor, "tangential_cor": result.tangential_cor,
            "contact_point_tangential_cor": result.contact_point_tangential_cor,
            "rebound_angle_deg": result.rebound_angle_deg,
            "rebound_spin_rad_s": result.rebound_spin_rad_s,
            "normalised_spin": float(normalised_spin(result.rebound_spin_rad_s, radius, c.friction,
                                                     e_n, v_n)) if with_friction else math.nan,
            "peak_force_n": result.peak_force_n, "contact_time_s": result.contact_time_s,
            "energy_balance_error": result.energy_balance_error, "steps": result.steps}


@dataclass(frozen=True)
class AngleSweep:
    """An angle sweep (SI): the runs (`fe.ImpactResult`s, ascending angles), their rows
    (`run_row`), the elastic-sphere reference (None where it does not apply) and its note, the
    ball's k^2 and the batch's wall time (s)."""

    results: list
    rows: list[dict[str, Any]]
    reference: dict | None
    reference_note: str
    k2: float
    wall_time_s: float


def angle_sweep(ball, condition: ImpactCondition, angles_deg, *,
                geometry: Hexahedral | None = None, target=None, progress=None,
                allow=(), start=None, announce: str = "") -> AngleSweep:
    """`condition` (speed, friction, spins) at each of `angles_deg` (from the normal) in one
    vmapped run on `geometry` (default `fe.Hexahedral()`) and `target` (None: the rigid
    plane); the checks and warnings are `fe.simulate_batch`'s. With `start`, the batch's cost is
    estimated before anything is meshed and `start(estimate)` gives the progress callback
    (`fe.runs.started`, with `announce`)."""
    conditions = [replace(condition, angle_deg=float(a)) for a in sorted(angles_deg)]
    geometry = geometry or Hexahedral()
    if start is not None:
        progress = started(start, ball, conditions, geometry, target=target, allow=allow,
                           announce=announce)
    began = time.perf_counter()
    results = simulate_batch(ball, conditions, geometry=geometry, target=target,
                             progress=progress, allow=allow)
    wall = time.perf_counter() - began
    rows = [run_row(r) for r in results]
    psi = [row["psi"] for row in rows if math.isfinite(row["psi"])]
    fastest = max(c.speed_m_s * math.cos(math.radians(c.angle_deg)) for c in conditions)
    reference, note = gripping_reference(ball, target, conditions[0],
                                         max(psi, default=math.nan), fastest)
    return AngleSweep(results, rows, reference, note, ball_k2(ball), wall)


def angle_sweep_summary(sweep: AngleSweep, ball) -> dict[str, Any]:
    """An angle sweep's JSON object (SI): the ball's name, the speed, friction and spin the
    runs share, the target, mesh (with the pole grading and penalty chosen for the batch), k^2,
    the batch's wall time, the rows ("runs"), the reference and its note ("plot": None until
    one is written)."""
    first = sweep.results[0]
    c = first.condition
    return {"ball": ball.name, "speed_m_s": c.speed_m_s, "friction": c.friction,
            "spin_rad_s": c.spin_rad_s, "target": first.target, "elements": first.elements,
            "pole_grading": first.pole_grading, "penalty_scale": first.penalty_scale,
            "half_model": first.half_model, "k2": sweep.k2, "wall_time_s": sweep.wall_time_s,
            "runs": sweep.rows, "reference": sweep.reference,
            "reference_note": sweep.reference_note, "plot": None}


def plot_angle_sweep(sweep: AngleSweep, path, ball) -> str:
    """The sweep's gripping plot (`plots.plot_gripping`: rebound spin and tangential COR in Maw
    et al.'s normalised axes, the rigid-body lines and, where it applies, the elastic
    reference), titled with the ball, speed, friction and target; returns the PNG's path."""
    from .plots import plot_gripping

    first, reference = sweep.results[0], sweep.reference
    c = first.condition
    plot_gripping(sweep.results, path, reference=reference["curves"] if reference else None,
                  title=f"{ball.name}: angle sweep at {c.speed_m_s:g} m/s, mu {c.friction:g} "
                        f"(3D FE, {first.target})",
                  k2=sweep.k2, poissons_ratio=reference["poissons_ratio"] if reference else None)
    return str(path)


def simulate_angles(spec, speed_m_s: float, angles_deg, geometry: Hexahedral | None = None, *,
                    spin_rad_s: float = 0.0, spin_x_rad_s: float = 0.0,
                    spin_z_rad_s: float = 0.0, friction: float = 0.0, target=None,
                    moduli: str | None = None, allow=(), files: RunFiles = RunFiles(),
                    start=None) -> dict[str, Any]:
    """An angle sweep as `ballimpact simulate --solver 3d --angle-deg 5,10,20` makes it: ball
    `spec` at `speed_m_s` (m/s), spins (rad/s) and `friction` at each of `angles_deg` (deg from
    the normal) in one batched 3D run (`angle_sweep`), on `target` (a preset or file, or None);
    every input checked first (`fe.runs.impact_inputs`; a history, series or animation of one
    run is refused, and a plot without friction, whose normalised axes divide by it). Returns
    its JSON object (`angle_sweep_summary`) with the row table and the plot of `files`
    written."""
    from ..fe.sweep import write_table

    files.refuse("vtk", "animation", "csv",
                 why="an angle sweep writes a row per angle with --table (or give one angle)")
    angles = sorted(float(a) for a in angles_deg)
    allow, ball, slab, geometry = impact_inputs(spec, speed_m_s, geometry or Hexahedral(), files,
                                                friction=friction, target=target,
                                                moduli=moduli, allow=allow)
    first = ImpactCondition(speed_m_s, angles[0], spin_rad_s, friction, spin_x_rad_s,
                            spin_z_rad_s)
    if files.plot is not None and friction <= 0.0:
        raise InputError("--plot: the normalised axes of an angle sweep divide by the friction; "
                         "give --friction > 0")
    announce = (f"simulating {ball.name} in 3D at {speed_m_s:g} m/s, {len(angles)} angles "
                f"({', '.join(f'{a:g}' for a in angles)} deg) in one batched run ...")
    sweep = angle_sweep(ball, first, angles, geometry=geometry, target=slab, allow=allow,
                        start=start, announce=announce)
    out = angle_sweep_summary(sweep, ball)
    if files.table is not None:
        out["table"] = write_table(sweep.rows, files.table)
    if files.plot is not None:
        out["plot"] = plot_angle_sweep(sweep, files.plot, ball)
    return out
