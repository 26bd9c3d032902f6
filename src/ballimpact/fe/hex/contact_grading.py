"""Mesh grading to the contact: the pole grading that puts a given number of elements across the
Hertz contact radius expected for an impact, and the 3D engine's defaults chosen from it
(`contact_settings`: `Options3D` with `pole_grading` and `penalty_scale` left None).

The contact radius is `fe.estimates.hertz_contact_radius_m`'s: Hertz's on a rigid plane at the
impact's normal speed, with the softest layer's long-term plane-strain modulus (exact for a
homogeneous elastic ball; the widest patch of a layered or viscoelastic one, and a target
widens it further, so the mesh is then at least as fine as asked).
"""

from __future__ import annotations

from dataclasses import replace

from ...errors import InputError
from ..estimates import hertz_contact_radius_m
from .mesh import GRADING_RANGE, pole_spacing_m

#: The default mesh's pole grading, kept where the contact spans enough elements with it ...
DEFAULT_POLE_GRADING = 2.0
#: ... else the grading that puts this many elements across the Hertz radius (docs/oblique.md,
#: "The gripping regime": 2 elements let the contact point reverse too little, 2.9 to 4.3 agree).
DEFAULT_CONTACT_ELEMENTS = 3.0
#: A contact spanned by fewer elements than this gets the penalty `SMALL_CONTACT_PENALTY_SCALE`
#: times the default (the balance of the penalty's softness and the coarse mesh's stiff stick
#: measured at 2.9 elements across); a ball impact's wider contact (4 to 10 elements at 5-40 m/s
#: on the default mesh) keeps the default penalty, with which the 3D engine was checked against
#: the axisymmetric one, Hertz and the rigid-body limits.
SMALL_CONTACT_ELEMENTS = 4.0
SMALL_CONTACT_PENALTY_SCALE = 3.0


def grading_for_contact(ball, normal_speed_m_s: float, divisions: int,
                        elements: float) -> tuple[float, float]:
    """(pole grading, contact radius m): the grading in `mesh.GRADING_RANGE` whose pole spacing puts
    `elements` elements across the Hertz radius (the smallest grading that does; 1 if the
    uniform mesh already does). Raises `InputError` when `divisions` cannot reach it at the
    largest grading, naming the divisions that would."""
    a = hertz_contact_radius_m(ball, normal_speed_m_s)
    wanted = a / elements
    grading = grading_for_spacing(ball.outer_radius_m, divisions, wanted)
    if grading is None:
        high = GRADING_RANGE[1]
        needed = divisions
        while needed < 64 and pole_spacing_m(ball.outer_radius_m, needed, high) > wanted:
            needed += 2
        raise InputError(
            f"contact_elements = {elements:g}: the Hertz contact radius {a * 1e3:.3g} mm needs "
            f"a pole spacing of {wanted * 1e3:.3g} mm; {divisions} divisions reach "
            f"{pole_spacing_m(ball.outer_radius_m, divisions, high) * 1e3:.3g} mm at the largest "
            f"grading {high:g} (use divisions >= {needed} or fewer contact elements)")
    return grading, a


def grading_for_spacing(outer_radius_m: float, divisions: int, spacing_m: float) -> float | None:
    """The smallest pole grading in `mesh.GRADING_RANGE` whose pole spacing on a ball of
    `outer_radius_m` (m) is at most `spacing_m` (m) (1 if the uniform mesh's is); None when the
    largest grading cannot reach it with `divisions`."""
    low, high = GRADING_RANGE
    if pole_spacing_m(outer_radius_m, divisions, low) <= spacing_m:
        return low
    if pole_spacing_m(outer_radius_m, divisions, high) > spacing_m:
        return None
    for _ in range(60):  # bisection: the pole spacing falls as the grading grows
        mid = 0.5 * (low + high)
        low, high = (mid, high) if pole_spacing_m(outer_radius_m, divisions, mid) > spacing_m \
            else (low, mid)
    return high


def contact_settings(ball, normal_speed_m_s: float, options):
    """`options` (`Options3D`) with the settings it leaves to the contact made numbers, for the
    Hertz radius a at `normal_speed_m_s` (m/s; a batch's slowest):

    - `contact_elements` given: the grading that puts that many elements across a;
    - `pole_grading` None: `DEFAULT_POLE_GRADING`, or finer until `DEFAULT_CONTACT_ELEMENTS`
      elements span a (at most the largest grading: a contact the divisions cannot resolve is
      warned about by the engine, `fe.engine.contact_resolution_note`);
    - `penalty_scale` None: `SMALL_CONTACT_PENALTY_SCALE` when fewer than
      `SMALL_CONTACT_ELEMENTS` elements of the mesh so chosen span a, 1 otherwise."""
    grading = options.pole_grading
    if options.contact_elements is not None:
        grading, _ = grading_for_contact(ball, normal_speed_m_s, options.divisions,
                                         options.contact_elements)
    elif grading is None:
        grading = DEFAULT_POLE_GRADING
        try:
            grading = max(grading, grading_for_contact(ball, normal_speed_m_s, options.divisions,
                                                       DEFAULT_CONTACT_ELEMENTS)[0])
        except InputError:  # the divisions cannot reach it: the finest pole they can
            grading = GRADING_RANGE[1]
    penalty = options.penalty_scale
    if penalty is None:
        across = (hertz_contact_radius_m(ball, normal_speed_m_s)
                  / pole_spacing_m(ball.outer_radius_m, options.divisions, grading))
        penalty = SMALL_CONTACT_PENALTY_SCALE if across < SMALL_CONTACT_ELEMENTS else 1.0
    return replace(options, pole_grading=grading, penalty_scale=penalty, contact_elements=None)


def without_contact(options):
    """`options` (`Options3D`) with what `contact_settings` leaves to the contact set where no
    impact is known (a mesh built or estimated on its own, an exported deck): grading
    `DEFAULT_POLE_GRADING`, penalty 1. Settings already chosen are kept."""
    if options.pole_grading is not None and options.penalty_scale is not None:
        return options  # already chosen (the hot path: every parameter build)
    return replace(options, pole_grading=options.pole_grading or DEFAULT_POLE_GRADING,
                   penalty_scale=options.penalty_scale or 1.0)
