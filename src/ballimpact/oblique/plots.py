"""Plots of 3D oblique impacts: histories of one run, and a sweep of incidence against the
rigid-body lines (and, in the gripping regime, the elastic-sphere reference).

Each panel is a `draw_*(ax, ...)` function on a matplotlib Axes the caller gives (returned); the
`plot_*` functions lay the panels out and write a file. Nothing here chooses a backend."""

from __future__ import annotations

import numpy as np

from .rigid_body import (HOMOGENEOUS_K2, normalised_incidence, normalised_spin, rigid_lines)


def _run_colors(results) -> list[str]:
    """A colour per run from the property cycle, the same in every panel of `plot_oblique`."""
    import matplotlib

    cycle = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    return [cycle[i % len(cycle)] for i in range(len(results))]


def _label(run) -> str:
    c = run.condition
    return f"{c.speed_m_s:g} m/s, {c.angle_deg:g} deg, mu {c.friction:g}"


def _finish_panel(ax, xlabel: str, ylabel: str) -> None:
    ax.set(xlabel=xlabel, ylabel=ylabel)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


def draw_oblique_forces(ax, results):
    """Normal (solid) and tangential (dashed) contact force against time of 3D runs on `ax`
    (ms, kN), a colour per run. Returns `ax`."""
    for r, color in zip(results, _run_colors(results)):
        h = r.history
        t = h["time_s"] * 1e3
        ax.plot(t, h["contact_force_n"] / 1e3, color=color, label=f"normal ({_label(r)})")
        ax.plot(t, h["tangential_force_x_n"] / 1e3, "--", color=color, label="tangential")
    _finish_panel(ax, "time (ms)", "contact force (kN)")
    return ax


def draw_oblique_spin(ax, results):
    """Spin about y against time of 3D runs on `ax` (rad/s, + topspin), a colour per run; for
    one run also its contact-point slip velocity, on a twin axis at the right. Returns `ax`."""
    for r, color in zip(results, _run_colors(results)):
        h = r.history
        ax.plot(h["time_s"] * 1e3, h["spin_y_rad_s"], color=color, label=f"spin ({_label(r)})")
    if len(results) == 1:  # several runs' slip velocities would crowd the panel
        h = results[0].history
        twin = ax.twinx()
        twin.plot(h["time_s"] * 1e3, h["contact_slip_velocity_m_s"], ":", color="C3")
        twin.set_ylabel("contact-point slip velocity (m/s)", color="C3")
    _finish_panel(ax, "time (ms)", "spin about y (rad/s, + topspin)")
    return ax


def draw_oblique_energy(ax, results):
    """The energy account against time of 3D runs on `ax` (J): kinetic, viscous and frictional
    dissipation, strain energy (a line style each, a colour per run). Returns `ax`."""
    for r, color in zip(results, _run_colors(results)):
        h = r.history
        for name, style in (("kinetic_energy_j", "-"), ("viscous_dissipation_j", "--"),
                            ("frictional_dissipation_j", ":"), ("strain_energy_j", "-.")):
            ax.plot(h["time_s"] * 1e3, h[name], style, color=color,
                    label=name.replace("_j", "").replace("_", " ") if r is results[0] else None)
    _finish_panel(ax, "time (ms)", "energy (J)")
    return ax


def plot_oblique(results, path) -> None:
    """Write a PNG of one or more runs: `draw_oblique_forces`, `draw_oblique_spin` and
    `draw_oblique_energy` side by side."""
    from ..plotting import save_and_close, subplots

    fig, axes = subplots(1, 3, figsize=(14, 4))
    draw_oblique_forces(axes[0], results)
    draw_oblique_spin(axes[1], results)
    draw_oblique_energy(axes[2], results)
    fig.tight_layout()
    save_and_close(fig, path)


def sweep_points(results) -> dict[str, np.ndarray]:
    """Normalised incidence, rebound spin and tangential velocity change of runs without
    initial spin (each normalised with its own normal COR)."""
    psi, spin, dv = [], [], []
    for r in results:
        c = r.condition
        theta = np.radians(c.angle_deg)
        v_x, v_n = c.speed_m_s * np.sin(theta), c.speed_m_s * np.cos(theta)
        e = r.normal_cor
        psi.append(normalised_incidence(v_x, v_n, c.spin_rad_s, r.outer_radius_m, c.friction, e))
        spin.append(normalised_spin(r.rebound_spin_rad_s, r.outer_radius_m, c.friction, e, v_n))
        dv.append((v_x - r.history["centre_velocity_x_m_s"][-1]) / (c.friction * (1 + e) * v_n))
    return {"psi": np.array(psi), "spin": np.array(spin), "tangential_change": np.array(dv)}


_PSI_LABEL = "normalised incidence Psi = 2 tan(theta) / (mu (1 + e_n))"


def _psi_top(psi) -> float:
    """The right end of the Psi axis: past the rigid transition (7 for k^2 = 0.4) and the runs."""
    finite = np.asarray(psi, float)[np.isfinite(psi)]
    return max(12.0, 1.1 * finite.max()) if finite.size else 12.0


def _save(fig, path, title: str) -> None:
    """The title (small: it can be long) above tightly laid out panels; saved and closed."""
    from ..plotting import save_and_close

    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    save_and_close(fig, path)


def _finish_sweep_panel(ax, transition: float) -> None:
    """The rigid-body transition (dashed), a legend and a grid."""
    ax.axvline(transition, color="0.6", lw=0.8, ls="--")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)


def _rigid_sweep_lines(psi):
    """The rigid-body lines (k^2 = 0.4) over the Psi axis of the runs `psi`."""
    psi_line = np.linspace(0, _psi_top(psi), 300)
    return (psi_line, *rigid_lines(psi_line, HOMOGENEOUS_K2))


# the rigid transition Psi = 2 (1 + k^2) / k^2 is 7 at k^2 = 0.4
_SWEEP_TRANSITION = 7.0


def _draw_sweep_panel(ax, results, line: int, key: str, line_label: str, ylabel: str):
    """One normalised quantity (`key` of `sweep_points`) against normalised incidence on `ax`,
    with rigid-body line `line` of `_rigid_sweep_lines` (1 spin, 2 tangential change)."""
    pts = sweep_points(results)
    lines = _rigid_sweep_lines(pts["psi"])
    ax.plot(lines[0], lines[line], "k-", label=line_label)
    ax.plot(pts["psi"], pts[key], "o", label="3D FE")
    ax.set(xlabel="normalised incidence 2 tan(theta) / (mu (1 + e_n))", ylabel=ylabel)
    _finish_sweep_panel(ax, _SWEEP_TRANSITION)
    return ax


def draw_sweep_spin(ax, results):
    """Normalised rebound spin against normalised incidence of runs without initial spin on
    `ax`, with the rigid-body line (k^2 = 0.4). Returns `ax`."""
    return _draw_sweep_panel(ax, results, 1, "spin", "rigid body (rolling, then sliding)",
                             "normalised spin w' R / (mu (1 + e_n) v_n)")


def draw_sweep_tangential(ax, results):
    """Normalised tangential velocity change against normalised incidence of runs without
    initial spin on `ax`, with the rigid-body line (k^2 = 0.4). Returns `ax`."""
    return _draw_sweep_panel(ax, results, 2, "tangential_change", "rigid body",
                             "(v_x - v_x') / (mu (1 + e_n) v_n)")


def plot_sweep(results, path, title: str = "") -> None:
    """Write `draw_sweep_spin` and `draw_sweep_tangential` side by side."""
    from ..plotting import subplots

    fig, axes = subplots(1, 2, figsize=(11, 4))
    draw_sweep_spin(axes[0], results)
    draw_sweep_tangential(axes[1], results)
    _save(fig, path, title)


def rigid_gripping_lines(psi, k2: float = HOMOGENEOUS_K2) -> dict[str, np.ndarray]:
    """The rigid-body lines (rolling, then sliding; no initial spin) against Psi (> 0) in the
    three gripping axes: normalised spin Omega (`rigid_lines`), and from the kinematic identities
    the tangential COR of the centre e_t = 1 - 2 k^2 Omega / Psi and of the contact point
    e_cp = -e_t + 2 Omega / Psi."""
    psi = np.asarray(psi, float)
    spin, _ = rigid_lines(psi, k2)
    e_t = 1.0 - 2.0 * k2 * spin / psi
    return {"normalised_spin": spin, "tangential_cor": e_t,
            "contact_point_cor": -e_t + 2.0 * spin / psi}


def gripping_points(results) -> dict[str, np.ndarray]:
    """The FE runs (no initial spin) in the gripping axes, each normalised with its own e_n:
    Psi, Omega (`sweep_points`), the tangential COR of the centre and of the contact point; runs
    whose Psi is not finite and positive (normal incidence, no friction) are left out."""
    pts = sweep_points(results)
    out = {"psi": pts["psi"], "normalised_spin": pts["spin"],
           "tangential_cor": np.array([r.tangential_cor for r in results], float),
           "contact_point_cor": np.array([r.contact_point_tangential_cor for r in results],
                                         float)}
    keep = np.isfinite(out["psi"]) & (out["psi"] > 0)
    return {key: value[keep] for key, value in out.items()}


#: the three panels of `plot_gripping`: key, y label
GRIPPING_PANELS = (("normalised_spin", "normalised spin Omega = w' R / (mu (1 + e_n) v_n)"),
                   ("tangential_cor", "tangential COR of the centre e_t = v_x' / v_x"),
                   ("contact_point_cor", "contact-point COR e_cp = -(v_x' - w' R) / v_x"))


def draw_gripping(ax, results, key: str = "normalised_spin", reference=None, *,
                  k2: float = HOMOGENEOUS_K2, poissons_ratio: float | None = None):
    """One of the gripping axes against the normalised incidence Psi on `ax`: `key` of
    `GRIPPING_PANELS` (Omega, e_t or e_cp; Maw, Barber & Fawcett's axes) of the FE runs (without
    initial spin; each normalised with its own e_n), the rigid-body line for `k2` (rolling, then
    sliding; dashed at the transition Psi = 2 (1 + k^2) / k^2) and, when given, the
    elastic-sphere reference `reference` (the dict of `elastic_reference.normalised_curves`,
    labelled with `poissons_ratio`). The Omega panel carries the legend. Returns `ax`."""
    pts = gripping_points(results)
    top = _psi_top(pts["psi"])
    if reference is not None:  # the whole reference shown (the CLI's grid ends at this top)
        top = max(top, float(np.nanmax(reference["psi"])))
    psi_line = np.linspace(0.02, top, 400)  # e_t and e_cp are 0/0 at Psi = 0
    ax.plot(psi_line, rigid_gripping_lines(psi_line, k2)[key], "k-", lw=1.2,
            label=f"rigid body (rolling, then sliding; k^2 = {k2:.3g})")
    if reference is not None:
        nu = "" if poissons_ratio is None else f", nu = {poissons_ratio:.3g}"
        ax.plot(reference["psi"], reference[key], "-", color="C1", lw=1.5,
                label=f"elastic sphere, Mindlin-Deresiewicz (Maw et al.){nu}")
    ax.plot(pts["psi"], pts[key], "o", color="C0", label="3D FE")
    if key == "normalised_spin":  # one legend (the panels share their lines), out of the way
        ax.legend(fontsize=8, loc="lower right")
    ax.axhline(0.0, color="0.8", lw=0.6)
    ax.set(xlabel=_PSI_LABEL, ylabel=dict(GRIPPING_PANELS)[key], xlim=(0.0, top))
    ax.axvline(2.0 * (1.0 + k2) / k2, color="0.6", lw=0.8, ls="--")
    ax.grid(alpha=0.3)
    return ax


def plot_gripping(results, path, reference=None, title: str = "", *,
                  k2: float = HOMOGENEOUS_K2, poissons_ratio: float | None = None) -> None:
    """Write `draw_gripping` of each of the three `GRIPPING_PANELS` side by side: normalised
    spin Omega, tangential COR of the centre e_t and contact-point COR e_cp against Psi."""
    from ..plotting import subplots

    fig, axes = subplots(1, 3, figsize=(15, 4.2))
    for ax, (key, _) in zip(axes, GRIPPING_PANELS):
        draw_gripping(ax, results, key, reference, k2=k2, poissons_ratio=poissons_ratio)
    _save(fig, path, title)
