"""A ball on a thin foam liner over a free backing mass, in closed form: the peak force, the
liner's compression and how much the liner lowers the backing's peak acceleration against the
bare backing (docs/equipment.md, "What a liner's stiffness implies").

The liner is taken as a bed of independent columns (Winkler), each in confined compression
(`material.modes.confined_stress`; for a hyperfoam of nu = 0 the uniaxial stress as well):
under a rigid sphere of radius R pressed in by d, the column at radius r is compressed by
w = d - r^2 / (2 R), so F(d) = 2 pi R integral_0^d sigma(w / h) dw, for any nonlinear foam.
The ball's own Hertz compliance is in series (d_ball = (F / k)^(2/3), k = (4/3) E* sqrt(R)),
and the energy balance (1/2) mu v^2 = integral F d(d_liner) + (2/5) F d_ball, with the
collision's reduced mass mu, gives the peak force. Without the liner it is Hertz's impact on
the backing. Quasi-static: the liner's mass and waves are left out, and so is the columns'
coupling through shear, which makes a real layer stiffer; the columns are exact when the
contact radius is large against the thickness (against the FE liner: docs/equipment.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import cumulative_trapezoid

from ..checks import check_positive, check_range
from ..closedform import hertz_impact, hertz_stiffness
from ..errors import InputError
from ..fe.hex.target import MAX_BACKING_KG

#: the deepest compression (of the thickness) the columns are followed to
MAX_COMPRESSION = 0.98
#: points of the column's stress curve
POINTS = 6000


@dataclass(frozen=True)
class LinerImpact:
    """The closed form's figures: the peak force on the liner and on the bare backing (N),
    their ratio (the factor by which the liner lowers the backing's peak acceleration, the
    liner's mass left out), the liner's largest compression (of its thickness) and the
    contact radius then (m)."""

    peak_force_n: float
    bare_peak_force_n: float
    factor: float
    max_compression: float
    contact_radius_m: float


def liner_impact(ball_radius_m: float, ball_mass_kg: float, ball_modulus_pa: float, layer,
                 backing_mass_kg: float, speed_m_s: float) -> LinerImpact:
    """The ball (radius m, mass kg, plane-strain modulus E* = E / (1 - nu^2) in Pa; math.inf
    for a rigid ball) at `speed_m_s` on the liner `layer` (a `fe.hex.target.TargetLayer`: its
    thickness and compressible material, instantaneous constants) over a free rigid
    `backing_mass_kg`, and on the bare backing (module docstring). `InputError` when the liner
    bottoms out (the energy is not taken within `MAX_COMPRESSION` of its thickness)."""
    from ..material.modes import confined_stress

    from ..balls.checks import check_ball_diameter, check_ball_mass

    # unit slips named: a radius in mm, masses in g, a modulus in MPa
    check_ball_diameter(2.0 * ball_radius_m, "2 x ball_radius_m")
    check_ball_mass(ball_mass_kg, "ball_mass_kg")
    check_range("backing_mass_kg", backing_mass_kg, 0.0, MAX_BACKING_KG, low_open=True,
                unit="kg", note=f"above {MAX_BACKING_KG:g} it looks like grams")
    check_positive("speed_m_s", speed_m_s)
    if ball_modulus_pa != math.inf:  # math.inf: a rigid ball
        check_range("ball_modulus_pa", ball_modulus_pa, 1e4, unit="Pa",
                    note="inf: rigid; below it looks like MPa given as Pa")
    h, radius = float(layer.thickness_m), float(ball_radius_m)
    mu = ball_mass_kg * backing_mass_kg / (ball_mass_kg + backing_mass_kg)
    energy = 0.5 * mu * speed_m_s ** 2
    # geometric: a stiff liner's small compressions resolved as well as a soft one's large
    strain = np.concatenate([[0.0], np.geomspace(1e-9, MAX_COMPRESSION, POINTS)])
    stress = -confined_stress(layer.material, 1.0 - strain)  # compression positive
    d = strain * h
    force = 2.0 * math.pi * radius * cumulative_trapezoid(stress, d, initial=0.0)
    work = cumulative_trapezoid(force, d, initial=0.0)
    stiffness = float(hertz_stiffness(ball_modulus_pa, 0.0, radius))
    ball_work = 0.4 * force * (force / stiffness) ** (2.0 / 3.0)
    total = work + ball_work
    if total[-1] < energy:
        raise InputError(f"liner {layer.name!r}: bottoms out: {h * 1e3:.3g} mm of it take "
                         f"{total[-1]:.3g} J at {MAX_COMPRESSION:.0%} compression, the impact "
                         f"brings {energy:.3g} J")
    peak_d = float(np.interp(energy, total, d))
    peak = float(np.interp(peak_d, d, force))
    bare = (math.inf if math.isinf(ball_modulus_pa) else
            hertz_impact(ball_modulus_pa, 0.0, radius, mu, speed_m_s)[1])
    return LinerImpact(peak, bare, peak / bare, peak_d / h, math.sqrt(2.0 * radius * peak_d))
