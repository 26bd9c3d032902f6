"""A method run on a ball model: `fe.simulate` at the method's speed on a rigid plane, or
`fe.compress` to its displacement, with the model's cost."""

from __future__ import annotations

import time
from typing import Any

from ..errors import InputError
from ..records.features import dynamic_stiffness
from .methods import COMPRESSION_STEPS, Method, SIXTY_MPH_M_S, checked_speed, get_method
from .lab import compression_quantities, impact_quantities


def method_options(radius_m: float):
    """The solver options the methods run a ball of `radius_m` (m) on: the universal study's
    mesh scaled to the ball (element size x R / 36 mm)."""
    from ..fe import SolverOptions
    from ..balls.ball import UNIVERSAL_RADIUS_M

    return SolverOptions(element_size_m=SolverOptions().element_size_m * radius_m
                         / UNIVERSAL_RADIUS_M)


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
    from ..fe import SolverOptions, compress, load_ball, simulate

    if options is None and element_size_m is not None:  # checked before the ball is loaded
        options = SolverOptions(element_size_m=element_size_m)
    method = get_method(method)
    if method.kind == "compression" and nominal is not None:
        raise InputError("--impact-speed-m-s: the compression method has no impact speed; "
                         "leave it out")
    speed = SIXTY_MPH_M_S if nominal is None else checked_speed(nominal)
    ball = load_ball(ball_spec, impact_speed_m_s=speed, allow=allow)
    if options is None:
        options = method_options(ball.outer_radius_m)
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
