"""The meshed ball for ParaView (meshio): `.vtu`, `.vtk` or `.xdmf` with per-cell layer index,
density and instantaneous moduli (the deck's units)."""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np

from ..errors import InputError
from ..balls.ball import BallModel
from .geometry import BallGeometry
from .units import UnitSystem

SUFFIXES = (".vtu", ".vtk", ".xdmf")


def write_mesh(path: Path, ball: BallModel, geom: BallGeometry, units: UnitSystem) -> None:
    points = geom.nodes_m * units.length
    if geom.dimension == 2:  # (r, z) in the x-y plane, as the decks
        points = np.column_stack([points, np.zeros(len(points))])
    cell_type = "quad" if geom.dimension == 2 else "hexahedron"
    layer = geom.element_layer.astype(np.int32)

    def per_layer(values) -> list[np.ndarray]:
        return [np.asarray(values, dtype=float)[layer]]

    cell_data = {
        "layer": [layer],
        "density": per_layer([l.density_kg_m3 * units.density for l in ball.layers]),
        "shear_modulus_instantaneous": per_layer(
            [l.material.shear_modulus_pa() * units.stress for l in ball.layers]),
        "bulk_modulus_instantaneous": per_layer(
            [l.material.bulk_modulus_pa() * units.stress for l in ball.layers]),
    }
    mesh = meshio.Mesh(points, [(cell_type, geom.elements.astype(np.int64))], cell_data=cell_data)
    try:
        meshio.write(str(path), mesh)
    except ModuleNotFoundError as error:  # XDMF needs h5py, an optional dependency of meshio
        raise InputError(f"out = {str(path)!r}: writing {path.suffix} needs the Python package "
                         f"{error.name!r} (pip install {error.name}); .vtu needs nothing "
                         "more") from None
