"""Quasi-static compression of a whole (layered) ball between two rigid, frictionless platens.

The ball rests on the platen z = 0 with its south pole; a second platen, parallel to it, comes
down on the north pole by the deflection D (m), the change of the ball's diameter between the
platens. The mesh, materials and energies are those of the impact solver (`Kernel.internal`:
the same internal nodal forces, hourglass control or F-bar, Prony update); there is no inertia
and no bulk viscosity. Each deflection increment solves the equilibrium

    f_int(u) = f_contact(u)

by Newton's method: the tangent d f_int / du is a sparse matrix assembled from a few Jacobian-
vector products (JAX forward mode) by a distance-2 colouring of the mesh's node graph (columns
that share no row are probed by one product), solved with SuperLU (`scipy.sparse.linalg.spsolve`)
on the free degrees of freedom (radial motion is zero on the axis). The platens are node-to-plane
penalty contacts with the impact solver's springs (`penalty_scale`); the penalty is piecewise
linear, so the Newton iteration is semismooth, with a backtracking line search on the residual.

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
import jax.numpy as jnp
import numpy as np

from ..errors import InputError, InputWarning, SimulationError
from .axi.kernel import Kernel, ball_arrays
from .steps import cast
from ..constitutive.stability import drucker_warnings
from ..checks import shown
from ..progress import waits_announced
from .programs import CompileWait
from .options import COMPRESSION_PENALTY_SCALE, SolverOptions

__all__ = ["CompressionResult", "compress", "compress_ball", "check_compression_input",
           "compression_options"]

#: Prony increment (s) that stands for "fully relaxed" (exp(-dt/tau) is 0 for any tau)
RELAXED_DT_S = 1e30
#: Newton: most iterations per increment, halvings of the line search, increment cuts
MAX_NEWTON_ITERATIONS = 25
MAX_LINE_SEARCH_HALVINGS = 10
MAX_INCREMENT_CUTS = 6
#: converged when the largest residual nodal force is below RESIDUAL_RELATIVE x the platen force
#: or RESIDUAL_ABSOLUTE x mu R^2 (the ball's force scale: mu its smallest long-term shear modulus)
RESIDUAL_RELATIVE = 1e-7
RESIDUAL_ABSOLUTE = 1e-11

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
    """InputError (one line naming the argument and its range) for a deflection outside
    (0, radius] (a deflection above the radius is most likely millimetres given as metres), a rate
    that is not > 0 or a step count that is not an integer >= 1."""
    diameter = 2.0 * ball.outer_radius_m
    try:
        d = float(deflection_m)
    except (TypeError, ValueError):
        raise InputError(f"deflection_m = {shown(deflection_m)}: expected a number (m)") from None
    if not (math.isfinite(d) and d > 0.0):
        raise InputError(f"deflection_m = {shown(deflection_m)}: must be > 0 (m), the platens' "
                         f"approach, below the ball's diameter {diameter:g} m")
    if d >= diameter:
        raise InputError(f"deflection_m = {d:g} m is not below the ball's diameter {diameter:g} m"
                         f"{_mm_hint(d, ball.outer_radius_m)}")
    if d > ball.outer_radius_m:
        raise InputError(f"deflection_m = {d:g} m is above the ball's radius "
                         f"{ball.outer_radius_m:g} m (the ball squashed to less than half its "
                         f"diameter; allowed (0, {ball.outer_radius_m:g}] m)"
                         f"{_mm_hint(d, ball.outer_radius_m)}")
    if rate_m_s is not None:
        try:
            r = float(rate_m_s)
        except (TypeError, ValueError):
            r = math.nan
        if not (math.isfinite(r) and r > 0.0):
            raise InputError(f"rate_m_s = {shown(rate_m_s)}: must be > 0 (m/s), the platen "
                             "speed; leave it out for the long-term (fully relaxed) curve")
        if r > MAX_RATE_M_S:
            raise InputError(f"rate_m_s = {r:g} m/s: above {MAX_RATE_M_S:g} m/s, faster than the "
                             "impacts the solvers are checked for, where no inertia-free solve "
                             f"holds; allowed (0, {MAX_RATE_M_S:g}] m/s (mm/s given as m/s? "
                             f"{r:g} mm/s is {r * 1e-3:g} m/s)")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
        raise InputError(f"steps = {shown(steps)}: must be an integer >= 1")


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


def unresolved_contact_note(ball, deflection_m: float, options: SolverOptions) -> str | None:
    """A note when the contact radius at `deflection_m` (m) spans fewer than
    `RESOLVED_CONTACT_ELEMENTS` elements at a platen on the mesh of `options`; None otherwise."""
    radius = hertz_platen_radius_m(ball, deflection_m)
    # the top platen's pole is refined only with both_poles
    size = (options.pole_element_size_m or options.element_size_m) if options.both_poles \
        else options.element_size_m
    if radius >= RESOLVED_CONTACT_ELEMENTS * size:
        return None
    return (f"contact not resolved: at a deflection of {deflection_m:g} m the platens' contact "
            f"radius (Hertz, about {radius * 1e3:.3g} mm) spans {radius / size:.2g} elements of "
            f"{size * 1e3:.3g} mm, fewer than {RESOLVED_CONTACT_ELEMENTS:g}: the force reads "
            "low (an elastic sphere of nu 0.3 on a uniform 1.5 mm mesh by 12-16% at 0.25-1% of its "
            "diameter, docs/materials.md); leave the mesh to compress (options=None)")


def compress(ball, deflection_m: float, *, rate_m_s: float | None = None, steps: int = 20,
             options: SolverOptions | None = None, progress=None) -> CompressionResult:
    """The force-deflection curve of `ball` squeezed between two rigid frictionless platens to
    `deflection_m` (m, the platens' approach) in `steps` equal increments.

    `rate_m_s`: platen speed (m/s) for viscoelastic layers (each increment lasts dD / rate);
    None: the long-term (fully relaxed) curve. `options`: the mesh, integration and contact
    penalty (`SolverOptions`); None: `compression_options`, a mesh that resolves the platens'
    contact at this deflection; options that leave it unresolved get an `InputWarning`. The
    solve is always in float64 (Newton needs it) and without bulk viscosity (no motion).
    `progress(done, total)` is called after each increment.
    Raises `InputError` on bad input, `SimulationError` when an increment does not converge
    after `MAX_INCREMENT_CUTS` halvings.
    """
    check_compression_input(ball, deflection_m, rate_m_s, steps)
    from .engine import Axisymmetric, kernel_for

    if options is None:
        options = compression_options(ball, deflection_m)
    else:
        note = unresolved_contact_note(ball, deflection_m, options)
        if note is not None:
            warnings.warn(note, InputWarning, stacklevel=2)

    started = time.perf_counter()
    # float64 (Newton), no bulk viscosity (no motion)
    options = dataclasses.replace(options, precision="float64", bulk_viscosity_linear=0.0,
                                  bulk_viscosity_quadratic=0.0)
    kernel, _ = kernel_for(ball, Axisymmetric(options))
    system = _system(kernel)
    arrays = ball_arrays(ball, kernel.geom, options)
    if rate_m_s is None:
        # the impact solver scales its hourglass springs with the instantaneous shear modulus;
        # a relaxed ball gets them from its long-term one (else a g = 0.5 ball's relaxed curve
        # read 2-3% stiff on a 3 mm mesh)
        relaxed = np.array([layer.material.shear_modulus_pa(False)
                            / layer.material.shear_modulus_pa() for layer in ball.layers])
        element_layer = np.concatenate([np.full(b - a, i) for i, (a, b)
                                        in enumerate(kernel.geom.layer_slices)])
        arrays = arrays._replace(hourglass_n_m=arrays.hourglass_n_m * relaxed[element_layer])
    mu = min(layer.material.shear_modulus_pa(False) for layer in ball.layers)
    force_scale = mu * ball.outer_radius_m ** 2
    target = float(deflection_m)
    with jax.enable_x64(True):
        params = jax.tree_util.tree_map(jnp.asarray, cast(arrays, np.float64))
        solver = _Solver(kernel, system, params, np.asarray(arrays.penalty_n_m), force_scale)
        mats = kernel.initial_materials(params)
        compile_start = time.perf_counter()
        with (CompileWait(f"compiling the compression solver for {kernel.geom.n_elements:,} "
                          "elements", f"compression {len(ball.layers)} layers")
              if progress is not None or waits_announced() else contextlib.nullcontext()):
            solver.warm_up(mats)
        compile_time = time.perf_counter() - compile_start
        u = np.zeros((2, system.n_nodes))
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
            forces.append(f_top)
            d_prev = d_new
            if progress is not None:
                progress(len(deflections) - 1, len(deflections) - 1 + len(planned))
    for message in drucker_warnings(ball, lam_min, lam_max):
        warnings.warn(f"{message}: principal stretches in this range occurred in the ball "
                      "(in some layer)", InputWarning, stacklevel=2)
    geom = kernel.geom
    return CompressionResult(
        ball_name=ball.name, deflection_m=np.array(deflections), force_n=np.array(forces),
        rate_m_s=None if rate_m_s is None else float(rate_m_s),
        outer_radius_m=ball.outer_radius_m, stretch_range=(lam_min, lam_max),
        increments=len(deflections) - 1, newton_iterations=iterations,
        max_force_imbalance=imbalance, elements=geom.n_elements, nodes=system.n_nodes,
        jacobian_products=len(system.seeds), integration=options.integration,
        compile_time_s=compile_time, wall_time_s=time.perf_counter() - started,
        moduli=tuple(layer.material.moduli for layer in ball.layers))


def compress_ball(ball: str, deflection_m: float, *, rate_m_s: float | None = None,
                  steps: int = 20, impact_speed_m_s: float | None = None,
                  element_size_m: float = SolverOptions.element_size_m,
                  integration: str = SolverOptions.integration,
                  penalty_scale: float = COMPRESSION_PENALTY_SCALE, moduli: str | None = None,
                  allow=(), csv_path: Path | None = None, plot_path: Path | None = None,
                  progress=None) -> dict[str, Any]:
    """`ballimpact compress`: the ball `ball` (preset or specification file; its constants at
    `impact_speed_m_s` (m/s) where they depend on the speed; `moduli` overriding its convention)
    compressed to `deflection_m` (m) by `compress` on `compression_options`' mesh of
    `element_size_m` (m) with `integration` and `penalty_scale`. Writes the curve to
    `csv_path` (`output.write_curve`: deflection_m,force_n) and its picture to `plot_path` (PNG)
    when given. Returns `CompressionResult.to_dict()` with the ball's `materials` and the paths
    written (`csv`, `plot`). Raises `InputError` (naming --plot, --csv, or the argument) on bad
    input before anything runs, and what `compress` raises."""
    from ..checks import check_allow
    from ..fileio import check_output_file, check_plot_path
    from .output import plot_curve, write_curve
    from .runs import load_model

    check_plot_path(plot_path)
    check_output_file(csv_path, "--csv", ".csv")
    allow = check_allow(allow)
    model = load_model(ball, impact_speed_m_s, moduli=moduli, allow=allow)
    options = dataclasses.replace(compression_options(model, deflection_m, element_size_m),
                                  integration=integration, penalty_scale=penalty_scale)
    result = compress(model, deflection_m, rate_m_s=rate_m_s, steps=steps, options=options,
                      progress=progress)
    out = {**result.to_dict(), "materials": model.to_dict()}
    if csv_path is not None:
        out["csv"] = write_curve(csv_path, result)
    if plot_path is not None:
        out["plot"] = str(plot_curve(result, plot_path))
    return out


# ---- the sparse tangent ----------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class _System:
    """What the Newton solve of one mesh needs (NumPy): the colouring's probe vectors, the
    tangent's sparsity pattern, the free degrees of freedom and the jitted functions."""

    n_nodes: int
    seeds: np.ndarray      # (n_probes, 2, n_nodes): one per colour and component
    rows: np.ndarray       # flat (component * n_nodes + node) indices of the pattern's entries
    cols: np.ndarray
    probe: np.ndarray      # which probe holds each entry
    probe_row: tuple       # (component, node) of each entry in that probe's product
    free: np.ndarray       # flat indices of the free degrees of freedom
    fns: dict


_SYSTEMS: dict[int, tuple[Kernel, _System]] = {}


def node_colouring(elements: np.ndarray, n_nodes: int) -> tuple[np.ndarray, np.ndarray,
                                                                  np.ndarray]:
    """(colour per node, I, J): a distance-2 colouring of the graph of nodes that share an
    element, greedy in node order, and that graph's pairs (self included). Two nodes of one colour
    share no element-neighbour, so their columns of the tangent share no row."""
    import scipy.sparse as sp

    a = np.repeat(elements, 4, axis=1).reshape(-1)
    b = np.tile(elements, (1, 4)).reshape(-1)
    adjacency = sp.csr_matrix((np.ones(len(a), np.int8), (a, b)), shape=(n_nodes, n_nodes))
    adjacency.sum_duplicates()
    adjacency.data[:] = 1
    reach = (adjacency @ adjacency).tocsr()  # nodes within two element hops
    colour = np.full(n_nodes, -1)
    for node in range(n_nodes):
        taken = colour[reach.indices[reach.indptr[node]:reach.indptr[node + 1]]]
        used = np.zeros(len(taken) + 1, bool)
        used[taken[(taken >= 0) & (taken <= len(taken))]] = True
        colour[node] = int(np.argmin(used))
    coo = adjacency.tocoo()
    return colour, coo.row.astype(np.int64), coo.col.astype(np.int64)


def _system(kernel: Kernel) -> _System:
    cached = _SYSTEMS.get(id(kernel))
    if cached is not None and cached[0] is kernel:
        return cached[1]
    g = kernel.geom
    n = len(g.nodes_m)
    colour, I, J = node_colouring(np.asarray(g.elements), n)
    n_colours = int(colour.max()) + 1
    on_axis = np.asarray(g.nodes_m)[:, 0] <= 0.0
    seeds = np.zeros((2 * n_colours, 2, n))
    for c in range(n_colours):
        for d in range(2):
            seeds[2 * c + d, d, colour == c] = 1.0
    seeds[:, 0, on_axis] = 0.0  # no radial motion on the axis
    rows, cols, probe, probe_component, probe_node = [], [], [], [], []
    for ci in range(2):
        for d in range(2):
            rows.append(ci * n + I)
            cols.append(d * n + J)
            probe.append(2 * colour[J] + d)
            probe_component.append(np.full(len(I), ci))
            probe_node.append(I)
    free_mask = np.ones((2, n), bool)
    free_mask[0, on_axis] = False
    system = _System(n_nodes=n, seeds=seeds, rows=np.concatenate(rows),
                     cols=np.concatenate(cols), probe=np.concatenate(probe),
                     probe_row=(np.concatenate(probe_component), np.concatenate(probe_node)),
                     free=np.flatnonzero(free_mask.reshape(-1)), fns=_functions(kernel))
    _SYSTEMS[id(kernel)] = (kernel, system)
    return system


def _functions(kernel: Kernel) -> dict:
    """Jitted internal forces (with diagnostics and new material states) and tangent probes."""
    def ones():
        return jnp.ones(kernel.geom.n_elements, kernel.dtype)

    def forces(params, u, mats, dt):
        f, new_mats, _, _, _, _, J, lam2_min, lam2_max, _ = kernel.internal(
            params, u, mats, ones(), dt)
        return f, new_mats, jnp.min(J), jnp.min(lam2_min), jnp.max(lam2_max)

    def tangent(params, u, mats, dt, seeds):
        f, linear = jax.linearize(lambda x: kernel.internal(params, x, mats, ones(), dt)[0], u)
        return f, jax.vmap(linear)(seeds)

    return {"forces": jax.jit(forces), "tangent": jax.jit(tangent)}


class _Solver:
    """Newton's method on f_int(u) - f_contact(u) = 0 at a platen deflection (host side)."""

    def __init__(self, kernel: Kernel, system: _System, params, penalty: np.ndarray,
                 force_scale: float) -> None:
        g = kernel.geom
        self.kernel, self.system, self.params = kernel, system, params
        self.surface = np.asarray(g.surface_nodes)
        self.height = np.asarray(kernel.surface_height_m, np.float64)  # south pole at 0
        self.top = float(self.height.max())  # the north pole's height: the ball's diameter
        self.penalty = penalty
        self.z = np.asarray(g.nodes_m, np.float64)[:, 1]
        self.radius = 0.5 * self.top
        self.force_scale = force_scale
        self.seeds = jnp.asarray(system.seeds)

    def warm_up(self, mats) -> None:
        """Compile both functions (timed apart from the solve)."""
        u = jnp.zeros((2, self.system.n_nodes))
        jax.block_until_ready(self.system.fns["tangent"](self.params, u, mats, 1.0, self.seeds))
        jax.block_until_ready(self.system.fns["forces"](self.params, u, mats, 1.0))

    def contact(self, u: np.ndarray, deflection: float):
        """(platen forces on the nodes (2, n), contact stiffness diagonal (2, n), F_top,
        F_bottom): node-to-plane penalty springs of both platens (frictionless)."""
        s, k = self.surface, self.penalty
        z = self.height + u[1, s]
        pen_bottom = -z
        pen_top = z - (self.top - deflection)
        tol = 1e-12 * self.radius
        f_bottom = k * np.maximum(pen_bottom, 0.0)
        f_top = k * np.maximum(pen_top, 0.0)
        force = np.zeros_like(u)
        force[1, s] = f_bottom - f_top
        stiffness = np.zeros_like(u)
        stiffness[1, s] = k * ((pen_bottom > -tol) + (pen_top > -tol))
        return force, stiffness, float(np.sum(f_top)), float(np.sum(f_bottom))

    def predict(self, history_u: list, deflections: list, d_new: float) -> np.ndarray:
        """Start of an increment: linear extrapolation of the last two solutions; at the first,
        a uniform axial strain that just touches both platens."""
        if len(history_u) < 2:
            u = np.zeros_like(history_u[-1])
            u[1] = -0.5 * d_new * (1.0 + self.z / self.radius)
            return u
        d1, d0 = deflections[-1], deflections[-2]
        return history_u[-1] + (d_new - d1) / (d1 - d0) * (history_u[-1] - history_u[-2])

    def _residual(self, u, mats, dt, deflection):
        f, _, min_j, _, _ = self.system.fns["forces"](self.params, jnp.asarray(u), mats, dt)
        contact, _, f_top, _ = self.contact(u, deflection)
        r = (np.asarray(f) - contact).reshape(-1)[self.system.free]
        return r, float(min_j), f_top

    def solve(self, u: np.ndarray, mats, dt: float, deflection: float):
        """(u, iterations, F_top, F_bottom) at equilibrium, or None if Newton fails."""
        import scipy.sparse as sp
        from scipy.sparse.linalg import spsolve

        sysm = self.system
        n2 = 2 * sysm.n_nodes
        free = sysm.free
        for iteration in range(1, MAX_NEWTON_ITERATIONS + 1):
            f, probes = sysm.fns["tangent"](self.params, jnp.asarray(u), mats, dt, self.seeds)
            contact, stiffness, f_top, f_bottom = self.contact(u, deflection)
            r = (np.asarray(f) - contact).reshape(-1)[free]
            if not np.all(np.isfinite(r)):
                return None
            norm = float(np.max(np.abs(r)))
            if norm <= max(RESIDUAL_RELATIVE * f_top, RESIDUAL_ABSOLUTE * self.force_scale):
                return u, iterations_done(iteration), f_top, f_bottom
            probes = np.asarray(probes)
            values = probes[sysm.probe, sysm.probe_row[0], sysm.probe_row[1]]
            K = sp.csr_matrix((values, (sysm.rows, sysm.cols)), shape=(n2, n2))
            K = (K + sp.diags(stiffness.reshape(-1))).tocsr()[free][:, free].tocsc()
            step = spsolve(K, -r)
            if not np.all(np.isfinite(step)):
                return None
            merit = float(np.dot(r, r))
            alpha = 1.0
            for _ in range(MAX_LINE_SEARCH_HALVINGS):
                trial = u.copy().reshape(-1)
                trial[free] += alpha * step
                trial = trial.reshape(u.shape)
                r_new, min_j, _ = self._residual(trial, mats, dt, deflection)
                if (min_j > 0 and np.all(np.isfinite(r_new))
                        and float(np.dot(r_new, r_new)) < (1.0 - 1e-4 * alpha) * merit):
                    break
                alpha *= 0.5
            else:
                return None
            u = trial
        return None

    def commit(self, u: np.ndarray, mats, dt: float):
        """The Prony states at the converged u, and the principal stretches' range there."""
        _, new_mats, _, lam2_min, lam2_max = self.system.fns["forces"](
            self.params, jnp.asarray(u), mats, dt)
        return new_mats, (math.sqrt(max(float(lam2_min), 0.0)), math.sqrt(float(lam2_max)))


def iterations_done(iteration: int) -> int:
    """Newton iterations taken when the residual check passes at the start of `iteration`."""
    return iteration - 1
