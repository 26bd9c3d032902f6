"""Ball models for other codes (docs/export.md): ABAQUS/CalculiX input decks, LS-DYNA
keyword decks and VTK/XDMF meshes, and the import of ABAQUS materials.

`export_ball` writes a complete impact on a rigid plane (or, with `ball_only`, the ball for the
user's own model) and returns what it wrote; `read_materials` / `read_ball` read ABAQUS input
back into the ball specification. Values are SI in and out; files carry the unit system named in
their header (`units`).
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError, InputWarning
from ..balls.ball import BallModel
from ..fe.progress import RunEstimate
from ..checks import check_allow
from . import abaqus, lsdyna, vtk
from .geometry import SOLVERS, BallGeometry, ball_geometry, estimate_elements
from .importer import import_abaqus_file, read_abaqus_file, read_ball, read_materials
from .materials import ExportError
from .setup import ImpactSetup
from .units import MM_TONNE_S, SI, UNIT_SYSTEMS, UnitSystem, unit_system

FORMATS = ("abaqus", "calculix", "lsdyna", "vtk")
SUFFIXES = {"abaqus": (".inp",), "calculix": (".inp",), "lsdyna": (".k", ".key", ".dyn"),
            "vtk": vtk.SUFFIXES}
#: largest shortfall of the mesh's mass below the ball's before the export says so
MESH_MASS_TOLERANCE = 0.02
DEFAULT_UNITS = {"abaqus": "mm-tonne-s", "calculix": "mm-tonne-s", "lsdyna": "mm-tonne-s",
                 "vtk": "si"}
#: memory of an export (bytes): the process, and per element the mesh, its geometry and the deck's
#: text (peaks measured writing ABAQUS decks of cricket-3layer: 0.29 GB with 2242 quadrilaterals,
#: 0.39 GB with 223,344, i.e. 0.5 kB each; 0.35 GB with 19,456 hexahedra, 1.0 GB with 131,072,
#: i.e. 5.8 kB each). On the high side.
EXPORT_BASE_BYTES = 0.4 * 2 ** 30
EXPORT_BYTES_PER_ELEMENT = {"axisymmetric": 1e3, "3d": 8e3}


def check_export_memory(ball: BallModel, solver: str = "axisymmetric", *,
                        element_size_m: float | None = None, divisions: int | None = None,
                        pole_grading: float | None = None, half: bool = False,
                        allow=()) -> RunEstimate:
    """The `large-run` check of an export before the ball is meshed: its memory, estimated from
    the mesh's counting rules (`geometry.estimate_elements`), against the available memory.
    Returns the estimate (steps 0: nothing is run)."""
    elements = estimate_elements(ball, solver, element_size_m=element_size_m,
                                 divisions=divisions, pole_grading=pole_grading, half=half)
    hint = ("a coarser mesh: --element-size-m, element_size_m" if solver == "axisymmetric"
            else "a coarser mesh: fewer --divisions")
    estimate = RunEstimate(elements=elements, steps=0, end_time_s=0.0, memory_bytes=0.0,
                           element_steps_limit=float("inf"), seconds_per_element_step=0.0,
                           hint=hint, model_bytes=EXPORT_BASE_BYTES
                           + EXPORT_BYTES_PER_ELEMENT[solver] * elements,
                           base_bytes=EXPORT_BASE_BYTES)
    estimate.check_memory(check_allow(allow), what="the export")
    return estimate


@dataclass(frozen=True)
class Export:
    """What `export_ball` wrote."""

    path: Path
    format: str
    units: str
    solver: str
    ball_only: bool
    n_nodes: int
    n_elements: int
    mesh_mass_kg: float
    notes: list[str] = field(default_factory=list)
    step_time_s: float | None = None

    def summary(self) -> dict:
        return {"out": str(self.path), "format": self.format, "units": self.units,
                "solver": self.solver, "ball_only": self.ball_only, "nodes": self.n_nodes,
                "elements": self.n_elements, "mesh_mass_kg": self.mesh_mass_kg,
                "step_time_s": self.step_time_s, "notes": self.notes}


def check_output(path: Path, fmt: str) -> None:
    """Refuse a path the format cannot have or that cannot be written (before any work)."""
    if fmt not in FORMATS:
        raise InputError(f"format = {fmt!r}: allowed {', '.join(FORMATS)}")
    path = Path(path)
    if path.suffix.lower() not in SUFFIXES[fmt]:
        raise InputError(f"out = {str(path)!r}: a {fmt} file ends in "
                         f"{' or '.join(SUFFIXES[fmt])}")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError(f"out = {str(path)!r}: folder {folder} does not exist")
    if not os.access(folder, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise InputError(f"out = {str(path)!r}: not writable")


def export_ball(ball: BallModel, path: Path, fmt: str, *, solver: str = "axisymmetric",
                setup: ImpactSetup | None = None, ball_only: bool = False,
                units: str | None = None, moduli: str | None = None, approximate: bool = False,
                element_size_m: float | None = None, divisions: int | None = None,
                pole_grading: float | None = None, half: bool = False, allow=()) -> Export:
    """Write `ball` in `fmt` to `path`. A complete deck needs `setup` (the impact); `ball_only`
    writes the ball alone (VTK is always the ball alone). `units`: si or mm-tonne-s (default
    mm-tonne-s for the decks, si for VTK). `moduli` picks CalculiX's elastic ball of a
    viscoelastic one; `approximate` lets LS-DYNA take the nearest card where a material has no
    exact one. Raises `InputError` (`ExportError`) naming what a format cannot express, and
    before meshing, one that would not fit in memory (`check_export_memory`: the `large-run`
    check, overridden by `allow`)."""
    path = Path(path)
    check_output(path, fmt)
    system = unit_system(units or DEFAULT_UNITS[fmt])
    if moduli is not None and moduli not in ("long_term", "instantaneous"):
        raise InputError(f"moduli = {moduli!r}: allowed long_term, instantaneous")
    if fmt == "vtk":
        ball_only = True
    if not ball_only and setup is None:
        raise InputError("a complete deck needs the impact (speed_m_s); or ask for ball_only")
    if half and (ball_only or solver != "3d"):
        raise InputError("half: only a 3D impact deck can be a half model (a ball for "
                         "inclusion is whole)")
    check_export_memory(ball, solver, element_size_m=element_size_m, divisions=divisions,
                        pole_grading=pole_grading, half=half, allow=allow)
    geom = ball_geometry(ball, solver, element_size_m=element_size_m, divisions=divisions,
                         pole_grading=pole_grading, half=half)
    notes: list[str] = []
    mesh_mass = geom.mass_kg(ball)
    shortfall = 1.0 - mesh_mass / ball.mass_kg
    if shortfall > MESH_MASS_TOLERANCE:  # the chords of a coarse mesh cut off the surface
        notes.append(f"the mesh's mass {mesh_mass:.4g} kg is {100 * shortfall:.1f}% "
                     f"below the ball's {ball.mass_kg:.4g} kg: refine the mesh (divisions, "
                     "element_size_m) for a faithful ball")
    if fmt == "vtk":
        text = None
    elif fmt == "lsdyna":
        text, deck_notes = lsdyna.write_deck(ball, geom, system, setup, ball_only, approximate)
        lsdyna.validate(text)
    else:
        text, deck_notes = abaqus.write_deck(ball, geom, system, fmt, setup, ball_only, moduli)
    if text is not None:
        notes = deck_notes + notes
    try:
        if text is None:
            vtk.write_mesh(path, ball, geom, system)
        else:
            path.write_text(text, encoding="ascii")
    except OSError as error:
        raise InputError(f"out = {str(path)!r}: cannot write ({error.strerror or error})") from None
    return Export(path, fmt, system.name, solver, ball_only, len(geom.nodes_m),
                  len(geom.elements), mesh_mass, notes,
                  None if ball_only else setup.step_time(ball))


def _refuse_other_solver_mesh(solver: str, element_size_m: float | None,
                              divisions: int | None, pole_grading: float | None) -> None:
    """A mesh flag of the other solver would be ignored silently: refuse it."""
    if solver == "3d" and element_size_m is not None:
        raise InputError("--element-size-m: sets the axisymmetric mesh; with --solver 3d the "
                         "mesh is set by --divisions and --pole-grading")
    if solver == "axisymmetric":
        for flag, value in (("--divisions", divisions), ("--pole-grading", pole_grading)):
            if value is not None:
                raise InputError(f"{flag}: sets the 3D mesh; the axisymmetric mesh is set by "
                                 "--element-size-m (or give --solver 3d)")


def _warn_ignored_impact_flags(ball_only: bool, angle_deg: float | None,
                               friction: float | None, step_time_s: float | None) -> None:
    """The impact's flags mean nothing to a file of the ball alone (--ball-only, or VTK): an
    `InputWarning` that names those given."""
    ignored = [flag for flag, value in (("--angle-deg", angle_deg), ("--friction", friction),
                                        ("--step-time-s", step_time_s)) if value is not None]
    if ignored:
        what = "--ball-only" if ball_only else "--format vtk"
        warnings.warn(f"{', '.join(ignored)}: ignored with {what} (the file holds the ball "
                      "alone, no impact); they set a complete deck's impact", InputWarning,
                      stacklevel=3)


def export_ball_spec(ball: str | Path, path: Path, fmt: str, *, speed_m_s: float | None = None,
                     angle_deg: float | None = None, friction: float | None = None,
                     step_time_s: float | None = None, solver: str = "axisymmetric",
                     ball_only: bool = False, units: str | None = None,
                     moduli: str | None = None, approximate: bool = False,
                     element_size_m: float | None = None, divisions: int | None = None,
                     pole_grading: float | None = None, half: bool = False,
                     allow=()) -> dict:
    """`ballimpact export`: the ball `ball` (preset or specification file, its constants at
    `speed_m_s` (m/s) where they depend on the speed; `moduli` overriding its convention)
    written by `export_ball` to `path` in `fmt`. A complete deck's impact is `speed_m_s`,
    `angle_deg` (deg, default 0), `friction` (default 0) and `step_time_s` (s, default from a
    Hertz estimate); those given for a file of the ball alone (`ball_only`, VTK) get an
    `InputWarning`. Returns the ball's name and `mass_kg` (kg), `Export.summary()` (its
    `notes` included) and, for a deck, its impact (`impact_speed_m_s`, `angle_deg`,
    `friction`). Raises `InputError` (naming the flag) on a mesh option of the other solver,
    a deck without a speed, and what `export_ball` raises."""
    from ..fe.runs import load_model

    check_output(path, fmt)
    _refuse_other_solver_mesh(solver, element_size_m, divisions, pole_grading)
    allow = check_allow(allow)
    model = load_model(ball, speed_m_s, moduli=moduli, allow=allow)
    setup = None
    if not ball_only and fmt != "vtk":
        if speed_m_s is None:
            raise InputError("--speed-m-s: needed for a complete deck (or give --ball-only)")
        setup = ImpactSetup(speed_m_s, angle_deg or 0.0, friction or 0.0, step_time_s)
    else:
        _warn_ignored_impact_flags(ball_only, angle_deg, friction, step_time_s)
    written = export_ball(model, path, fmt, solver=solver, setup=setup, ball_only=ball_only,
                          units=units, moduli=moduli, approximate=approximate,
                          element_size_m=element_size_m, divisions=divisions,
                          pole_grading=pole_grading, half=half, allow=allow)
    out = {"ball": model.name, "mass_kg": model.mass_kg, **written.summary()}
    if setup is not None:
        out.update(impact_speed_m_s=setup.speed_m_s, angle_deg=setup.angle_deg,
                   friction=setup.friction)
    return out


__all__ = ["DEFAULT_UNITS", "FORMATS", "MM_TONNE_S", "SI", "SOLVERS", "UNIT_SYSTEMS",
           "BallGeometry", "Export", "ExportError", "ImpactSetup", "UnitSystem", "ball_geometry",
           "check_export_memory", "check_output", "export_ball", "export_ball_spec",
           "import_abaqus_file", "read_abaqus_file", "read_ball", "read_materials"]
