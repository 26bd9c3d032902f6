"""Kelvin-Voigt model: a linear spring and dashpot, F = k y + c y' (thesis 2.4, eq. 2-13..2-22).

Its closed-form solution is `ballimpact.records.pulses.KelvinVoigt`. The ball leaves when the force
returns to zero, t_c = [pi - atan2(2 b w, w0^2 - 2 b^2)] / w, which comes before the displacement
does (t_c = pi / w, the separation of the classic solution and of the thesis, with a tensile force
just before it). `kelvin_voigt_from_test` inverts either convention: k and c from the contact time
and the impact and rebound speeds.
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
from scipy.optimize import brentq

from ..checks import check_positive, check_range
from ..errors import InputError
from .base import Parameter
from .engine import OdeModel
from .single_element import force as single_element_force


def force(q, state):
    return single_element_force(jnp.stack([q[0], 1.0, q[1]]), state)


def split(p, mass):
    return p[None, :], jnp.atleast_1d(mass)


def bounds(scale):
    return {"k": scale.stiffness_force_bounds_n,
            "c": (0.0, 1.5 * scale.force_per_speed_n_s_m)}


def validate(params):
    check_range("params.k", params["k"], 0.0, low_open=True)
    check_range("params.c", params["c"], 0.0)


MODEL = OdeModel(
    name="kelvin_voigt",
    summary="linear spring + dashpot, F = k y + c y' (thesis eq. 2-13)",
    parameters=(Parameter("k", "N/m", "stiffness", "stiffness", 1.0),
                Parameter("c", "N s/m", "damping coefficient")),
    bounds=bounds,
    split=split,
    force=force,
    validate=validate,
)


def kelvin_voigt_from_test(
    contact_time_s: float,
    impact_speed_m_s: float,
    rebound_speed_m_s: float,
    mass_kg: float,
    *,
    separation: str = "force",
    keep_b_squared: bool = True,
) -> dict[str, float]:
    """k (N/m) and c (N s/m) of the Kelvin-Voigt ball that reproduces a test's contact time and
    COR e = v_out / v_in. With b = -ln(e) / t_c (eq. 2-21):

    - `separation="displacement"`: the thesis' eq. 2-19..2-22, contact ending at x = 0:
      w = pi / t_c, c = 2 m b, k = m (w^2 + b^2). Eq. 2-19 as printed drops the b^2 term
      (k = m pi^2 / t_c^2); `keep_b_squared=False` reproduces it.
    - `separation="force"` (default, consistent with the `kelvin_voigt` model): contact ends when
      k x + c x' = 0, so w solves w t_c = pi - atan2(2 b w, w^2 - b^2); then c = 2 m b,
      k = m (w^2 + b^2). Needs e > exp(-2).
    """
    t = check_positive("contact_time_s", contact_time_s)
    v_in = check_positive("impact_speed_m_s", impact_speed_m_s)
    v_out = check_positive("rebound_speed_m_s", rebound_speed_m_s)
    m = check_positive("mass_kg", mass_kg)
    if v_out >= v_in:
        raise InputError(f"rebound_speed_m_s: must be below the impact speed {v_in!r}, got {v_out!r}")
    b = -np.log(v_out / v_in) / t
    if separation == "displacement":
        w = np.pi / t
        k = m * (w**2 + b**2) if keep_b_squared else m * w**2
        return {"k": float(k), "c": float(2 * m * b)}
    if separation != "force":
        raise InputError(f"separation: must be 'force' or 'displacement', got {separation!r}")
    if b * t >= 2.0:
        raise InputError(
            f"rebound_speed_m_s: a COR of {v_out / v_in:.4g} is below exp(-2) = 0.135, which no "
            "underdamped Kelvin-Voigt ball with force-based separation reaches"
        )
    residual = lambda w: w * t - np.pi + np.arctan2(2 * b * w, w**2 - b**2)  # noqa: E731
    w = brentq(residual, 1e-9 * np.pi / t, 1e3 * np.pi / t, xtol=1e-14 / t, rtol=1e-15)
    return {"k": float(m * (w**2 + b**2)), "c": float(2 * m * b)}
