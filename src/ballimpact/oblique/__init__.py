"""3D explicit FE of oblique impacts (thesis 5.2.4 and chapter 8): a layered hexahedral ball with
Coulomb friction and spin on a rigid plane or a deformable slab, with XDMF output and animations.
The runs are `fe.simulate(..., geometry=fe.Hexahedral(options))` (the engine's 3D geometry); this
package holds the oblique-impact science: rigid-body limits, the elastic-sphere reference, angle
sweeps, output and plots. The axisymmetric geometry stays the workhorse for normal impacts; the
two agree there."""

from .options import ImpactCondition, Options3D
from .rigid_body import rigid_oblique_impact
from .solver import ObliqueResult, estimate_oblique, simulate_oblique, simulate_oblique_batch
from ..fe.hex.target import Backing, Target, load_target

__all__ = ["Backing", "ImpactCondition", "ObliqueResult", "Options3D", "Target", "estimate_oblique",
           "load_target", "rigid_oblique_impact", "simulate_oblique", "simulate_oblique_batch"]
