"""Files of FE results: a run's histories as CSV, the files `ballimpact simulate` writes of one
run (histories, sweep-table row, ParaView series, animation, plot), and a compression curve's
CSV and plot. Tables are `fileio.write_table`'s (SI unit suffixes in the header)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError
from ..fileio import check_output_folder, check_plot_path, column_rows, write_table


@dataclass(frozen=True)
class RunFiles:
    """The files a run or a sweep writes (None: not written; errors name the command line's
    flags): `csv` one run's histories, `table` a row per run (CSV), `vtk` a ParaView time series
    (.pvd or .xdmf) and `animation` a GIF/MP4 of the mid-plane section (3D runs), `plot` a PNG."""

    csv: Path | None = None
    table: Path | None = None
    vtk: Path | None = None
    animation: Path | None = None
    plot: Path | None = None

    @property
    def frames(self) -> bool:
        """Whether the run must keep frames (a time series or an animation)."""
        return self.vtk is not None or self.animation is not None

    def check(self) -> None:
        """Refuse, before anything runs, a file that could not be written: a missing folder, a
        plot that is not a PNG, a series or an animation of the wrong kind."""
        check_output_folder(self.csv, "--csv")
        check_plot_path(self.plot)
        check_output_folder(self.table, "--table")
        check_output_folder(self.vtk, "--vtk")
        if self.vtk is not None and Path(self.vtk).suffix.lower() not in (".pvd", ".xdmf"):
            raise InputError(f"--vtk {self.vtk}: the file must end in .pvd or .xdmf")
        check_output_folder(self.animation, "--animate")
        if self.animation is not None:
            from ..oblique.output import check_animation_path

            check_animation_path(self.animation)

    def refuse(self, *names: str, why: str) -> None:
        """`InputError` for the first of `names` (fields) given: `--FLAG: writes WHAT; WHY`."""
        what = {"csv": "the histories of one run", "vtk": "the time series of one run",
                "animation": "the animation of one run"}
        for name in names:
            if getattr(self, name) is not None:
                flag = "--animate" if name == "animation" else f"--{name}"
                raise InputError(f"{flag}: writes {what[name]}; {why}")


def write_history(path: Path, history: dict) -> str:
    """A run's histories (`ImpactResult.history`) as CSV, one row per step, the names (with SI
    unit suffixes) in the header; returns the path written."""
    names = list(history)
    return write_table(Path(path), names, column_rows(*(history[n] for n in names)))


def write_run_files(result, files: RunFiles) -> dict[str, str]:
    """The `files` of one run (`fe.ImpactResult`): `csv` its histories (`write_history`),
    `table` its speed-sweep row (`sweep.write_table`), `vtk` a ParaView time series and
    `animation` a GIF/MP4 of the mid-plane section (3D runs that kept frames; `oblique.output`),
    `plot` a PNG (force-time curve and deformed shape: `plotting.plot_fe`; 3D:
    `oblique.plots.plot_oblique`). Returns {"csv", "table", "vtk", "animation", "plot"}: the
    paths written, for those given."""
    csv, table, vtk, animation, plot = (files.csv, files.table, files.vtk, files.animation,
                                        files.plot)
    written: dict[str, str] = {}
    if csv is not None:
        written["csv"] = write_history(csv, result.history)
    if table is not None:
        from .sweep import sweep_json_row, write_table as write_rows

        written["table"] = write_rows([sweep_json_row(result)], table)
    if vtk is not None:
        from ..oblique.output import write_series

        written["vtk"] = str(write_series(result, vtk))
    if animation is not None:
        from ..oblique.output import animate_section

        written["animation"] = str(animate_section(result, animation))
    if plot is not None:
        if result.geometry == "axisymmetric":
            from ..plotting import plot_fe

            plot_fe([result], plot)
        else:
            from ..oblique.plots import plot_oblique

            plot_oblique([result], plot)
        written["plot"] = str(plot)
    return written


def write_curve(path: Path, result) -> str:
    """A compression curve (`fe.CompressionResult`) as CSV with the header
    `deflection_m,force_n` (m, N); returns the path written."""
    return write_table(Path(path), ["deflection_m", "force_n"],
                       column_rows(result.deflection_m, result.force_n))


def plot_curve(result, path: Path) -> Path:
    """A compression curve's force (N) against deflection (mm), one PNG; returns its path."""
    from ..plotting import save_and_close, subplots

    figure, axis = subplots(figsize=(5.5, 4.2), layout="constrained")
    axis.plot(result.deflection_m * 1e3, result.force_n, "o-", ms=3)
    axis.set_xlabel("deflection (platen approach), mm")
    axis.set_ylabel("force, N")
    curve = (f"{result.rate_m_s:g} m/s" if result.rate_m_s is not None else "long-term")
    axis.set_title(f"{result.ball_name} between two platens\n({curve})", fontsize=10)
    axis.grid(alpha=0.3)
    return save_and_close(figure, path)
