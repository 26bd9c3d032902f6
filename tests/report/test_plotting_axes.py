"""The plot modules as a library: importing them leaves the user's matplotlib backend alone, each
`draw_*` function draws on an Axes of the caller's own figure and returns it, and the `plot_*`
wrappers still write PNG files."""

import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.figure import Figure

from ballimpact import plotting
from ballimpact.calibrate import plots as calibrate_plots
from ballimpact.calibrate.search import SearchResult
from ballimpact.lumped import fit as fit_lumped
from ballimpact.material import plots as material_plots
from ballimpact.material.data import read_test
from ballimpact.material.hyperelastic import fit_hyperelastic
from ballimpact.oblique import plots as oblique_plots
from ballimpact.records.pipeline import process
from ballimpact.universal import load_model
from ballimpact.universal import plots as universal_plots
from ballimpact.universal.model import TARGETS

DATA = Path(__file__).resolve().parents[2] / "src" / "ballimpact" / "data"
PNG = b"\x89PNG\r\n\x1a\n"
#: every module with pictures: none may choose a backend or import pyplot when imported
PLOT_MODULES = ("ballimpact.plotting", "ballimpact.material.plots", "ballimpact.calibrate.plots",
                "ballimpact.universal.plots", "ballimpact.video.plots",
                "ballimpact.oblique.plots", "ballimpact.oblique.output", "ballimpact.fe.sweep",
                "ballimpact.report.figures")


def test_importing_the_plot_modules_keeps_the_users_backend():
    """In a notebook the user's backend (here svg, set through MPLBACKEND) must survive
    `import ballimpact.plotting`; none of the modules even imports pyplot."""
    code = ("import sys, matplotlib\n"
            f"import {', '.join(PLOT_MODULES)}\n"
            "print(matplotlib.get_backend(), 'matplotlib.pyplot' in sys.modules)\n")
    env = {**os.environ, "MPLBACKEND": "svg"}
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["svg", "False"]


def user_figure():
    """A user's figure of several panels, with a line already on the first (left alone)."""
    figure = Figure(figsize=(9, 6))
    axes = figure.subplots(2, 2)
    axes[0, 0].plot([0, 1], [0, 1], label="the user's own line")
    return figure, axes.flat


@pytest.fixture(scope="module")
def impact(single_params, clean_pulse, noisy_pulse):
    """A processed synthetic impact (filtered, so both force curves are drawn) and a short
    lumped-model fit of it."""
    record = noisy_pulse(clean_pulse("single_element", single_params, 20.0), 0.01, seed=1)
    processed = process(record, filter="cfc12000")
    result = fit_lumped(record, "single_element", generations=4, population=8, seed=0,
                        polish=False)
    return processed, result


def test_impact_panels_draw_on_the_users_axes(impact):
    processed, fit = impact
    figure, (mine, ax_time, ax_loop, _) = user_figure()
    assert plotting.draw_force_time(ax_time, processed.raw, processed.filtered,
                                    processed.features, fit) is ax_time
    assert plotting.draw_force_displacement(ax_loop, processed.features) is ax_loop
    # raw, filtered, peak, fit, the contact legend entry; the window's two edges
    assert len(ax_time.lines) == 7
    labels = ax_time.get_legend_handles_labels()[1]
    assert labels[:2] == ["raw (baseline removed)", "filtered (cfc12000)"]
    assert labels[2].startswith("peak") and labels[-1].startswith("contact")
    assert len(ax_loop.lines) == 1 and ax_loop.get_title().startswith("force-displacement")
    assert len(mine.lines) == 1 and ax_time.figure is figure


def test_fit_panels_draw_on_the_users_axes(impact):
    _, fit = impact
    figure, (_, ax_force, ax_history, ax_speeds) = user_figure()
    assert plotting.draw_fit(ax_force, fit) is ax_force
    assert plotting.draw_fit_convergence(ax_history, fit) is ax_history
    assert plotting.draw_speed_fits(ax_speeds, [fit, fit], title="two") is ax_speeds
    assert ax_force.get_legend_handles_labels()[1] == ["measured", "single_element fit"]
    assert len(ax_history.lines) == 3  # mean, best, final
    assert len(ax_history.lines[1].get_xdata()) == len(fit.history_best)
    assert len(ax_speeds.lines) == 4 and ax_speeds.get_title() == "two"


def fake_fe(name, speed):
    """An FE result's shape for the pictures: one quad element, a half-sine force."""
    t = np.linspace(0.0, 1e-3, 50)
    return SimpleNamespace(
        ball_name=name, impact_speed_m_s=speed, outer_radius_m=0.036,
        history={"time_s": t, "contact_force_n": 5e3 * np.sin(np.pi * t / 1e-3)},
        nodes_m=np.array([[0.0, -0.036], [0.01, -0.036], [0.01, -0.026], [0.0, -0.026]]),
        displacement_at_peak_m=np.zeros((4, 2)), elements_connectivity=np.array([[0, 1, 2, 3]]),
        layer_slices=[(0, 1)], peak_force_n=5e3, time_of_peak_s=5e-4)


def test_fe_panels_draw_on_the_users_axes():
    runs = [fake_fe("a", 10.0), fake_fe("b", 20.0)]
    figure, (_, ax_force, ax_section, _) = user_figure()
    assert plotting.draw_fe_forces(ax_force, runs) is ax_force
    assert plotting.draw_fe_section(ax_section, runs[0]) is ax_section
    assert ax_force.get_legend_handles_labels()[1] == ["a, 10 m/s", "b, 20 m/s"]
    assert len(ax_section.collections) == 2  # the meridian and its mirror image
    assert ax_section.get_title().startswith("a: peak 5.00 kN")


@pytest.fixture(scope="module")
def rubber():
    tests = [read_test(DATA / f"treloar1944_{mode}.csv", mode) for mode in ("uniaxial", "planar")]
    return tests, fit_hyperelastic(tests, "neo_hookean")


def test_material_fit_draws_one_mode_on_the_users_axes(rubber):
    tests, fit = rubber
    figure, (_, ax_uniaxial, ax_planar, _) = user_figure()
    assert material_plots.deformations(tests) == ["uniaxial", "planar"]
    assert material_plots.draw_fit(ax_uniaxial, tests, fit, "uniaxial") is ax_uniaxial
    assert material_plots.draw_fit(ax_planar, tests, fit, "planar") is ax_planar
    assert len(ax_uniaxial.lines) == 2  # data and model of the one uniaxial test
    assert ax_uniaxial.get_title() == "uniaxial" and ax_planar.get_title() == "planar"
    assert ax_planar.get_legend_handles_labels()[1][1].startswith("neo_hookean (R^2 0.")


def search_result(objectives):
    """A calibration's designs over three generations, without running anything."""
    f = np.array([[0.10, 0.05, 0.02], [0.05, 0.08, 0.03], [0.04, 0.04, 0.05],
                  [0.08, 0.02, 0.04], [0.12, 0.09, 0.07], [0.06, 0.03, 0.01]])
    m = len(objectives)
    return SearchResult(problem=SimpleNamespace(objectives=objectives), unit=np.zeros((6, 1)),
                        objectives=f[:, :m], generation=np.array([0, 0, 1, 1, 2, 2]),
                        failed=[], per_test=[], fe_runs=6, wall_time_s=1.0, algorithm="nsga2")


def test_calibration_panels_draw_on_the_users_axes():
    result = search_result(("nrmse", "cor", "contact_time"))
    figure, (_, ax_pair, ax_best, ax_hv) = user_figure()
    assert calibrate_plots.objective_pairs(result) == [(0, 1), (0, 2), (1, 2)]
    assert calibrate_plots.draw_pareto(ax_pair, result, chosen=2, pair=(0, 1)) is ax_pair
    assert ax_pair.get_legend_handles_labels()[1] == ["evaluated", "Pareto front", "chosen"]
    assert len(ax_pair.lines[1].get_xdata()) == len(result.pareto())
    c = result.convergence()
    assert calibrate_plots.draw_best_so_far(ax_best, c, result.problem.objectives) is ax_best
    assert calibrate_plots.draw_hypervolume(ax_hv, c) is ax_hv
    assert len(ax_best.lines) == 3 and len(ax_hv.lines) == 1


def test_single_objective_calibration_draws_against_the_generation():
    result = search_result(("nrmse",))
    figure, (_, ax, _, _) = user_figure()
    assert calibrate_plots.draw_single_objective(ax, result, chosen=5) is ax
    assert list(ax.lines[0].get_xdata()) == [0, 0, 1, 1, 2, 2]
    assert ax.get_legend_handles_labels()[1] == ["chosen"]


def test_held_out_panel_draws_on_the_users_axes():
    model = load_model()
    figure, (_, ax, _, _) = user_figure()
    assert universal_plots.draw_held_out(ax, model, TARGETS[0]) is ax
    assert ax.get_title().startswith(f"{TARGETS[0]}: coverage")
    assert len(ax.collections) == 3  # interval bars, inside, outside
    assert len(ax.lines) == 1  # the diagonal


def fake_oblique(angle_deg, spin):
    """A 3D run's shape for the gripping axes, without running anything."""
    t = np.linspace(0.0, 1e-3, 20)
    return SimpleNamespace(
        condition=SimpleNamespace(speed_m_s=10.0, angle_deg=angle_deg, spin_rad_s=0.0,
                                  friction=0.3),
        normal_cor=0.8, outer_radius_m=0.036, rebound_spin_rad_s=spin,
        history={"time_s": t, "centre_velocity_x_m_s": np.full(20, 5.0)},
        tangential_cor=0.6, contact_point_tangential_cor=-0.2)


def test_gripping_panels_draw_on_the_users_axes():
    runs = [fake_oblique(20.0, 50.0), fake_oblique(40.0, 80.0)]
    figure, (_, ax_spin, ax_cor, ax_sweep) = user_figure()
    assert oblique_plots.draw_gripping(ax_spin, runs, "normalised_spin") is ax_spin
    assert oblique_plots.draw_gripping(ax_cor, runs, "tangential_cor") is ax_cor
    assert oblique_plots.draw_sweep_spin(ax_sweep, runs) is ax_sweep
    # rigid line, FE points; the zero line and the transition
    assert len(ax_spin.lines) == 4 and len(ax_spin.lines[1].get_xdata()) == 2
    assert ax_spin.get_legend() is not None and ax_cor.get_legend() is None  # one legend
    assert ax_cor.get_ylabel().startswith("tangential COR")
    assert len(ax_sweep.lines) == 3


def test_plot_wrappers_still_write_png(tmp_path, impact, rubber):
    processed, fit = impact
    tests, rubber_fit = rubber
    written = [
        plotting.plot_impact(processed.raw, processed.filtered, processed.features,
                             tmp_path / "impact.png", title="impact", fit=fit),
        plotting.plot_fit(fit, tmp_path / "fit.png"),
        plotting.plot_speed_fits([fit], tmp_path / "speeds.png"),
        plotting.plot_fe([fake_fe("a", 10.0)], tmp_path / "fe.png"),
        material_plots.plot_fit(tests, rubber_fit, tmp_path / "material.png"),
        calibrate_plots.plot_pareto(search_result(("nrmse", "cor")), 2, tmp_path / "pareto.png"),
    ]
    for path in written:
        assert path.read_bytes()[:8] == PNG and path.stat().st_size > 10_000, path


def test_save_and_close_releases_a_pyplot_figure(tmp_path):
    """A figure a user made with pyplot is dropped from pyplot's list once written."""
    plt = pytest.importorskip("matplotlib.pyplot")
    figure, ax = plt.subplots()
    ax.plot([0, 1], [1, 0])
    path = plotting.save_and_close(figure, tmp_path / "mine.png", "title")
    assert path.read_bytes()[:8] == PNG
    assert not plt.fignum_exists(figure.number)
