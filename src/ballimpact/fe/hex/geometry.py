"""The hexahedral (3D) geometry of the engine (`fe.engine`): a layered ball meshed as an O-grid
(a half model on the plane of incidence unless told otherwise), oblique impacts with Coulomb
friction and spin on a rigid plane or a deformable slab (`target.Target`; its base fixed, or
carried by a free rigid backing, `target.Backing`, whose histories the result gains:
`kernel.BACKING_HISTORY`). On a slab the result also gains each layer's internal work and
compression at the slab's centre (`kernel.target_layer_history`, `target_energies`: the
axisymmetric geometry's columns and figures).

`Hexahedral(options)` gives the engine what it needs of this geometry: the structure a compiled
program depends on, the mesh's size before it is built, the kernel and mesh, the per-run
parameters and initial values, the cost constants, snapshots for output and the result.
Extensive results (forces, energies, mass) are for the whole ball: a half model's are doubled.

Results: normal COR e_n = v_z' / (-v_z), tangential COR e_t = v_x' / v_x (the centre of mass, as
ball-sports studies quote it), the contact point's tangential COR -(v_x' - w' R) / (v_x - w R),
rebound angle from the normal atan(v_x' / v_z') and rebound spin (`ImpactCondition` sign).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import jax
import numpy as np

from ...errors import InputError
from ..estimates import hertz_series_impact
from ..options import COMPRESSION_PENALTY_SCALE, ImpactCondition, Options3D
from ..platens import PlatenModel, relaxed_hourglass
from ..steps import cast
from ..result import ImpactResult, contact_end_time, energy_histories, target_energies
from ..stable_increment import increment_factor
from . import kernel as kernel_module
from .contact_grading import contact_settings, grading_for_spacing, without_contact
from .element import geometry as element_geometry
from .kernel import HISTORY, HexParams, Kernel
from .mesh import (
    GRADING_RANGE,
    HexMesh,
    ball_mesh,
    combine,
    estimate_ball_mesh,
    graded_depths_m,
    graded_line,
    pole_cell_growth,
    pole_spacing_m,
    slab_mesh,
    uniform_depths_m,
)
from .target import check_target_width


def structure(ball, target) -> tuple:
    """What a compiled run depends on: the ball's and the slab's layers (radii, thicknesses,
    material models, bulk relaxation, Prony terms), the slab's half width and whether its base is
    backed (`target.Backing`; its constants are parameters)."""
    layers = tuple((layer.outer_radius_m, type(layer.material), layer.material.sum_k > 0,
                    len(layer.material.prony)) for layer in ball.layers)
    slab = None if target is None else (
        target.half_width_m, tuple((layer.thickness_m, type(layer.material),
                                    layer.material.sum_k > 0, len(layer.material.prony))
                                   for layer in target.layers),
        target.backing is not None)
    return layers, slab


#: a target slab's in-plane cells grow by this a cell outward from the centre
SLAB_GROWTH = 1.15


def slab_cell_m(ball, options: Options3D) -> float:
    """The target slab's cell size near the contact (m): about the ball mesh's arc spacing at
    the pole (the exact spacing is `mesh.pole_spacing_m`; this estimate is kept because the
    slab's documented figures rest on it)."""
    return (ball.outer_radius_m * math.radians(90.0 / options.divisions)
            / options.pole_grading ** 0.5)


def slab_layout(ball, target, options: Options3D) -> tuple[int, float, np.ndarray]:
    """(cells across half the slab, their grading, depths of the cell boundaries m).

    Default: in plane about `slab_cell_m` near the centre (the count is the one the slab's
    documented figures rest on; with its grading capped at 20 the centre cells come out finer
    than the ball's pole spacing), through the depth uniform cells of about 4 pole spacings or
    `slab_depth_cell_m` (at least 2 a layer). With `slab_depth_growth` the slab is matched to the ball's contact: in
    plane cells of the pole spacing (`mesh.pole_spacing_m`) at the centre growing outward as
    the ball's cells do from its pole (at least by 1.15 a cell: the ball's nodes then press on
    target nodes of about their own mass, see `_contact_spring_factors`), through the depth
    the pole spacing at the surface growing by that factor to 4 pole spacings."""
    options = without_contact(options)
    thicknesses = [layer.thickness_m for layer in target.layers]
    if options.slab_depth_growth is None:
        pole = slab_cell_m(ball, options)
        cells = max(4, int(math.ceil(math.log(1 + target.half_width_m / pole)
                                     / math.log(SLAB_GROWTH))))
        if options.slab_depth_cell_m is None:
            through = [max(2, int(math.ceil(t / (4 * pole)))) for t in thicknesses]
        else:  # a layer of a whole number of the cells given gets that number
            through = [max(2, int(math.ceil(t / options.slab_depth_cell_m - 1e-9)))
                       for t in thicknesses]
        return cells, min(20.0, SLAB_GROWTH ** (cells - 1)), uniform_depths_m(thicknesses,
                                                                              through)
    pole = pole_spacing_m(ball.outer_radius_m, options.divisions, options.pole_grading)
    growth = max(SLAB_GROWTH, pole_cell_growth(options.divisions, options.pole_grading))
    # rounded down: the centre cells at least the pole spacing, so never lighter than the ball's
    cells = max(4, int(math.log(1 + (growth - 1) * target.half_width_m / pole)
                       / math.log(growth)))
    return cells, growth ** (cells - 1), graded_depths_m(thicknesses, pole, 4 * pole,
                                                          options.slab_depth_growth)


def mesh_for(ball, target, options: Options3D, half: bool) -> HexMesh:
    """The mesh of a ball (and target), ball layers then target layers as groups."""
    options = without_contact(options)
    mesh = ball_mesh(ball.layer_radii_m, options.divisions, options.pole_grading, half=half)
    if target is None:
        return mesh
    cells, grading, depths = slab_layout(ball, target, options)
    slab = slab_mesh([layer.thickness_m for layer in target.layers], target.half_width_m,
                     cells, grading=grading, half=half, depths_m=depths)
    return combine(mesh, slab, len(ball.layers))


def mesh_size(ball, target, options: Options3D, half: bool) -> tuple[int, float]:
    """(elements, about the smallest element's length m) of `mesh_for`, without building it."""
    options = without_contact(options)
    elements, smallest = estimate_ball_mesh(ball.layer_radii_m, options.divisions,
                                            options.pole_grading, half)
    if target is not None:
        cells, grading, depths = slab_layout(ball, target, options)
        centre = float(graded_line(target.half_width_m, cells, grading)[1])
        elements += (2 * cells) * (cells if half else 2 * cells) * (len(depths) - 1)
        smallest = min(smallest, centre, float(np.min(np.diff(depths))))
    return elements, smallest


def build_kernel(ball, target, options: Options3D, half: bool) -> tuple[Kernel, HexMesh]:
    """The kernel and mesh of a ball (and target) structure."""
    mesh = mesh_for(ball, target, options, half)
    materials = [layer.material for layer in ball.layers]
    if target is not None:
        materials += [layer.material for layer in target.layers]
    geom, _ = element_geometry(mesh, len(materials))
    free = np.ones((3, len(mesh.nodes_m)))
    free[1, mesh.symmetry_nodes] = 0.0
    free[:, mesh.fixed_nodes] = 0.0
    layers = {}
    if target is not None:
        layers = {"centre_column": centre_column(mesh, target), "ball_groups": len(ball.layers),
                  "thicknesses_m": [layer.thickness_m for layer in target.layers]}
    kernel = kernel_module.build(
        geom, [type(m).energy for m in materials], [m.sum_k > 0 for m in materials],
        mesh.contact_nodes, mesh.ball_nodes, free, half, options.integration == "reduced",
        mesh.target, np.dtype(options.precision),
        backing=(mesh.fixed_nodes if target is not None and target.backing is not None
                 else None), **layers)
    return kernel, mesh


def centre_column(mesh: HexMesh, target) -> np.ndarray:
    """The slab's node ids at x = y = 0 (the first touch point) at the top of each of its layers
    and at its base (top down; the slab's node lines hold 0 and every layer's bottom)."""
    slab = np.flatnonzero(~np.asarray(mesh.ball_nodes))
    x = np.asarray(mesh.nodes_m)[slab]
    depths = np.concatenate([[0.0], np.cumsum([layer.thickness_m for layer in target.layers])])
    ids = []
    for depth in depths:
        distance = np.linalg.norm(x - [0.0, 0.0, -depth], axis=1)
        i = int(np.argmin(distance))
        if distance[i] > 1e-9 * target.thickness_m:
            raise ValueError(f"slab mesh: no node at x = y = 0, depth {depth:g} m")
        ids.append(slab[i])
    return np.array(ids)


def model_arrays(ball, target, kernel: Kernel, options: Options3D,
                 condition: ImpactCondition) -> HexParams:
    """Per-run parameters (NumPy float64)."""
    options = without_contact(options)
    geom = kernel.geom
    layers = list(ball.layers) + (list(target.layers) if target is not None else [])
    rho = np.array([layer.density_kg_m3 for layer in layers])
    wave = np.array([layer.material.wave_modulus_pa() for layer in layers])
    shear = np.array([layer.material.shear_modulus_pa() for layer in layers])
    c_d = np.sqrt(wave / rho)
    group = np.concatenate([np.full(b - a, i) for i, (a, b) in enumerate(geom.group_slices)])
    mass = rho @ np.asarray(geom.nodal_volume_m3, np.float64)
    s = kernel.contact_nodes
    m_s = mass[s]
    length = np.asarray(geom.characteristic_length_m, np.float64)
    penalty = options.penalty_scale * m_s * (c_d[len(ball.layers) - 1]
                                             / np.asarray(geom.node_length_m, np.float64)[s]) ** 2
    return HexParams(
        mass_kg=mass, ball_mass_kg=float(np.sum(mass[kernel.ball_nodes])),
        backing=_backing_constants(target, kernel, mass),
        outer_radius_m=float(ball.outer_radius_m),
        penalty_n_m=penalty, stick_n_m=options.stick_scale * penalty,
        contact_damping_n_s_m=options.contact_damping * 2.0 * np.sqrt(penalty * m_s),
        contact_spring_factor=_contact_spring_factors(ball, target, kernel, mass, condition,
                                                      options),
        friction=float(condition.friction),
        hourglass_n_m=(options.hourglass_scale * shear[group]
                       * np.asarray(geom.hourglass_length_m, np.float64)),
        bv_linear_pa_s=options.bulk_viscosity_linear * rho[group] * c_d[group] * length,
        bv_quadratic_pa_s2=rho[group] * (options.bulk_viscosity_quadratic * length) ** 2,
        energy_error_limit=float(options.energy_error_limit),
        increment_factor=increment_factor(options.time_step_scale,
                                          options.bulk_viscosity_linear),
        groups=[layer.material.constants() for layer in layers],
        # arange(n_el) as data: `element.materialized`'s fusion boundary
        element_index=np.arange(geom.n_elements, dtype=np.int32))


def _backing_constants(target, kernel: Kernel, mass: np.ndarray) -> np.ndarray:
    """A backed slab's (M kg, k N/m, c N s/m, the base nodes' lumped mass kg) of the model (a
    half model carries half of each), or an empty array for a fixed base."""
    if kernel.backing is None:
        return np.zeros(0)
    b = target.backing
    share = 0.5 if kernel.half else 1.0
    return np.array([share * b.mass_kg, share * b.spring_n_m, share * b.damper_n_s_m,
                     float(np.sum(mass[kernel.backing]))])


def _contact_spring_factors(ball, target, kernel: Kernel, mass: np.ndarray,
                            condition: ImpactCondition, options: Options3D) -> np.ndarray:
    """Per contact node, the factor on its contact springs in the stable increment's estimate
    (n_contact,): a ball node of mass m pressed on target nodes of mass m_t makes a two-mass
    spring, 1 + m / m_t times stiffer than one tied to the ground (1 on the rigid plane).

    Only the ball nodes that can meet the target get it, with m_t the lightest target surface
    node they can meet (`_contact_reach`: within the reach angle of the first touch, and on
    the slab's cells under them give or take the travel). The bound over every pair (the
    heaviest ball node on the lightest target node) made a run on a slab matched to the contact
    take ten times the steps it needs."""
    s = np.asarray(kernel.contact_nodes)
    factors = np.ones(len(s))
    if target is None:
        return factors
    reach_rad, travel_m = _contact_reach(ball, target, kernel, mass, condition, options)
    top_mass = mass[np.asarray(kernel.target["top"])]
    xs, ys = (np.asarray(kernel.target[k], np.float64) for k in ("x_m", "y_m"))
    x = np.asarray(kernel.geom.nodes_m, np.float64)[s]
    radius = ball.outer_radius_m
    from_pole = np.arccos(np.clip((radius - x[:, 2]) / np.linalg.norm(
        x - np.array([0.0, 0.0, radius]), axis=1), -1.0, 1.0))
    for i in np.flatnonzero(from_pole <= reach_rad):
        box = [(x[i, k] - travel_m, x[i, k] + travel_m) for k in (0, 1)]
        factors[i] += mass[s[i]] / _lightest_partner_kg(xs, ys, top_mass, *box)
    return factors


def _lightest_partner_kg(xs, ys, top_mass, x_range, y_range) -> float:
    """The smallest effective mass (kg) a point pressed anywhere in the box x_range x y_range
    meets on a target surface of node lines `xs`, `ys` and node masses `top_mass`: with the
    bilinear weights w_j of the four corners, 1 / m = sum w_j^2 / m_j. That sum is convex along
    each axis within a cell, so its largest value is at a corner of the box cut by the cells:
    the box's corners and edges on the lines and the nodes inside."""
    def points(line, low, high):
        low, high = max(low, line[0]), min(high, line[-1])
        return np.unique(np.concatenate([[low, high], line[(line > low) & (line < high)]]))

    def cell_weights(line, p):
        i = np.clip(np.searchsorted(line, p, "right") - 1, 0, len(line) - 2)
        f = (p - line[i]) / (line[i + 1] - line[i])
        return i, f

    (ix, fx), (iy, fy) = (cell_weights(line, points(line, *span))
                          for line, span in ((xs, x_range), (ys, y_range)))
    ix, iy, fx, fy = ix[:, None], iy[None, :], fx[:, None], fy[None, :]
    inverse = sum((wx * wy) ** 2 / top_mass[ix + dx, iy + dy]
                  for dx, wx in ((0, 1 - fx), (1, fx)) for dy, wy in ((0, 1 - fy), (1, fy)))
    return float(1.0 / np.max(inverse))


#: the reach's margin on the Hertz contact radius and on the contact time
REACH_MARGIN = 1.5


def _contact_reach(ball, target, kernel: Kernel, mass: np.ndarray, condition: ImpactCondition,
                   options: Options3D) -> tuple[float, float]:
    """(angle rad, travel m): the angle from the first touch within which the ball's surface
    can meet a target, and how far a point of it can move along the target while in contact.

    From the Hertz contact (the ball's and the target's softest moduli in series) with
    `REACH_MARGIN` on its radius and time: the contact's half angle plus the rotation over the
    contact at the initial spin plus the most friction can add, plus two pole spacings; the
    travel is the tangential speed and that rotation over the contact, plus a pole spacing."""
    theta = math.radians(condition.angle_deg)
    v_n, v_t = condition.speed_m_s * math.cos(theta), abs(condition.speed_m_s * math.sin(theta))
    materials = [layer.material for layer in target.layers]
    radius = ball.outer_radius_m
    y_max, _, contact_time = hertz_series_impact(ball, v_n, materials)
    a, contact_time = REACH_MARGIN * math.sqrt(radius * y_max), REACH_MARGIN * contact_time
    ball_nodes = np.asarray(kernel.ball_nodes)
    x = np.asarray(kernel.geom.nodes_m, np.float64)[ball_nodes]
    inertia = float(np.sum(mass[ball_nodes] * (x[:, 0] ** 2 + (x[:, 2] - radius) ** 2)))
    spin = float(np.linalg.norm(condition.spin_vector_rad_s))
    k = inertia / (float(np.sum(mass[ball_nodes])) * radius ** 2)
    # friction's impulse over m: at most mu (1 + 1) v_n, and at most what reverses the contact
    # point's initial speed fully (a tangential COR of 1)
    impulse = min(2.0 * condition.friction * v_n, 2.0 * (v_t + spin * radius) / (1.0 + 1.0 / k))
    spin += impulse / (k * radius)
    pole = pole_spacing_m(radius, options.divisions, options.pole_grading)
    rotation = spin * contact_time
    return (math.asin(min(1.0, a / radius)) + rotation + 2.0 * pole / radius,
            (v_t + spin * radius) * contact_time + pole)

_STRESS: dict[Any, Any] = {}  # jitted stress recovery per kernel


def _frame(kernel: Kernel, params, state) -> dict[str, np.ndarray]:
    """A snapshot for output (one run): time (s), displacement and velocity (3, n_nodes), Cauchy
    stress (6, n_el; xx, yy, zz, xy, yz, zx, elements sorted by group) and contact forces
    (3, n_nodes)."""
    if id(kernel) not in _STRESS:
        _STRESS[id(kernel)] = jax.jit(kernel.cauchy_stress)
    stress = _STRESS[id(kernel)]
    return {"time_s": float(state.t),
            "displacement_m": np.asarray(state.u, np.float64),
            "velocity_m_s": np.asarray(state.v, np.float64),
            "stress_pa": np.asarray(stress(params, state.u, state.mat), np.float64),
            "contact_force_n": np.asarray(state.f_contact, np.float64)}


#: elements across the platens' Hertz contact radius that `Hexahedral.for_compression` grades the
#: poles to (the 3D impacts' `contact_grading.DEFAULT_CONTACT_ELEMENTS`): on an elastic sphere
#: (nu 0.3, D / 2R = 2%) 12 divisions read 1.9% over the axisymmetric reference and 16 divisions
#: 1.2% under it; 5 elements read further off at 12 divisions (+3.3%: the steeper grading's
#: cells grow by 1.62 a cell against 1.41) and cost more (docs/materials.md)
COMPRESSION_CONTACT_ELEMENTS = 3.0


@dataclass(frozen=True)
class Hexahedral:
    """The hexahedral geometry with its settings (`options`: mesh, friction's stick springs,
    target slab cells, output frames and the settings both geometries share). `half` is the
    resolved half-model choice (None: chosen from the conditions by `checked`)."""

    options: Options3D = Options3D()
    half: bool | None = None

    #: the speed range's key (`fe.speed_range.check_fe_speed`)
    solver = "3d"
    #: element updates above which a run is flagged as very long: about 1.5 min at
    #: `SECONDS_PER_ELEMENT_STEP` (about 36 divisions, half model; the default 16 is 1.5e7 by
    #: the estimate, 1.1e7 run)
    ELEMENT_STEPS_WARNING = 3e8
    #: wall time of one hexahedron update on a 2-core CPU (s; float64, reduced integration, after
    #: issue 28: 3.1e-7 at 1408, 2.5e-7 at 7424 and 2.4e-7 at 22,464 hexahedra, the last 3.0e-7
    #: on a slow minute of the machine; benchmarks/bench_oblique.py, docs/oblique.md "Cost")
    SECONDS_PER_ELEMENT_STEP = 3e-7
    #: the stable increment over the smallest element's L / c_d at time_step_scale 0.8 (0.84 at
    #: 8 and 0.66 at 16 divisions on the universal ball; lower is safer)
    INCREMENT_OVER_SMALLEST_ELEMENT = 0.66
    #: memory of a run (bytes): the process with JAX and the compiled program, and per
    #: hexahedron and run held at once (measured on the universal ball, reduced integration,
    #: half models of 8 to 32 divisions: docs/oblique.md; full integration's eight points
    #: assumed to double it)
    BASE_MEMORY_BYTES = 0.8 * 2 ** 30
    MEMORY_PER_ELEMENT_BYTES = 16e3
    HINT = ("a coarser mesh: fewer divisions, --divisions (a slab: a thinner or narrower "
            "--target, whose cells follow the ball's pole spacing)")
    REFINE = "more divisions"
    REFINE_POLE = ("more divisions, pole_grading or contact_elements: --divisions, "
                   "--pole-grading, --contact-elements")
    HISTORY = HISTORY
    FINAL = ("peak_force", "t_peak", "dt0", "dt", "stretch_min", "stretch_max", "ke0")

    def __post_init__(self) -> None:
        if not isinstance(self.options, Options3D):
            raise InputError(f"Hexahedral(options): expected Options3D, got "
                             f"{type(self.options).__name__}")

    def checked(self, ball, conditions: list, target) -> "Hexahedral":
        """The geometry for these runs of `ball`: the half model when every condition is
        symmetric (or as `options.half` says), the pole grading and penalty the options leave
        to the contact chosen for it (`contact_grading.contact_settings`); a target narrower
        than the ball refused (`target.check_target_width`)."""
        symmetric = all(c.symmetric for c in conditions)
        half = symmetric if self.options.half is None else bool(self.options.half)
        if half and not symmetric:
            raise InputError("half = True: out-of-plane spin (spin_x_rad_s, spin_z_rad_s) needs "
                             "the full model (half = False or None)")
        if target is not None:
            if not hasattr(target, "layers"):
                raise InputError(f"target = {type(target).__name__}: the 3D geometry takes a "
                                 "layered Target; a rigid plane on a PlaneBacking runs on the "
                                 "axisymmetric geometry")
            if target.sphere_radius_m is not None:
                raise InputError(f"target {target.name!r}: sphere_radius_m (a spherical cap) "
                                 "runs on the axisymmetric geometry (normal impacts); the 3D "
                                 "geometry meshes flat slabs")
            check_target_width(target, ball)
        slowest = min(c.speed_m_s * math.cos(math.radians(c.angle_deg)) for c in conditions)
        return replace(self, options=contact_settings(ball, slowest, self.options), half=half)

    def structure(self, ball, target=None) -> tuple:
        return structure(ball, target)

    @property
    def settings(self) -> Options3D:
        """The options, with what `checked` chooses from the contact set as without one
        (`contact_grading.without_contact`) where it has not run."""
        return without_contact(self.options)

    def kernel_key(self, ball, target=None) -> tuple:
        o = self.settings
        return ("3d", structure(ball, target), o.divisions, o.pole_grading, self.half,
                o.integration, o.precision,
                None if target is None else (o.slab_depth_growth, o.slab_depth_cell_m))

    def build(self, ball, target=None) -> tuple[Kernel, HexMesh]:
        return build_kernel(ball, target, self.settings, self.half)

    def mesh_size(self, ball, target=None) -> tuple[int, float]:
        return mesh_size(ball, target, self.settings, self.half)

    def pole_element_m(self, ball) -> float:
        return pole_spacing_m(ball.outer_radius_m, self.settings.divisions,
                              self.settings.pole_grading)

    def for_compression(self, ball, contact_radius_m: float) -> "Hexahedral":
        """The geometry of a platen compression (`fe.compress`), the ball's poles at both
        platens (the O-grid is graded toward every face centre alike): a pole grading left None
        puts `COMPRESSION_CONTACT_ELEMENTS` (or the options' `contact_elements`) elements across
        the platens' contact radius `contact_radius_m` (m; the largest grading where the
        divisions cannot), a penalty left None is `options.COMPRESSION_PENALTY_SCALE`, the half
        model unless `half` is False; float64, no bulk viscosity."""
        o = self.options
        grading = o.pole_grading
        if grading is None or o.contact_elements is not None:
            elements = o.contact_elements or COMPRESSION_CONTACT_ELEMENTS
            grading = grading_for_spacing(ball.outer_radius_m, o.divisions,
                                          contact_radius_m / elements) or GRADING_RANGE[1]
        options = replace(o, pole_grading=grading, contact_elements=None,
                          penalty_scale=(COMPRESSION_PENALTY_SCALE if o.penalty_scale is None
                                         else o.penalty_scale),
                          precision="float64", bulk_viscosity_linear=0.0,
                          bulk_viscosity_quadratic=0.0)
        return Hexahedral(options, half=o.half is not False)

    def platen_element_m(self, ball) -> float:
        return self.pole_element_m(ball)

    def compression_model(self, ball, kernel: Kernel, relaxed: bool) -> PlatenModel:
        """The ball between two platens (`fe.platens.PlatenModel`): the mirror planes x = 0 and
        y = 0 of the problem hold u_x and u_y (a half model's y = 0 already does), which also
        removes the rigid motions the frictionless platens leave free; `relaxed`: hourglass
        springs from the long-term shear moduli. Forces of a half model are doubled."""
        g = kernel.geom
        params = cast(model_arrays(ball, None, kernel, self.settings, ImpactCondition(1.0)),
                      np.float64)
        if relaxed:
            params = params._replace(hourglass_n_m=relaxed_hourglass(
                params.hourglass_n_m, ball.layers, g.group_slices))
        nodes = np.asarray(g.nodes_m, np.float64)
        free = np.asarray(kernel.free_dof) > 0
        for axis in (0, 1):
            free[axis, np.abs(nodes[:, axis]) <= 1e-9 * ball.outer_radius_m] = False
        ones = np.ones(g.n_elements)

        def internal(params, u, mats, dt):
            f, new_mats, J, _, _, _, lam_lo, lam_hi, _ = kernel.internal(params, u, mats,
                                                                          ones, dt)
            return f, new_mats, J.min(), lam_lo.min(), lam_hi.max()

        surface = np.asarray(kernel.contact_nodes)
        return PlatenModel(internal=internal, initial_materials=kernel.initial_materials,
                           params=params, elements=np.asarray(g.elements), free=free, axis=2,
                           surface=surface,
                           penalty_n_m=np.asarray(params.penalty_n_m), height_m=nodes[:, 2],
                           force_factor=2.0 if kernel.half else 1.0)

    def slack(self, target) -> float:
        return 1.0 if target is None else 4.0  # a slab lengthens the contact

    def default_group_size(self, runs: int, cpu: bool) -> int:
        return max(1, runs)  # the conditions of a ball run as one vmapped group

    def frames_bytes(self, steps: int, elements: int, nodes: int, runs: int) -> float:
        """Memory of the frames kept for output (displacement, velocity, contact force,
        stress), single runs only."""
        if not (self.options.frames and runs == 1):
            return 0.0
        return 8.0 * steps / (self.options.chunk_steps * self.options.frames) * (
            9 * nodes + 6 * elements)

    def params(self, ball, target, kernel: Kernel, condition: ImpactCondition) -> HexParams:
        return model_arrays(ball, target, kernel, self.settings, condition)

    def initial(self, conditions: list) -> list[np.ndarray]:
        return [np.array([c.speed_m_s for c in conditions]),
                np.radians([c.angle_deg for c in conditions]),
                np.array([c.spin_vector_rad_s for c in conditions])]

    def label(self, ball, condition: ImpactCondition) -> str:
        return f"ball {ball.name}, {condition}"

    def frame(self, kernel, params, state):
        return _frame(kernel, params, state)

    def result(self, ball, target, condition: ImpactCondition, history: np.ndarray,
               final: dict, params, t_end: float, kernel: Kernel, mesh, wall: float,
               frames: list) -> ImpactResult:
        n = int(np.searchsorted(history[:, 0], t_end * (1 + 1e-6))) + 1
        factor = 2.0 if self.half else 1.0
        names = kernel.history_names
        h = {name: history[:n, j] for j, name in enumerate(names)}
        for name in names:
            if name.endswith("_n") or name.endswith("_j") or name.endswith("_kg_m_s"):
                h[name] = factor * h[name]
        mass = factor * float(params.ball_mass_kg)
        v, theta = condition.speed_m_s, math.radians(condition.angle_deg)
        w = condition.spin_rad_s
        vx, vz = v * math.sin(theta), -v * math.cos(theta)
        ke0 = factor * float(final["ke0"])
        largest = energy_histories(h, ke0)
        if kernel.backing is not None:  # the backing's spring and damper in the balance
            balance = (h["kinetic_energy_j"] + h["backing_spring_energy_j"]
                       + h["backing_damper_dissipation_j"] + h["internal_work_j"]
                       - h["contact_work_j"] - ke0)
            h["energy_balance_error"] = balance / ke0
            largest = float(np.max(np.abs(balance)))
        h["frictional_dissipation_j"] = -h["tangential_work_j"] - h["stick_energy_j"]
        energies = {name: float(values[-1]) for name, values in h.items()
                    if name.endswith("_j") and not name.startswith("target_layer_")}
        energies["initial_kinetic_energy_j"] = float(ke0)
        energies["peak_hourglass_energy_j"] = float(np.max(h["hourglass_energy_j"]))
        if kernel.centre_column is not None:
            energies.update(target_energies(h, target))
        vx_out, vz_out = h["centre_velocity_x_m_s"][-1], h["centre_velocity_z_m_s"][-1]
        vy_out = h["centre_velocity_y_m_s"][-1]
        w_out = h["spin_y_rad_s"][-1]
        radius = ball.outer_radius_m
        contact_in = vx - w * radius
        return ImpactResult(
            ball_name=ball.name, condition=condition, history=h, geometry="3d",
            cor=float(vz_out / -vz),
            tangential_cor=float(vx_out / vx) if vx != 0 else float("nan"),
            contact_point_tangential_cor=(float(-(vx_out - w_out * radius) / contact_in)
                                          if abs(contact_in) > 1e-9 * v else float("nan")),
            rebound_angle_deg=float(math.degrees(math.atan2(math.hypot(vx_out, vy_out),
                                                            vz_out))),
            rebound_spin_rad_s=float(w_out),
            rebound_speed_m_s=float(math.sqrt(vx_out ** 2 + vy_out ** 2 + vz_out ** 2)),
            peak_force_n=factor * float(final["peak_force"]),
            time_of_peak_s=float(final["t_peak"]),
            contact_time_s=contact_end_time(h["time_s"], h["contact_force_n"]),
            energy_balance_error=largest / ke0, energies_j=energies,
            stable_time_increment_s=float(final["dt0"]),
            final_time_increment_s=float(final["dt"]), steps=n,
            elements=int(kernel.geom.n_elements), nodes=int(kernel.n_nodes), mass_kg=mass,
            outer_radius_m=radius, half_model=bool(self.half),
            target="rigid plane" if target is None else target.name, wall_time_s=wall,
            stretch_range=(float(final["stretch_min"]), float(final["stretch_max"])),
            pole_grading=float(self.settings.pole_grading),
            penalty_scale=float(self.settings.penalty_scale),
            pole_spacing_m=self.pole_element_m(ball), integration=self.options.integration,
            precision=self.options.precision, frames=frames, mesh=mesh,
            kernel_geometry=kernel.geom)
