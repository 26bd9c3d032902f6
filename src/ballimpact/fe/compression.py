"""Quasi-static compression of a whole (layered) ball between two rigid, frictionless platens, on
either geometry of the engine (`fe.Axisymmetric`, the default, or `fe.Hexahedral`).

The ball rests on the platen z = 0 with its south pole; a second platen, parallel to it, comes
down on the north pole by the deflection D (m), the change of the ball's diameter between the
platens. The mesh, materials and energies are those of the impact engine on that geometry (the
kernel's internal nodal forces, hourglass control or F-bar, Prony update); there is no inertia
and no bulk viscosity. Each deflection increment solves the equilibrium f_int(u) = f_contact(u)
by Newton's method with a sparse tangent (`fe.platens`). The driver reaches the geometry only
through the object passed to it: `for_compression` (its settings for a static solve and the
platens' contact), `platen_element_m`, `build` and `compression_model` (a `platens.PlatenModel`).

Viscoelastic layers: with `rate_m_s` the platen moves at that speed, so an increment lasts
dD / rate (s) and the Prony states are advanced by it and committed after each converged
increment (Simo's update, as in the impact solver: exact for a piecewise-linear stress history).
Without a rate the curve is the long-term one (fully relaxed: the limit of a slow laboratory test,
whose seconds are far above the milliseconds of a ball's relaxation times).
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import jax
import numpy as np

from ..checks import check_integer, check_range, is_finite_number, range_text, shown
from ..constitutive.stability import drucker_warnings
from ..errors import InputError, InputWarning, SimulationError
from ..progress import waits_announced
from .options import COMPRESSION_PENALTY_SCALE, SolverOptions
from .platens import PlatenModel, PlatenSolver, platen_functions, tangent_pattern
from .programs import CompileWait

__all__ = ["CompressionResult", "compress", "compress_ball", "check_compression_input",
           "compression_options"]

#: Prony increment (s) that stands for "fully relaxed" (exp(-dt/tau) is 0 for any tau)
RELAXED_DT_S = 1e30
#: halvings of an increment whose Newton iteration fails before the run gives up
MAX_INCREMENT_CUTS = 6

#: The compression's own mesh (`compression_options`): both poles refined so that about this many
#: elements span the Hertz contact radius sqrt(R D / 2) at the full deflection D (5-7: the pole
#: size is taken on a ladder, below). Against a reference of 20 elements and a 100x penalty the
#: force is then within 1.3% on elastic spheres (nu 0.3, 0.49; D / 2R = 0.25-5%;
#: benchmarks/bench_compress_hertz.py, docs/materials.md).
CONTACT_ELEMENTS = 5
#: Pole element sizes are the element size divided by powers of this ratio, so that nearby
#: deflections share a mesh and its compiled programs.
POLE_SIZE_RATIO = math.sqrt(2.0)
#: The refined zone spans this many contact radii of arc from each pole.
ZONE_CONTACT_RADII = 2.5
#: Fewer elements than this across the contact radius at the full deflection get a warning.
RESOLVED_CONTACT_ELEMENTS = 3.0


@dataclass(frozen=True, eq=False)
class CompressionResult:
    """A force-deflection curve of a ball between two platens (SI). `deflection_m[0]` = 0."""

    ball_name: str
    deflection_m: np.ndarray
    force_n: np.ndarray
    rate_m_s: float | None           # None: the long-term (fully relaxed) curve
    outer_radius_m: float
    stretch_range: tuple[float, float]
    increments: int                 # converged increments (more than `steps` after cuts)
    newton_iterations: int
    max_force_imbalance: float      # max |F_bottom - F_top| / F_top over the curve
    elements: int
    nodes: int
    jacobian_products: int          # Jacobian-vector products per tangent (colours x 2)
    integration: str
    geometry: str                   # "axisymmetric" or "3d"
    compile_time_s: float
    wall_time_s: float
    moduli: tuple[str, ...] = ()

    @property
    def peak_force_n(self) -> float:
        return float(np.max(self.force_n))

    @property
    def end_stiffness_n_m(self) -> float:
        """dF/dD at the end of the curve (N/m): the slope of its last increment."""
        d, f = self.deflection_m, self.force_n
        return float((f[-1] - f[-2]) / (d[-1] - d[-2]))

    @property
    def secant_stiffness_n_m(self) -> float:
        """F/D at the end of the curve (N/m)."""
        return float(self.force_n[-1] / self.deflection_m[-1])

    def force_at(self, deflection_m) -> np.ndarray:
        """The force (N) at deflections within the curve (m), by linear interpolation."""
        return np.interp(deflection_m, self.deflection_m, self.force_n)

    def record(self) -> dict[str, list[float]]:
        """The curve as lists: `deflection_m`, `force_n` (and `time_s` with a rate)."""
        out = {"deflection_m": self.deflection_m.tolist(), "force_n": self.force_n.tolist()}
        if self.rate_m_s is not None:
            out["time_s"] = (self.deflection_m / self.rate_m_s).tolist()
        return out

    def summary(self) -> dict[str, Any]:
        """The scalar results, JSON-able, with SI unit suffixes."""
        return {"ball": self.ball_name, "deflection_m": float(self.deflection_m[-1]),
                "rate_m_s": self.rate_m_s,
                "curve": "rate" if self.rate_m_s is not None else "long_term",
                "peak_force_n": self.peak_force_n,
                "end_stiffness_n_m": self.end_stiffness_n_m,
                "secant_stiffness_n_m": self.secant_stiffness_n_m,
                "principal_stretch_range": list(self.stretch_range),
                "increments": self.increments, "newton_iterations": self.newton_iterations,
                "max_force_imbalance": self.max_force_imbalance,
                "elements": self.elements, "nodes": self.nodes,
                "jacobian_products": self.jacobian_products, "integration": self.integration,
                "geometry": self.geometry,
                "outer_radius_m": self.outer_radius_m,
                "moduli": self.moduli[0] if len(set(self.moduli)) == 1 else list(self.moduli),
                "compile_time_s": self.compile_time_s, "wall_time_s": self.wall_time_s}

    def to_dict(self) -> dict[str, Any]:
        """`summary()` with the curve's lists (`deflection_m` then holds the list)."""
        return {**self.summary(), **self.record()}


#: fastest platen (m/s): the top of the impact speeds the FE solver is checked for
#: (the `speed-range` check); a faster one is no quasi-static test (and mostly mm/s as m/s)
MAX_RATE_M_S = 80.0


def check_compression_input(ball, deflection_m, rate_m_s=None, steps=20) -> None:
    """InputError (one line naming the argument and its range, `checks`' shape) for a deflection
    outside (0, radius] (a deflection above the radius is most likely millimetres given as
    metres, and named so), a rate outside (0, `MAX_RATE_M_S`] m/s (mm/s named) or a step count
    that is not an integer >= 1."""
    radius = ball.outer_radius_m
    try:
        d = float(deflection_m)
    except (TypeError, ValueError):
        d = deflection_m  # refused below, shown as given
    if is_finite_number(d) and d > radius:
        where = ("at or above the ball's diameter" if d >= 2 * radius else
                 "above the ball's radius: squashed to less than half its diameter")
        raise InputError(range_text("deflection_m", d, "allowed range", 0.0, radius,
                                    low_open=True, unit="m", note=where)
                         + _mm_hint(d, radius))
    check_range("deflection_m", d, 0.0, radius, low_open=True, unit="m",
                note="the platens' approach, up to the ball's radius")
    if rate_m_s is not None:
        try:
            r = float(rate_m_s)
        except (TypeError, ValueError):
            r = rate_m_s
        if is_finite_number(r) and r > MAX_RATE_M_S:
            raise InputError(range_text(
                "rate_m_s", r, "allowed range", 0.0, MAX_RATE_M_S, low_open=True, unit="m/s",
                note="faster than the impacts the solvers are checked for, where no "
                     "inertia-free solve holds") + f"; mm/s given as m/s? {r:g} mm/s is "
                f"{r * 1e-3:g} m/s")
        check_range("rate_m_s", r, 0.0, MAX_RATE_M_S, low_open=True, unit="m/s",
                    note="the platen speed; leave it out for the long-term, fully relaxed curve")
    check_integer("steps", steps, 1)


def _mm_hint(d: float, radius_m: float) -> str:
    """'; millimetres given as metres? (5 mm is 0.005 m)' where d / 1000 fits the ball."""
    if d >= 0.1 and d * 1e-3 <= radius_m:  # 0.1 mm and more, typed in mm
        return f"; millimetres given as metres? ({d:g} mm is {d * 1e-3:g} m)"
    return ""


def hertz_platen_radius_m(ball, deflection_m: float) -> float:
    """The Hertz contact radius (m) of each platen at the deflection `deflection_m` (m): each
    contact approaches D / 2, so a = sqrt(R D / 2), whatever the materials."""
    return math.sqrt(ball.outer_radius_m * 0.5 * float(deflection_m))


def compression_options(ball, deflection_m: float,
                        element_size_m: float = SolverOptions.element_size_m) -> SolverOptions:
    """The mesh and contact `compress` uses by default: elements of `element_size_m` (m) away
    from the poles, both poles refined to about `CONTACT_ELEMENTS` elements across the contact
    radius at `deflection_m` (m), and the platens' `options.COMPRESSION_PENALTY_SCALE`."""
    check_compression_input(ball, deflection_m)
    radius = hertz_platen_radius_m(ball, deflection_m)
    pole = element_size_m
    while pole > radius / CONTACT_ELEMENTS and pole > 1e-3 * element_size_m:
        pole /= POLE_SIZE_RATIO
    if pole >= element_size_m:
        return SolverOptions(element_size_m=element_size_m,
                             penalty_scale=COMPRESSION_PENALTY_SCALE)
    zone = math.degrees(ZONE_CONTACT_RADII * CONTACT_ELEMENTS * pole / ball.outer_radius_m)
    return SolverOptions(element_size_m=element_size_m, pole_element_size_m=pole,
                         pole_zone_deg=min(max(zone, 5.0), 45.0), both_poles=True,
                         penalty_scale=COMPRESSION_PENALTY_SCALE)


def unresolved_contact_note(ball, deflection_m: float, platen_element_m: float) -> str | None:
    """A note when the contact radius at `deflection_m` (m) spans fewer than
    `RESOLVED_CONTACT_ELEMENTS` elements of `platen_element_m` (m, the mesh's element at a
    platen, `geometry.platen_element_m`); None otherwise."""
    radius = hertz_platen_radius_m(ball, deflection_m)
    size = platen_element_m
    if radius >= RESOLVED_CONTACT_ELEMENTS * size:
        return None
    return (f"contact not resolved: at a deflection of {deflection_m:g} m the platens' contact "
            f"radius (Hertz, about {radius * 1e3:.3g} mm) spans {radius / size:.2g} elements of "
            f"{size * 1e3:.3g} mm, fewer than {RESOLVED_CONTACT_ELEMENTS:g}: the force reads "
            "low (an elastic sphere of nu 0.3 on a uniform 1.5 mm mesh by 12-16% at 0.25-1% of its "
            "diameter, docs/materials.md); leave the mesh to compress (no geometry or options; "
            "3D: pole_grading None)")


def compression_geometry(ball, deflection_m: float, geometry=None, options=None):
    """The geometry `compress` solves on: `geometry` (or `options` as in `fe.simulate`:
    `SolverOptions` -> `Axisymmetric`, `Options3D` -> `Hexahedral`) with what it leaves to the
    contact chosen for the platens' (`for_compression`: float64, no bulk viscosity; a 3D
    geometry's pole grading from `hex.geometry.COMPRESSION_CONTACT_ELEMENTS` across the Hertz
    radius and the platen penalty `COMPRESSION_PENALTY_SCALE`); neither given: `Axisymmetric(compression_options)`,
    a mesh that resolves the contact at this deflection. A mesh given that leaves it unresolved
    gets an `InputWarning` (`unresolved_contact_note`)."""
    from .engine import Axisymmetric, _geometry

    geometry = _geometry(geometry, options)
    if geometry is None:
        geometry = Axisymmetric(compression_options(ball, deflection_m))
    chosen = geometry.for_compression(ball, hertz_platen_radius_m(ball, deflection_m))
    note = unresolved_contact_note(ball, deflection_m, chosen.platen_element_m(ball))
    if note is not None:
        warnings.warn(note, InputWarning, stacklevel=3)
    return chosen


#: (tangent pattern, jitted functions) of each kernel compressed, by id (the kernel kept with it)
_PLATEN_PROGRAMS: dict[int, tuple] = {}


def _programs(kernel, model: PlatenModel):
    cached = _PLATEN_PROGRAMS.get(id(kernel))
    if cached is None or cached[0] is not kernel:
        cached = (kernel, tangent_pattern(model), platen_functions(model.internal))
        _PLATEN_PROGRAMS[id(kernel)] = cached
    return cached[1], cached[2]


def compress(ball, deflection_m: float, *, rate_m_s: float | None = None, steps: int = 20,
             geometry=None, options=None, progress=None) -> CompressionResult:
    """The force-deflection curve of `ball` squeezed between two rigid frictionless platens to
    `deflection_m` (m, the platens' approach) in `steps` equal increments.

    `rate_m_s`: platen speed (m/s) for viscoelastic layers (each increment lasts dD / rate);
    None: the long-term (fully relaxed) curve. `geometry`: `fe.Axisymmetric(SolverOptions(...))`
    or `fe.Hexahedral(Options3D(...))` (a half model by default; `options` is short for it, as
    in `fe.simulate`); None: the axisymmetric mesh of `compression_options`, which resolves the
    platens' contact at this deflection (`compression_geometry`). The solve is always in float64
    (Newton needs it) and without bulk viscosity (no motion). `progress(done, total)` is called
    after each increment.
    Raises `InputError` on bad input, `SimulationError` when an increment does not converge
    after `MAX_INCREMENT_CUTS` halvings.
    """
    check_compression_input(ball, deflection_m, rate_m_s, steps)
    from .engine import kernel_for

    geometry = compression_geometry(ball, deflection_m, geometry, options)
    started = time.perf_counter()
    kernel, _ = kernel_for(ball, geometry)
    # a relaxed ball's hourglass springs from its long-term shear modulus (the impact solver
    # takes the instantaneous one; else a g = 0.5 ball's relaxed curve read 2-3% stiff on a
    # 3 mm mesh)
    model = geometry.compression_model(ball, kernel, relaxed=rate_m_s is None)
    pattern, fns = _programs(kernel, model)
    mu = min(layer.material.shear_modulus_pa(False) for layer in ball.layers)
    force_scale = mu * ball.outer_radius_m ** 2 / model.force_factor
    target = float(deflection_m)
    with jax.enable_x64(True):
        solver = PlatenSolver(model, pattern, fns, force_scale)
        mats = model.initial_materials(solver.params)
        compile_start = time.perf_counter()
        with (CompileWait(f"compiling the compression solver for {kernel.geom.n_elements:,} "
                          "elements", f"compression {len(ball.layers)} layers")
              if progress is not None or waits_announced() else contextlib.nullcontext()):
            solver.warm_up(mats)
        compile_time = time.perf_counter() - compile_start
        u = solver.zeros()
        history_u = [u]
        deflections, forces = [0.0], [0.0]
        lam_min, lam_max = 1.0, 1.0
        iterations, imbalance = 0, 0.0
        d_prev = 0.0
        planned = list(np.linspace(0.0, target, steps + 1)[1:])
        cuts = 0
        while planned:
            d_new = planned[0]
            dt = RELAXED_DT_S if rate_m_s is None else (d_new - d_prev) / float(rate_m_s)
            guess = solver.predict(history_u, deflections, d_new)
            outcome = solver.solve(guess, mats, dt, d_new)
            if outcome is None:  # not converged: cut the increment
                cuts += 1
                if cuts > MAX_INCREMENT_CUTS:
                    raise SimulationError(
                        f"ball {ball.name}: compression did not converge at a deflection of "
                        f"{d_new:.4g} m after {MAX_INCREMENT_CUTS} cuts of the increment (try "
                        "more --steps, a finer mesh or full integration)")
                planned.insert(0, 0.5 * (d_prev + d_new))
                continue
            cuts = 0
            planned.pop(0)
            u, its, f_top, f_bottom = outcome
            iterations += its
            mats, (l_min, l_max) = solver.commit(u, mats, dt)
            lam_min, lam_max = min(lam_min, l_min), max(lam_max, l_max)
            imbalance = max(imbalance, abs(f_bottom - f_top) / max(f_top, 1e-300))
            history_u.append(u)
            deflections.append(d_new)
            forces.append(model.force_factor * f_top)
            d_prev = d_new
            if progress is not None:
                progress(len(deflections) - 1, len(deflections) - 1 + len(planned))
    for message in drucker_warnings(ball, lam_min, lam_max):
        warnings.warn(f"{message}: principal stretches in this range occurred in the ball "
                      "(in some layer)", InputWarning, stacklevel=2)
    return CompressionResult(
        ball_name=ball.name, deflection_m=np.array(deflections), force_n=np.array(forces),
        rate_m_s=None if rate_m_s is None else float(rate_m_s),
        outer_radius_m=ball.outer_radius_m, stretch_range=(lam_min, lam_max),
        increments=len(deflections) - 1, newton_iterations=iterations,
        max_force_imbalance=imbalance, elements=kernel.geom.n_elements, nodes=model.n_nodes,
        jacobian_products=pattern.products, integration=geometry.options.integration,
        geometry=geometry.solver, compile_time_s=compile_time,
        wall_time_s=time.perf_counter() - started,
        moduli=tuple(layer.material.moduli for layer in ball.layers))


def compress_ball(ball: str, deflection_m: float, *, rate_m_s: float | None = None,
                  steps: int = 20, impact_speed_m_s: float | None = None,
                  solver: str = "axisymmetric",
                  element_size_m: float = SolverOptions.element_size_m,
                  divisions: int | None = None, pole_grading: float | None = None,
                  full_model: bool = False, integration: str = SolverOptions.integration,
                  penalty_scale: float = COMPRESSION_PENALTY_SCALE, moduli: str | None = None,
                  allow=(), csv_path: Path | None = None, plot_path: Path | None = None,
                  progress=None) -> dict[str, Any]:
    """`ballimpact compress`: the ball `ball` (preset or specification file; its constants at
    `impact_speed_m_s` (m/s) where they depend on the speed; `moduli` overriding its convention)
    compressed to `deflection_m` (m) by `compress` with `integration` and `penalty_scale`, on
    the `solver`'s mesh: "axisymmetric", `compression_options`' mesh of `element_size_m` (m);
    "3d", hexahedra of `divisions` (default 16) graded to the platens by `pole_grading`
    (default: chosen for the contact), the half model unless `full_model`. Writes the curve to
    `csv_path` (`output.write_curve`: deflection_m,force_n) and its picture to `plot_path` (PNG)
    when given. Returns `CompressionResult.to_dict()` with the ball's `materials` and the paths
    written (`csv`, `plot`). Raises `InputError` (naming --plot, --csv, or the argument) on bad
    input before anything runs, and what `compress` raises."""
    from ..checks import check_allow
    from ..fileio import check_output_file, check_plot_path
    from .engine import Axisymmetric, Hexahedral
    from .options import Options3D
    from .output import plot_curve, write_curve
    from .runs import load_model

    if solver not in ("axisymmetric", "3d"):
        raise InputError(f"solver = {shown(solver)}: allowed axisymmetric, 3d")
    check_plot_path(plot_path)
    check_output_file(csv_path, "--csv", ".csv")
    allow = check_allow(allow)
    model = load_model(ball, impact_speed_m_s, moduli=moduli, allow=allow)
    if solver == "3d":
        geometry = Hexahedral(Options3D(
            divisions=Options3D.divisions if divisions is None else divisions,
            pole_grading=pole_grading, half=False if full_model else None,
            integration=integration, penalty_scale=penalty_scale))
    else:
        geometry = Axisymmetric(dataclasses.replace(
            compression_options(model, deflection_m, element_size_m), integration=integration,
            penalty_scale=penalty_scale))
    result = compress(model, deflection_m, rate_m_s=rate_m_s, steps=steps, geometry=geometry,
                      progress=progress)
    out = {**result.to_dict(), "materials": model.to_dict()}
    if csv_path is not None:
        out["csv"] = write_curve(csv_path, result)
    if plot_path is not None:
        out["plot"] = str(plot_curve(result, plot_path))
    return out
