"""Plots of 3D oblique impacts: histories of one run, and a sweep of incidence against the
rigid-body lines."""

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


def plot_sweep(results, path, title: str = "") -> None:
    """Normalised rebound spin and tangential velocity change against normalised incidence,
    with the rigid-body lines (k^2 = 0.4)."""
    plt = _pyplot()
    pts = sweep_points(results)
    psi_line = np.linspace(0, max(12.0, 1.1 * pts["psi"].max()), 300)
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
    for ax in axes:
        ax.axvline(7.0, color="0.6", lw=0.8, ls="--")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
