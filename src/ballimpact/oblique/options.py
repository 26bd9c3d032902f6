"""Settings of the 3D solver (SI), validated on construction; the impact condition and the
settings both engines share are `fe.options`'."""

from __future__ import annotations

from dataclasses import dataclass

from ..checks import check_range, shown
from ..errors import InputError
from ..fe.options import ExplicitOptions, ImpactCondition, check_count
from ..fe.hex.mesh import GRADING_RANGE

__all__ = ["ImpactCondition", "Options3D"]


@dataclass(frozen=True)
class Options3D(ExplicitOptions):
    """Settings of the 3D engine (SI): the shared ones (`fe.options.ExplicitOptions`) and its
    mesh's, friction's, targets' and output's.

    - `divisions`: elements along each edge of the O-grid's cube (90 degrees of arc); even.
    - `pole_grading`: largest over smallest arc spacing (finer toward the contact pole).
    - `half`: a half model on the plane of incidence (symmetric: no out-of-plane spin). None:
      half when every condition allows it, the full model otherwise.
    - `contact_elements`: when set, the pole grading is chosen for the impact so that this many
      elements span the Hertz contact radius expected at the smallest normal speed of a run
      (`oblique.contact_grading`; `pole_grading` is then ignored).
    - `stick_scale`: stick-spring stiffness of friction over the normal penalty stiffness.
    - `slab_depth_growth`: a target slab's cells. None: through the depth uniform, 4 pole
      spacings thick (in plane graded toward the centre, see `solver._slab_layout`). A growth
      factor in (1, 2]: a slab matched to the contact: cells of the ball's pole spacing at the
      centre of its surface, growing in plane as the ball's cells grow from its pole (at least
      1.15 a cell) and by this factor a cell down to at most 4 pole spacings; it resolves a small contact's stresses in the slab (a light
      foam's finer surface cells may chatter against the ball).
    - `frames`: keep the displacements every this many chunks for VTK output and animation
      (0: none).
    """

    divisions: int = 16
    pole_grading: float = 2.0
    contact_elements: float | None = None
    half: bool | None = None
    stick_scale: float = 8.0
    slab_depth_growth: float | None = None
    frames: int = 0

    def __post_init__(self) -> None:
        if not (isinstance(self.divisions, int) and self.divisions >= 4
                and self.divisions % 2 == 0 and self.divisions <= 64):
            raise InputError(f"divisions = {shown(self.divisions)}: must be an even integer in [4, 64]")
        check_range("pole_grading", self.pole_grading, *GRADING_RANGE)
        if self.contact_elements is not None:
            check_range("contact_elements", self.contact_elements, 0.5, 50.0)
        check_range("stick_scale", self.stick_scale, 0.0, 100.0, low_open=True)
        if self.slab_depth_growth is not None:
            check_range("slab_depth_growth", self.slab_depth_growth, 1.0, 2.0, low_open=True)
        check_count("frames", self.frames, 0)
        super().__post_init__()
