"""The axisymmetric geometry of the engine (`fe.engine`): a layered ball meshed in its meridian
plane (quadrilateral rings), normal impacts on a rigid plane.

`Axisymmetric(options)` gives the engine what it needs of this geometry and nothing else: the
structure a compiled program depends on, the mesh's size before it is built, the kernel, the
per-ball parameters and initial values, the cost constants and the result."""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass

import jax
import numpy as np

from ...errors import InputError, InputWarning
from ...constitutive.stability import drucker_warnings
from ..backing import PlaneBacking, backing_energies
from ..platens import PlatenModel, relaxed_hourglass
from ..steps import cast
from ..hex.target import Target, check_target_width
from ..options import ImpactCondition, SolverOptions
from ..result import ImpactResult, contact_end_time, energy_histories, target_energies
from .element import geometry as element_geometry
from .kernel import HISTORY, Kernel, ball_arrays
from .target_kernel import TargetKernel, target_params
from .target_mesh import target_mesh
from .mesh import estimate_mesh, layered_sphere_mesh


def constant_shapes(material) -> tuple:
    """The shapes of a material's constants (its Prony and Ogden terms' counts), as a tuple."""
    return tuple(np.shape(v) for v in jax.tree_util.tree_leaves(material.constants()))


def structure(ball) -> tuple:
    """What a compiled run depends on: radii, material models, Prony terms, bulk relaxation."""
    return tuple((layer.outer_radius_m, type(layer.material), layer.material.sum_k > 0,
                  constant_shapes(layer.material)) for layer in ball.layers)


def mesh_radii(ball, options: SolverOptions) -> np.ndarray:
    """The node circles of a ball's mesh: its layer radii and `options.mesh_radii_m` inside."""
    radii = np.asarray(ball.layer_radii_m)
    extra = [r for r in options.mesh_radii_m if 0 < r < radii[-1]]
    return np.unique(np.concatenate([radii, extra]))


def build_kernel(ball, options: SolverOptions, backing_modes: int = 0) -> Kernel:
    """The compiled-program data (mesh, material models, precision) of a ball's structure, on
    a fixed plane or a plane on a backing of `backing_modes` modes."""
    mesh = _ball_mesh(ball, options)
    return Kernel.build(
        element_geometry(mesh), [type(layer.material).energy for layer in ball.layers],
        [layer.material.sum_k > 0 for layer in ball.layers],
        reduced=options.integration == "reduced", dtype=np.dtype(options.precision),
        backing_modes=backing_modes)


def _ball_mesh(ball, options: SolverOptions):
    """The ball's mesh, its rings assigned to the ball's layers."""
    radii = np.asarray(ball.layer_radii_m)
    circles = mesh_radii(ball, options)
    mesh = layered_sphere_mesh(tuple(circles), options.element_size_m,
                               options.pole_element_size_m, options.pole_zone_deg,
                               options.both_poles)
    # mesh rings -> ball layers: a ring belongs to the first layer that reaches its radius
    ring_layer = np.searchsorted(radii, circles - 1e-12 * radii[-1])
    return dataclasses.replace(mesh, element_layer=ring_layer[mesh.element_layer],
                               layer_radii_m=tuple(radii))


def build_target_kernel(ball, target, options: SolverOptions) -> TargetKernel:
    """The kernel of a ball on a layered target (`fe.hex.target.Target`): one mesh, the ball's
    nodes and elements first (`target_kernel`)."""
    mesh = _ball_mesh(ball, options)
    pole = options.pole_element_size_m or options.element_size_m
    tm = target_mesh([layer.thickness_m for layer in target.layers], target.half_width_m, pole,
                     target.sphere_radius_m)
    nb, n_layers = mesh.n_nodes, len(ball.layers)
    below = mesh.nodes_m[:, 1].min()  # the south pole touches the target's top at t = 0
    nodes = np.concatenate([mesh.nodes_m, tm.nodes_m + [0.0, below]])
    surface = np.asarray(mesh.surface_nodes)
    contact = surface[mesh.nodes_m[surface, 1] < 0.0]  # the lower hemisphere
    combined = dataclasses.replace(
        mesh, nodes_m=nodes, elements=np.concatenate([mesh.elements, tm.elements + nb]),
        element_layer=np.concatenate([mesh.element_layer, tm.element_layer + n_layers]),
        surface_nodes=contact,
        layer_radii_m=tuple(mesh.layer_radii_m) + (0.0,) * len(target.layers))
    geom = dataclasses.replace(element_geometry(combined), surface_layer=n_layers - 1)
    materials = [layer.material for layer in list(ball.layers) + list(target.layers)]
    kernel = Kernel.build(geom, [type(m).energy for m in materials],
                          [m.sum_k > 0 for m in materials],
                          reduced=options.integration == "reduced",
                          dtype=np.dtype(options.precision),
                          backing_modes=0 if target.backing is None else 1)
    return TargetKernel.build_on(kernel, nb, n_layers, contact, tm.top_nodes + nb,
                                 tm.base_nodes + nb, tm.axis_layer_nodes + nb,
                                 tm.thicknesses_m)


def target_structure(target) -> tuple:
    """What a compiled run on a layered target depends on: its layers' thicknesses and material
    models, its width and shape, whether it is backed."""
    return (target.half_width_m, target.sphere_radius_m, target.backing is not None,
            tuple((layer.thickness_m, type(layer.material), layer.material.sum_k > 0,
                   constant_shapes(layer.material)) for layer in target.layers))


def backing_of(target, base_kg: float = 0.0) -> PlaneBacking | None:
    """A target's backing (`fe.hex.target.Backing`: a rigid mass on a spring and damper), with
    the target's base nodes' `base_kg` (kg) added, as the kernel's `PlaneBacking`, unchecked
    (a test's 1e6 kg stands for the fixed base)."""
    b = target.backing
    if b is None:
        return None
    return PlaneBacking.rigid_mass(b.mass_kg + base_kg, b.spring_n_m, b.damper_n_s_m,
                                   f"{target.name}.backing")


def normal_impact_speed(condition: ImpactCondition) -> float:
    """The speed (m/s) of a normal impact without spin, or `InputError`."""
    if not condition.normal:
        raise InputError(f"{condition}: the axisymmetric solver runs normal impacts without spin "
                         "(angle_deg 0, spins 0); oblique and spinning impacts need the 3D "
                         "geometry (fe.Hexahedral, --solver 3d)")
    return condition.speed_m_s


@dataclass(frozen=True)
class Axisymmetric:
    """The axisymmetric geometry with its settings (`options`: mesh, integration, precision and
    the settings both geometries share)."""

    options: SolverOptions = SolverOptions()

    #: the speed range's key (`fe.speed_range.check_fe_speed`)
    solver = "axisymmetric"
    #: element updates above which a run is flagged as very long: about 5 min at
    #: `SECONDS_PER_ELEMENT_STEP` (the universal ball at 25 m/s with 0.2 mm elements; the
    #: default 1.5 mm mesh is 4.6e6 by the estimate, 3.5e6 run)
    ELEMENT_STEPS_WARNING = 2e9
    #: wall time of one element update on a 2-core CPU (s; float64, reduced integration:
    #: 1.3-1.6e-7 measured with 1482 to 20590 elements on the machine of this work while shared
    #: with other jobs; 8e-8 at 1482 elements when it was not, docs/fe.md "Speed")
    SECONDS_PER_ELEMENT_STEP = 1.5e-7
    #: the stable increment of the assembled system over the smallest element's L / c_d at
    #: time_step_scale 0.8 (1.52 on the default meshes of both presets; lower is safer)
    INCREMENT_OVER_SMALLEST_ELEMENT = 1.5
    #: memory of a run (bytes): the process with JAX and the compiled program (peak 0.55-0.6 GB
    #: with 210 to 13,110 elements), and per element and ball run at once (mesh, geometry,
    #: state, Lanczos vectors: 4-6 kB measured with 13,110 to 80,370 elements, reduced
    #: integration; full integration's four points are assumed to double it, not measured)
    BASE_MEMORY_BYTES = 0.6 * 2 ** 30
    MEMORY_PER_ELEMENT_BYTES = 8e3
    #: how to make a run smaller (the warnings and the large-run check)
    HINT = ("a coarser mesh: element_size_m, --element-size-m (or a coarser pole refinement: "
            "pole_element_size_m, --pole-element-size-m)")
    #: what to refine against an inverted element, and to resolve the contact patch
    REFINE = "element size"
    REFINE_POLE = "pole_element_size_m, --pole-element-size-m"
    HISTORY = HISTORY
    #: the state's values a result is made of
    FINAL = ("peak_force", "t_peak", "u_peak", "dt0", "dt", "stretch_min", "stretch_max")
    #: balls per vmapped group on a CPU, where larger groups run out of cache
    CPU_GROUP_SIZE = 4
    #: balls per vmapped group on an accelerator: on an H100 (benchmarks/bench_accelerator.py)
    #: groups of 256, 1024 and 4096 universal balls ran 192, 204 and 219 runs/s in float32 and
    #: 121, 122 and 125 in float64, so 1024 is within 7% of the largest group's rate at a
    #: quarter of its memory
    ACCELERATOR_GROUP_SIZE = 1024

    def __post_init__(self) -> None:
        if not isinstance(self.options, SolverOptions):
            raise InputError(f"Axisymmetric(options): expected SolverOptions, got "
                             f"{type(self.options).__name__}")

    def checked(self, ball, conditions: list, target) -> "Axisymmetric":
        """The geometry for these runs of `ball`: normal impacts on the rigid plane (fixed or
        on a backing, `fe.backing.PlaneBacking`) or on a layered target
        (`fe.hex.target.Target`, flat or a spherical cap, its base fixed or backed)."""
        if target is not None and not isinstance(target, (PlaneBacking, Target)):
            raise InputError(f"target = {type(target).__name__}: expected a PlaneBacking or a "
                             "Target")
        if isinstance(target, Target):
            check_target_width(target, ball)
        for condition in conditions:
            normal_impact_speed(condition)
        return self

    def structure(self, ball, target=None) -> tuple:
        return structure(ball)

    def kernel_key(self, ball, target=None) -> tuple:
        o = self.options
        key = ("axisymmetric", structure(ball), o.element_size_m, o.pole_element_size_m,
               o.pole_zone_deg, o.both_poles, tuple(o.mesh_radii_m), o.integration,
               o.precision)
        if isinstance(target, Target):
            return key + ("target", target_structure(target))
        return key + (0 if target is None else target.count,)

    def build(self, ball, target=None) -> tuple[Kernel, None]:
        if isinstance(target, Target):
            return build_target_kernel(ball, target, self.options), None
        return build_kernel(ball, self.options, 0 if target is None else target.count), None

    def mesh_size(self, ball, target=None) -> tuple[int, float]:
        """(elements, smallest element's length m) of the mesh, from its counting rules (a
        target's cells counted as meshed)."""
        o = self.options
        mesh = estimate_mesh(mesh_radii(ball, o), o.element_size_m, o.pole_element_size_m,
                             o.pole_zone_deg, o.both_poles)
        if not isinstance(target, Target):
            return mesh.elements, mesh.smallest_length_m
        tm = target_mesh([layer.thickness_m for layer in target.layers], target.half_width_m,
                         self.pole_element_m(ball), target.sphere_radius_m)
        cells = np.diff(tm.nodes_m.reshape(-1, len(tm.top_nodes), 2), axis=0)
        depth = float(np.min(np.linalg.norm(cells, axis=-1)))
        width = float(np.min(np.diff(tm.nodes_m[tm.top_nodes, 0])))
        return (mesh.elements + len(tm.elements),
                min(mesh.smallest_length_m, 0.5 * min(depth, width)))

    def pole_element_m(self, ball) -> float:
        return self.options.pole_element_size_m or self.options.element_size_m

    def for_compression(self, ball, contact_radius_m: float) -> "Axisymmetric":
        """The geometry of a platen compression (`fe.compress`): the mesh as set (its default
        for a deflection is `fe.compression.compression_options`), float64, no bulk viscosity."""
        return Axisymmetric(dataclasses.replace(self.options, precision="float64",
                                                bulk_viscosity_linear=0.0,
                                                bulk_viscosity_quadratic=0.0))

    def platen_element_m(self, ball) -> float:
        """The element size at the platens (the top one is refined only with both_poles)."""
        o = self.options
        return (o.pole_element_size_m or o.element_size_m) if o.both_poles else o.element_size_m

    def compression_model(self, ball, kernel: Kernel, relaxed: bool) -> PlatenModel:
        """The ball between two platens (`fe.platens.PlatenModel`): radial motion held on the
        axis; `relaxed`: hourglass springs from the long-term shear moduli."""
        g = kernel.geom
        params = cast(ball_arrays(ball, g, self.options), np.float64)
        if relaxed:
            params = params._replace(hourglass_n_m=relaxed_hourglass(
                params.hourglass_n_m, ball.layers, g.layer_slices))
        nodes = np.asarray(g.nodes_m, np.float64)
        free = np.ones((2, len(nodes)), bool)
        free[0, nodes[:, 0] <= 0.0] = False  # no radial motion on the axis
        ones = np.ones(g.n_elements)

        def internal(params, u, mats, dt):
            f, new_mats, _, _, _, _, J, lam2_min, lam2_max, _ = kernel.internal(
                params, u, mats, ones, dt)
            return f, new_mats, J.min(), lam2_min.min(), lam2_max.max()

        height = nodes[:, 1] - nodes[:, 1].min()
        surface = np.asarray(g.surface_nodes)
        return PlatenModel(internal=internal, initial_materials=kernel.initial_materials,
                           params=params, elements=np.asarray(g.elements), free=free, axis=1,
                           surface=surface,
                           penalty_n_m=np.asarray(params.penalty_n_m), height_m=height)

    def slack(self, target) -> float:
        """The time limit over the Hertz estimate's: a backing's springs or a soft target may
        hold the contact longer than a fixed plane."""
        return 1.0 if target is None else 2.0

    def default_group_size(self, runs: int, cpu: bool) -> int:
        """Balls per vmapped group: `CPU_GROUP_SIZE` on a CPU, up to `ACCELERATOR_GROUP_SIZE`
        on an accelerator."""
        return self.CPU_GROUP_SIZE if cpu else max(1, min(runs, self.ACCELERATOR_GROUP_SIZE))

    def frames_bytes(self, steps: int, elements: int, nodes: int, runs: int) -> float:
        return 0.0

    def params(self, ball, target, kernel: Kernel, condition: ImpactCondition):
        if isinstance(target, Target):
            params = ball_arrays(ball, kernel.geom, self.options, None,
                                 list(ball.layers) + list(target.layers))
            if target.backing is not None:
                # the base's nodes move with the backing: their mass is the backing's
                base_kg = float(np.sum(params.mass_kg[kernel.base_nodes]))
                params = params._replace(**backing_of(target, base_kg).arrays())
            return target_params(params, kernel.ball_nodes)
        params = ball_arrays(ball, kernel.geom, self.options, target)
        if target is not None:
            target.check_against(float(np.max(params.mass_kg[kernel.geom.surface_nodes])),
                                 ball.name)
        return params

    def initial(self, conditions: list) -> list[np.ndarray]:
        return [np.array([c.speed_m_s for c in conditions])]

    def label(self, ball, condition: ImpactCondition) -> str:
        return f"ball {ball.name}"

    def result(self, ball, target, condition: ImpactCondition, history: np.ndarray,
               final: dict, params, t_end: float, kernel: Kernel, mesh, wall: float,
               frames: list) -> ImpactResult:
        n = int(np.searchsorted(history[:, 0], t_end * (1 + 1e-6))) + 1
        h = {name: history[:n, j] for j, name in enumerate(kernel.history_names)}
        speed = condition.speed_m_s
        mass = float(params.ball_mass_kg)
        ke0 = 0.5 * mass * speed ** 2
        largest = energy_histories(h, ke0)
        energies = {name: float(values[-1]) for name, values in h.items()
                    if name.endswith("_j") and not name.startswith("target_layer_")}
        energies["peak_internal_energy_j"] = float(np.max(h["strain_energy_j"]
                                                          + h["hourglass_energy_j"]))
        energies["peak_hourglass_energy_j"] = float(np.max(h["hourglass_energy_j"]))
        if min(energies["viscous_dissipation_j"],
               energies["bulk_viscous_dissipation_j"]) < -1e-3 * ke0:
            warnings.warn(f"ball {ball.name}: a negative dissipation at the end of the run "
                          f"({energies['viscous_dissipation_j']:.3g} J viscous): the "
                          "strain-energy split is approximate at large strains", InputWarning,
                          stacklevel=4)
        energies["initial_kinetic_energy_j"] = ke0
        if isinstance(target, Target):
            energies.update(target_energies(h, target))
            if target.backing is not None:
                energies.update(backing_energies(h, energies, backing_of(target)))
        elif target is not None:
            energies.update(backing_energies(h, energies, target))
        stretch = (float(final["stretch_min"]), float(final["stretch_max"]))
        for message in drucker_warnings(ball, *stretch):
            warnings.warn(f"{message}: principal stretches in this range occurred in the ball "
                          "(in some layer)", InputWarning, stacklevel=4)
        geom = kernel.geom
        cor = float(h["centre_velocity_z_m_s"][-1] / speed)
        return ImpactResult(
            ball_name=ball.name, condition=condition, history=h, cor=cor,
            rebound_speed_m_s=cor * speed,
            peak_force_n=float(final["peak_force"]), time_of_peak_s=float(final["t_peak"]),
            contact_time_s=contact_end_time(h["time_s"], h["contact_force_n"]),
            energy_balance_error=largest / ke0, energies_j=energies,
            stable_time_increment_s=float(final["dt0"]),
            final_time_increment_s=float(final["dt"]), steps=n, elements=geom.n_elements,
            nodes=len(geom.nodes_m), mass_kg=mass, stretch_range=stretch,
            outer_radius_m=ball.outer_radius_m, geometry="axisymmetric",
            target="rigid plane" if target is None else target.name,
            moduli=tuple(layer.material.moduli for layer in ball.layers),
            nodes_m=np.asarray(geom.nodes_m, np.float64), elements_connectivity=geom.elements,
            layer_slices=geom.layer_slices, displacement_at_peak_m=final["u_peak"].T,
            wall_time_s=wall, integration=self.options.integration,
            precision=self.options.precision)
