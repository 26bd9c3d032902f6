"""Plots of 3D oblique impacts: histories of one run, and a sweep of incidence against the
rigid-body lines (and, in the gripping regime, the elastic-sphere reference)."""

from __future__ import annotations

import numpy as np

from .rigid_body import (HOMOGENEOUS_K2, normalised_incidence, normalised_spin, rigid_lines)


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_oblique(results, path) -> None:
    """Normal and tangential contact force, spin and contact-point slip velocity against time,
    and the energy account, for one or more runs."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    for r in results:
        h = r.history
        t = h["time_s"] * 1e3
        c = r.condition
        label = f"{c.speed_m_s:g} m/s, {c.angle_deg:g} deg, mu {c.friction:g}"
        line, = axes[0].plot(t, h["normal_force_n"] / 1e3, label=f"normal ({label})")
        axes[0].plot(t, h["tangential_force_x_n"] / 1e3, "--", color=line.get_color(),
                     label="tangential")
        axes[1].plot(t, h["spin_y_rad_s"], color=line.get_color(), label=f"spin ({label})")
        ax2 = axes[1].twinx() if len(results) == 1 else None
        if ax2 is not None:
            ax2.plot(t, h["contact_slip_velocity_m_s"], ":", color="C3")
            ax2.set_ylabel("contact-point slip velocity (m/s)", color="C3")
        for name, style in (("kinetic_energy_j", "-"), ("viscous_dissipation_j", "--"),
                            ("frictional_dissipation_j", ":"), ("strain_energy_j", "-.")):
            axes[2].plot(t, h[name], style, label=name.replace("_j", "").replace("_", " ")
                         if r is results[0] else None, color=line.get_color())
    axes[0].set(xlabel="time (ms)", ylabel="contact force (kN)")
    axes[1].set(xlabel="time (ms)", ylabel="spin about y (rad/s, + topspin)")
    axes[2].set(xlabel="time (ms)", ylabel="energy (J)")
    for ax in axes:
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


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


def _finish(fig, axes, path, title: str, transition: float, legends=None) -> None:
    """The rigid-body transition (dashed), legends (on `legends`, default every panel), grids,
    the title; saved and closed."""
    for ax in axes:
        ax.axvline(transition, color="0.6", lw=0.8, ls="--")
        if legends is None or ax in legends:
            ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    _pyplot().close(fig)


def plot_sweep(results, path, title: str = "") -> None:
    """Normalised rebound spin and tangential velocity change against normalised incidence,
    with the rigid-body lines (k^2 = 0.4)."""
    plt = _pyplot()
    pts = sweep_points(results)
    psi_line = np.linspace(0, _psi_top(pts["psi"]), 300)
    spin_line, dv_line = rigid_lines(psi_line, HOMOGENEOUS_K2)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    axes[0].plot(psi_line, spin_line, "k-", label="rigid body (rolling, then sliding)")
    axes[0].plot(pts["psi"], pts["spin"], "o", label="3D FE")
    axes[0].set(xlabel="normalised incidence 2 tan(theta) / (mu (1 + e_n))",
                ylabel="normalised spin w' R / (mu (1 + e_n) v_n)")
    axes[1].plot(psi_line, dv_line, "k-", label="rigid body")
    axes[1].plot(pts["psi"], pts["tangential_change"], "o", label="3D FE")
    axes[1].set(xlabel="normalised incidence 2 tan(theta) / (mu (1 + e_n))",
                ylabel="(v_x - v_x') / (mu (1 + e_n) v_n)")
    # the rigid transition Psi = 2 (1 + k^2) / k^2 is 7 at k^2 = 0.4
    _finish(fig, axes, path, title, 7.0)


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


def plot_gripping(results, path, reference=None, title: str = "", *,
                  k2: float = HOMOGENEOUS_K2, poissons_ratio: float | None = None) -> None:
    """Normalised spin Omega, tangential COR of the centre e_t and contact-point COR e_cp against
    the normalised incidence Psi (Maw, Barber & Fawcett's axes), three panels: the FE runs
    (without initial spin; each normalised with its own e_n), the rigid-body lines for `k2`
    (rolling, then sliding; dashed at the transition Psi = 2 (1 + k^2) / k^2) and, when given,
    the elastic-sphere reference `reference` (the dict of `elastic_reference.normalised_curves`,
    labelled with `poissons_ratio`)."""
    plt = _pyplot()
    pts = gripping_points(results)
    top = _psi_top(pts["psi"])
    if reference is not None:  # the whole reference shown (the CLI's grid ends at this top)
        top = max(top, float(np.nanmax(reference["psi"])))
    psi_line = np.linspace(0.02, top, 400)  # e_t and e_cp are 0/0 at Psi = 0
    rigid = rigid_gripping_lines(psi_line, k2)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    nu = "" if poissons_ratio is None else f", nu = {poissons_ratio:.3g}"
    for ax, (key, ylabel) in zip(axes, GRIPPING_PANELS):
        ax.plot(psi_line, rigid[key], "k-", lw=1.2,
                label=f"rigid body (rolling, then sliding; k^2 = {k2:.3g})")
        if reference is not None:
            ax.plot(reference["psi"], reference[key], "-", color="C1", lw=1.5,
                    label=f"elastic sphere, Mindlin-Deresiewicz (Maw et al.){nu}")
        ax.plot(pts["psi"], pts[key], "o", color="C0", label="3D FE")
        if key == "normalised_spin":  # one legend (the panels share their lines), out of the way
            ax.legend(fontsize=8, loc="lower right")
        ax.axhline(0.0, color="0.8", lw=0.6)
        ax.set(xlabel=_PSI_LABEL, ylabel=ylabel, xlim=(0.0, top))
    _finish(fig, axes, path, title, 2.0 * (1.0 + k2) / k2, legends=())
