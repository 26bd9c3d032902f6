"""`ballimpact simulate --solver 3d --angle-deg 5,10,20,30,45,60`: an angle sweep of the 3D solver.

All angles run as one vmapped batch (`fe.simulate_batch` on `fe.Hexahedral`) at one speed, friction and
spin. Each run is normalised as Maw, Barber & Fawcett (1976) did (`oblique.rigid_body`): incidence
Psi = 2 (v_x - w R) / (mu (1 + e_n) v_n) and rebound spin Omega = w' R / (mu (1 + e_n) v_n),
each with the run's own normal COR e_n. A one-layer ball of a purely elastic material (no Prony
terms) on the rigid plane without initial spin gets the elastic-sphere reference of the gripping
regime (`oblique.elastic_reference.normalised_curves`) at its small-strain Poisson's ratio.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import replace
from typing import Any

from ..checks import allowed_range, check_range
from ..errors import InputError

#: the angles a sweep accepts (deg from the normal; `ImpactCondition.angle_deg`'s range)
ANGLE_RANGE_DEG = (0.0, 89.0)
_RANGE = f"allowed range {allowed_range(*ANGLE_RANGE_DEG, unit='deg')}"
#: points of the elastic reference curves (Psi from `REFERENCE_PSI_MIN` to max(12, 1.1 max Psi))
REFERENCE_POINTS = 200
REFERENCE_PSI_MIN = 0.05
#: the fields of a run's row, in the table's order (SI; dimensionless where no unit is named)
ROW_FIELDS = ("angle_deg", "psi", "normal_cor", "tangential_cor", "contact_point_tangential_cor",
              "rebound_angle_deg", "rebound_spin_rad_s", "normalised_spin", "peak_force_n",
              "contact_time_s", "energy_balance_error", "steps")


def parse_angles(text: str) -> tuple[float, ...]:
    """Angles from the surface normal (deg) from a comma-separated list ("5,10,20"): each item a
    number in `ANGLE_RANGE_DEG` (`checks.check_range`), none empty, none given twice (a repeated
    angle would look like two points). Their order is kept. Raises `InputError` naming the item
    and the allowed range."""
    items = text.split(",")
    angles: list[float] = []
    for k, item in enumerate(items, 1):
        where = f"item {k} of {text!r}"
        if not item.strip():
            raise InputError(f"{where}: empty; give angles separated by commas, e.g. 5,10,20 "
                             f"({_RANGE})")
        try:
            value = float(item)
        except ValueError:
            raise InputError(f"{where}: {item.strip()!r} is not a number ({_RANGE})") from None
        check_range(f"{where}: angle_deg", value, *ANGLE_RANGE_DEG, unit="deg")
        if value in angles:
            raise InputError(f"{where}: {value:g} deg is given twice; give each angle once "
                             f"({_RANGE})")
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
    import numpy as np

    from ..fe.estimates import hertz_contact_radius_m
    from ..oblique.elastic_reference import normalised_curves

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
            "mu >= 1.4 beta, a / R < 0.1, --contact-elements 2.9 and --penalty-scale 3 the FE "
            "was within 0.02 of its e_t from Psi 0.5 to 10; with the default penalty it "
            "reverses too little below Psi 3 (docs/oblique.md, the gripping regime)")
    return {"poissons_ratio": nu, "curves": {k: v.tolist() for k, v in curves.items()},
            "note": note, "coupling_beta": beta, "contact_radius_over_radius": a_over_r}, note


def run_row(result) -> dict[str, Any]:
    """A run's row (SI): its angle, Psi and Omega (normalised with its own normal COR), CORs,
    rebound angle and spin, peak force, contact time, energy balance error and steps."""
    from ..oblique.rigid_body import normalised_incidence, normalised_spin

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


def _checked_sweep(args: argparse.Namespace) -> tuple[argparse.Namespace, tuple[float, ...]]:
    """The checks only a sweep has, before the shared ones: the solver, one speed, no per-run
    output. Returns the namespace with one speed (a float) and the angles, ascending."""
    angles = tuple(sorted(float(a) for a in args.angle_deg))
    if args.solver != "3d":
        raise InputError("--angle-deg: a sweep of angles needs --solver 3d")
    speed = args.speed_m_s
    if isinstance(speed, (tuple, list)):
        if len(speed) > 1:
            raise InputError("--speed-m-s: an angle sweep runs at one speed; give one speed with "
                             "a list of --angle-deg (or one angle with a list of speeds)")
        speed = float(speed[0])
    for flag, name, what in (("--vtk", "vtk", "the time series of one run"),
                             ("--animate", "animate", "the animation of one run"),
                             ("--csv", "csv", "the histories of one run")):
        if getattr(args, name, None) is not None:
            raise InputError(f"{flag}: writes {what}; an angle sweep writes a row per angle "
                             "with --table (or give one angle)")
    return argparse.Namespace(**{**vars(args), "speed_m_s": speed}), angles


def run_angle_sweep(args: argparse.Namespace) -> dict[str, Any]:
    """Several `--angle-deg` of one ball at one speed in one batched 3D run: a row per angle, a
    table, a plot in Maw et al.'s normalised axes and, where it applies, the elastic reference."""
    from ..fe import Hexahedral, RunProgress, estimate, simulate_batch
    from ..oblique.plots import plot_gripping
    from .common import use_compilation_cache
    from .simulate import _check_flags, _checked_3d, _checked_allow, _warn_now

    # every check on the input before anything is printed (progress, warnings) or meshed
    args, angles = _checked_sweep(args)
    _check_flags(args)
    allow = _checked_allow(args)
    ball, first, target, options = _checked_3d(
        argparse.Namespace(**{**vars(args), "angle_deg": angles[0]}), allow)
    if args.plot is not None and first.friction <= 0.0:
        raise InputError("--plot: the normalised axes of an angle sweep divide by the friction; "
                         "give --friction > 0")
    conditions = [replace(first, angle_deg=angle) for angle in angles]
    # refused before meshing; the mesh is then built and cached for the run
    geometry = Hexahedral(options)
    cost = estimate(ball, conditions, geometry=geometry, target=target, allow=allow)
    use_compilation_cache()
    print(f"simulating {ball.name} in 3D at {first.speed_m_s:g} m/s, {len(angles)} angles "
          f"({', '.join(f'{a:g}' for a in angles)} deg) in one batched run ...",
          file=sys.stderr, flush=True)
    _warn_now(cost.warning())
    started = time.perf_counter()
    results = simulate_batch(ball, conditions, geometry=geometry, target=target, allow=allow,
                             progress=RunProgress(cost.end_time_s, options.chunk_steps))
    wall = time.perf_counter() - started
    rows = [run_row(r) for r in results]
    psi = [row["psi"] for row in rows if math.isfinite(row["psi"])]
    fastest = max(c.speed_m_s * math.cos(math.radians(c.angle_deg)) for c in conditions)
    reference, note = gripping_reference(ball, target, first, max(psi, default=math.nan), fastest)
    out = {"ball": ball.name, "speed_m_s": first.speed_m_s, "friction": first.friction,
           "spin_rad_s": first.spin_rad_s, "target": results[0].target,
           "elements": results[0].elements, "half_model": results[0].half_model,
           "k2": ball_k2(ball), "wall_time_s": wall, "runs": rows, "reference": reference,
           "reference_note": note, "plot": None}
    if args.table is not None:
        from ..sweep import write_table

        out["table"] = write_table(rows, args.table)
    if args.plot is not None:
        plot_gripping(results, args.plot, reference=reference["curves"] if reference else None,
                      title=f"{ball.name}: angle sweep at {first.speed_m_s:g} m/s, mu "
                            f"{first.friction:g} (3D FE, {results[0].target})",
                      k2=out["k2"], poissons_ratio=reference["poissons_ratio"] if reference
                      else None)
        out["plot"] = str(args.plot)
    if not args.json:
        _print_angle_sweep(out)
    return out


def _print_angle_sweep(out: dict[str, Any]) -> None:
    print(f"{out['ball']} in 3D at {out['speed_m_s']:g} m/s, friction {out['friction']:g}, spin "
          f"{out['spin_rad_s']:g} rad/s on {out['target']}: {len(out['runs'])} angles in one "
          "batched run")
    print(f"{'angle deg':>10}{'Psi':>8}{'normal COR':>11}{'tang COR':>9}{'cp COR':>8}"
          f"{'rebound deg':>12}{'spin rad/s':>11}{'norm spin':>10}")
    for r in out["runs"]:
        print(f"{r['angle_deg']:>10.4g}{r['psi']:>8.3f}{r['normal_cor']:>11.4f}"
              f"{r['tangential_cor']:>9.4f}{r['contact_point_tangential_cor']:>8.4f}"
              f"{r['rebound_angle_deg']:>12.2f}{r['rebound_spin_rad_s']:>11.1f}"
              f"{r['normalised_spin']:>10.3f}")
    steps = [r["steps"] for r in out["runs"]]
    print(f"  {out['wall_time_s']:.2f} s wall for the batch, {out['elements']} hexahedra "
          f"({'half' if out['half_model'] else 'full'} model), {min(steps)}-{max(steps)} steps")
    print(f"  {out['reference_note']}")
    for key in ("table", "plot"):
        if out.get(key) is not None:
            print(f"{key} written to {out[key]}")
