"""Output of 3D runs for viewing: a time series written with meshio (ParaView opens both kinds:
`.pvd`, one compressed binary `.vtu` per frame and an index; or `.xdmf`, one file, with HDF5 data
where h5py is installed, XML otherwise), and an animation (GIF, or MP4 where ffmpeg is installed)
of the mid-plane section y = 0.

Fields: point data `displacement_m`, `velocity_m_s`, `contact_force_n` and `contact_pressure_pa`
(normal contact force over the node's share of the surface); cell data `stress_pa` (Cauchy:
xx, yy, zz, xy, yz, zx), `von_mises_pa`, `pressure_pa` and `group` (ball layers, then target
layers). A half model is written as it is (ParaView's Reflect filter mirrors it about y = 0).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..fe.hex.element import FACES


def _need_frames(result) -> None:
    if not result.frames:
        raise InputError("no frames were kept: run with Options3D(frames=N) (N >= 1)")


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises stress of (6, n) Cauchy components (Pa)."""
    xx, yy, zz, xy, yz, zx = stress
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2)
                   + 3.0 * (xy ** 2 + yz ** 2 + zx ** 2))


def _surface_quads(elements: np.ndarray, node_set: np.ndarray) -> np.ndarray:
    """Element faces (n, 4) whose four nodes are all in `node_set` (bool per node)."""
    faces = np.concatenate([elements[:, list(f)] for f in FACES])
    return faces[np.all(node_set[faces], axis=1)]


def tributary_area_m2(nodes: np.ndarray, elements: np.ndarray, surface: np.ndarray) -> np.ndarray:
    """Each node's quarter share of the areas of the surface faces around it (m^2)."""
    mask = np.zeros(len(nodes), bool)
    mask[surface] = True
    quads = _surface_quads(elements, mask)
    x = nodes[quads]
    area = 0.5 * np.linalg.norm(np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1]), axis=1)
    out = np.zeros(len(nodes))
    np.add.at(out, quads.reshape(-1), np.repeat(area / 4.0, 4))
    return out


def _frame_data(result):
    """Per frame: time, point data and cell data (see the module docstring)."""
    geom = result.kernel_geometry
    nodes, elements = np.asarray(geom.nodes_m, float), np.asarray(geom.elements)
    area = tributary_area_m2(nodes, elements, result.mesh.contact_nodes)
    group = np.concatenate([np.full(b - a, i) for i, (a, b) in enumerate(geom.group_slices)])
    for frame in result.frames:
        force = frame["contact_force_n"].T
        pressure = np.where(area > 0, np.abs(force[:, 2]) / np.where(area > 0, area, 1.0), 0.0)
        stress = frame["stress_pa"]
        yield frame["time_s"], {
            "displacement_m": frame["displacement_m"].T, "velocity_m_s": frame["velocity_m_s"].T,
            "contact_force_n": force, "contact_pressure_pa": pressure}, {
            "stress_pa": [stress.T], "von_mises_pa": [von_mises(stress)],
            "pressure_pa": [-(stress[0] + stress[1] + stress[2]) / 3.0],
            "group": [group.astype(float)]}


def write_series(result, path) -> Path:
    """The kept frames as a time series: `.pvd` (with `.vtu` files beside it, named after it)
    or `.xdmf`."""
    import meshio

    _need_frames(result)
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".pvd", ".xdmf"):
        raise InputError(f"--vtk {path}: the file must end in .pvd or .xdmf")
    geom = result.kernel_geometry
    points, cells = np.asarray(geom.nodes_m, float), [("hexahedron", np.asarray(geom.elements))]
    if suffix == ".xdmf":
        data_format = "HDF" if importlib.util.find_spec("h5py") else "XML"
        with meshio.xdmf.TimeSeriesWriter(str(path), data_format=data_format) as writer:
            writer.write_points_cells(points, cells)
            for t, point_data, cell_data in _frame_data(result):
                writer.write_data(t, point_data=point_data, cell_data=cell_data)
        return path
    entries = []
    for i, (t, point_data, cell_data) in enumerate(_frame_data(result)):
        name = f"{path.stem}_{i:04d}.vtu"
        meshio.write(path.parent / name, meshio.Mesh(points, cells, point_data=point_data,
                                                     cell_data=cell_data), binary=True)
        entries.append(f'    <DataSet timestep="{t:.9g}" part="0" file="{name}"/>')
    path.write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                    "  <Collection>\n" + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return path


def _section(result):
    """Faces of the mid-plane y = 0 (n, 4) and the element each belongs to."""
    geom = result.kernel_geometry
    nodes, elements = np.asarray(geom.nodes_m, float), np.asarray(geom.elements)
    on_plane = np.abs(nodes[:, 1]) < 1e-9 * result.outer_radius_m
    faces, owners = [], []
    for f in FACES:
        quad = elements[:, list(f)]
        keep = np.all(on_plane[quad], axis=1)
        faces.append(quad[keep])
        owners.append(np.flatnonzero(keep))
    return np.concatenate(faces), np.concatenate(owners)


def _draw(ax, result, frame, faces, owners, norm):
    from matplotlib.collections import PolyCollection

    nodes = np.asarray(result.kernel_geometry.nodes_m, float)
    x = nodes + frame["displacement_m"].T
    polys = x[faces][:, :, [0, 2]] * 1e3
    mises = von_mises(frame["stress_pa"])[owners] / 1e6
    coll = PolyCollection(polys, array=mises, cmap="viridis", norm=norm, edgecolors="k",
                          linewidths=0.15)
    ax.add_collection(coll)
    return coll


def _stress_scale(result):
    """One colour scale for every frame: 0 to the run's peak von Mises stress (MPa)."""
    from matplotlib.colors import Normalize

    return Normalize(0, max(np.max(von_mises(f["stress_pa"])) for f in result.frames) / 1e6)


def draw_section(ax, result, frame_index: int = -1):
    """The mid-plane section of one kept frame on the matplotlib Axes `ax` (mm), coloured by
    von Mises stress (MPa, on the run's scale) with a colour bar. Returns `ax`."""
    _need_frames(result)
    faces, owners = _section(result)
    frame = result.frames[frame_index]
    coll = _draw(ax, result, frame, faces, owners, _stress_scale(result))
    _frame_axes(ax, result, frame["time_s"])
    ax.figure.colorbar(coll, ax=ax, label="von Mises stress (MPa)")
    return ax


def section_figure(result, frame_index: int = -1, path=None):
    """A matplotlib `Figure` (no pyplot) of `draw_section`; PNG if `path`."""
    from ..plotting import subplots

    fig, ax = subplots(figsize=(6, 4.5))
    draw_section(ax, result, frame_index)
    if path is not None:
        fig.savefig(path, dpi=120, bbox_inches="tight")
    return fig


def _frame_axes(ax, result, t):
    r = result.outer_radius_m * 1e3
    c = result.condition
    ax.axhline(0.0, color="0.3", lw=1.5)
    ax.set_xlim(-1.6 * r, 2.6 * r)
    ax.set_ylim(-0.4 * r, 2.3 * r)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm)")
    ax.set_title(f"{c.speed_m_s:g} m/s at {c.angle_deg:g} deg, "
                 f"mu {c.friction:g}; t = {t * 1e3:.3f} ms", fontsize=9)


def check_animation_path(path) -> None:
    """Refuse, before a run, an animation file that `animate_section` could not write: a suffix
    other than .gif or .mp4, or .mp4 without ffmpeg."""
    path = Path(path)
    if path.suffix.lower() not in (".gif", ".mp4"):
        raise InputError(f"--animate {path}: the file must end in .gif or .mp4")
    if path.suffix.lower() == ".mp4":
        from matplotlib import animation

        if not animation.FFMpegWriter.isAvailable():
            raise InputError(f"--animate {path}: MP4 needs ffmpeg; write a .gif instead")


def animate_section(result, path, fps: int = 12) -> Path:
    """An animation of the mid-plane section over the kept frames: GIF, or MP4 (ffmpeg)."""
    from matplotlib import animation

    from ..plotting import subplots

    _need_frames(result)
    path = Path(path)
    if path.suffix.lower() not in (".gif", ".mp4"):
        raise InputError(f"--animate {path}: the file must end in .gif or .mp4")
    faces, owners = _section(result)
    norm = _stress_scale(result)
    fig, ax = subplots(figsize=(6, 4.5))
    coll = _draw(ax, result, result.frames[0], faces, owners, norm)
    fig.colorbar(coll, ax=ax, label="von Mises stress (MPa)")

    def update(i):
        for artist in list(ax.collections):
            artist.remove()
        _draw(ax, result, result.frames[i], faces, owners, norm)
        _frame_axes(ax, result, result.frames[i]["time_s"])
        return ax.collections

    anim = animation.FuncAnimation(fig, update, frames=len(result.frames), blit=False)
    if path.suffix.lower() == ".gif":
        anim.save(path, writer=animation.PillowWriter(fps=fps), dpi=80)
    else:
        if not animation.FFMpegWriter.isAvailable():
            raise InputError(f"--animate {path}: MP4 needs ffmpeg; write a .gif instead")
        anim.save(path, writer=animation.FFMpegWriter(fps=fps), dpi=100)
    return path
