"""Explicit finite-element ball models (thesis chapters 5 and 6): layered hyper-viscoelastic
balls and one explicit engine (`engine`) whose geometry is a plug-in: axisymmetric
(`Axisymmetric`, normal impacts on a rigid plane) or hexahedral 3D (`Hexahedral`, oblique and
spinning impacts with friction, on a rigid plane or a slab).

The names below are imported when first used (PEP 562): importing a light module of the package
(`fe.sweep`, `fe.speed_range`) does not load JAX, which the command line's start-up needs."""

from __future__ import annotations

import importlib

#: name -> the module that defines it
_WHERE = {
    **dict.fromkeys(("PRESETS", "BallModel", "Layer", "describe_presets", "load_ball",
                     "universal_parameters"), "ballimpact.balls"),
    **dict.fromkeys(("CompressionResult", "compress"), "ballimpact.fe.compression"),
    **dict.fromkeys(("Axisymmetric", "Hexahedral", "estimate", "simulate", "simulate_batch"),
                    "ballimpact.fe.engine"),
    **dict.fromkeys(("ExplicitOptions", "ImpactCondition", "Options3D", "SolverOptions"),
                    "ballimpact.fe.options"),
    "RunProgress": "ballimpact.fe.progress",
    **dict.fromkeys(("FailedRun", "ImpactResult"), "ballimpact.fe.result"),
    **dict.fromkeys(("FEResult", "estimate_run"), "ballimpact.fe.solver"),  # one release
}

__all__ = sorted(_WHERE)


def __getattr__(name: str):
    if name in _WHERE:
        value = getattr(importlib.import_module(_WHERE[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'ballimpact.fe' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_WHERE))
