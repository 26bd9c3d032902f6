"""Rigid-body oblique impact of a sphere on a flat surface with Coulomb friction (closed form),
the reference for the 3D solver's oblique results.

Normal impulse P_n = m (1 + e_n) v_n. The tangential impulse that stops the contact point's slip
s = v_x - w R is P_stop = m s k^2 / (1 + k^2) (k^2 = I / (m R^2), 0.4 for a homogeneous sphere):
if mu P_n >= |P_stop| the ball leaves rolling (P = P_stop; Daish: v_x' = (5 v_x + 2 R w) / 7 for
k^2 = 0.4 with this file's spin sign), otherwise it slides throughout (P = mu P_n sign(s)). Spin is
positive for topspin (`ImpactCondition`): a ball rolling at v_x spins at v_x / R.

Normalised axes (Maw, Barber & Fawcett 1976; the Chung & Ooi 2011 benchmark tests 4-6):
incidence Psi = 2 tan(theta) / (mu (1 + e_n)) with tan(theta) = s / v_n, and rebound spin
Omega = w' R / (mu (1 + e_n) v_n): Omega = 1 / k^2 (2.5) in gross sliding (Psi >= 2 (1 + k^2) / k^2
= 7), Omega = Psi / (2 (1 + k^2)) when the ball leaves rolling.
"""

from __future__ import annotations

import numpy as np

HOMOGENEOUS_K2 = 0.4


def rigid_oblique_impact(v_x, v_n, spin_rad_s, radius_m, friction, normal_cor,
                         k2: float = HOMOGENEOUS_K2) -> dict[str, np.ndarray]:
    """Rebound of a rigid sphere: v_x' (m/s), v_n' (m/s, away from the surface), spin' (rad/s)
    and whether it left rolling. `v_n` > 0 is the approach speed along the normal."""
    v_x, v_n, w = (np.asarray(x, float) for x in (v_x, v_n, spin_rad_s))
    slip = v_x - w * radius_m
    p_stop = slip * k2 / (1.0 + k2)                # per unit mass
    p_limit = friction * (1.0 + normal_cor) * v_n
    rolling = np.abs(p_stop) <= p_limit
    p = np.where(rolling, p_stop, np.sign(slip) * p_limit)
    return {"v_x_m_s": v_x - p, "v_n_m_s": normal_cor * v_n,
            "spin_rad_s": w + p / (k2 * radius_m), "rolling": rolling}


def normalised_incidence(v_x, v_n, spin_rad_s, radius_m, friction, normal_cor):
    """Psi = 2 (v_x - w R) / (mu (1 + e_n) v_n)."""
    return 2.0 * (np.asarray(v_x) - np.asarray(spin_rad_s) * radius_m) / (
        friction * (1.0 + normal_cor) * np.asarray(v_n))


def normalised_spin(spin_rad_s, radius_m, friction, normal_cor, v_n):
    """Omega = w' R / (mu (1 + e_n) v_n)."""
    return np.asarray(spin_rad_s) * radius_m / (friction * (1.0 + normal_cor) * np.asarray(v_n))


def rigid_lines(psi, k2: float = HOMOGENEOUS_K2) -> tuple[np.ndarray, np.ndarray]:
    """Rigid-body normalised spin and normalised tangential velocity change
    (v_x - v_x') / (mu (1 + e_n) v_n) against Psi (no initial spin)."""
    psi = np.asarray(psi, float)
    transition = 2.0 * (1.0 + k2) / k2
    spin = np.where(psi >= transition, 1.0 / k2, psi / (2.0 * (1.0 + k2)))
    dv = np.where(psi >= transition, 1.0, psi * k2 / (2.0 * (1.0 + k2)))
    return spin, dv
