"""Ball models: a layered ball's specification (`BallModel`, `Layer`), the presets and
`load_ball` (a preset name, a JSON/TOML file or a dict) in `ball`; the `ball-units` check in
`checks`. Every stage that takes a ball (the FE engine, export, the universal model, standards,
calibration) takes one of these.

The names below are imported when first used (PEP 562): the materials behind `ball` load JAX,
which `checks` alone (and the command line's start-up) does not need."""

from __future__ import annotations

import importlib

__all__ = ["PRESETS", "BallModel", "Layer", "describe_presets", "load_ball",
           "universal_parameters"]


def __getattr__(name: str):
    if name in __all__:
        value = getattr(importlib.import_module("ballimpact.balls.ball"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'ballimpact.balls' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
