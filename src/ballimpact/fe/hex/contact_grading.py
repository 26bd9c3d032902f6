"""Mesh grading to the contact: the pole grading that puts a given number of elements across the
Hertz contact radius expected for an impact.

The contact radius is `fe.estimates.hertz_contact_radius_m`'s: Hertz's on a rigid plane at the
impact's normal speed, with the softest layer's long-term plane-strain modulus (exact for a
homogeneous elastic ball; the widest patch of a layered or viscoelastic one, and a target
widens it further, so the mesh is then at least as fine as asked).
"""

from __future__ import annotations

from ...errors import InputError
from ..estimates import hertz_contact_radius_m
from .mesh import GRADING_RANGE, pole_spacing_m


def grading_for_contact(ball, normal_speed_m_s: float, divisions: int,
                        elements: float) -> tuple[float, float]:
    """(pole grading, contact radius m): the grading in `mesh.GRADING_RANGE` whose pole spacing puts
    `elements` elements across the Hertz radius (the smallest grading that does; 1 if the
    uniform mesh already does). Raises `InputError` when `divisions` cannot reach it at the
    largest grading, naming the divisions that would."""
    a = hertz_contact_radius_m(ball, normal_speed_m_s)
    wanted = a / elements
    low, high = GRADING_RANGE
    radius = ball.outer_radius_m
    if pole_spacing_m(radius, divisions, low) <= wanted:
        return low, a
    if pole_spacing_m(radius, divisions, high) > wanted:
        needed = divisions
        while needed < 64 and pole_spacing_m(radius, needed, high) > wanted:
            needed += 2
        raise InputError(
            f"contact_elements = {elements:g}: the Hertz contact radius {a * 1e3:.3g} mm needs "
            f"a pole spacing of {wanted * 1e3:.3g} mm; {divisions} divisions reach "
            f"{pole_spacing_m(radius, divisions, high) * 1e3:.3g} mm at the largest grading "
            f"{high:g} (use divisions >= {needed} or fewer contact elements)")
    for _ in range(60):  # bisection: the pole spacing falls as the grading grows
        mid = 0.5 * (low + high)
        low, high = (mid, high) if pole_spacing_m(radius, divisions, mid) > wanted else (low, mid)
    return high, a
