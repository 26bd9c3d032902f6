"""Drucker-stable stretch ranges of a fitted (or given) material per deformation mode, and the
unstable intervals that fall inside the stretches a test (or an impact) reaches. A thin layer
over `fe.materials.stability`, which checks the material's own energy."""

from __future__ import annotations

from typing import Any

from ..fe.materials import Material
from ..fe.materials.stability import MODES, checked, drucker_unstable, stable_range


def stable_ranges(material: Material) -> dict[str, tuple[float, float]]:
    """mode -> (low, high), the Drucker-stable interval containing stretch 1 within 0.05..20;
    empty for a material that is not checked (linear elastic)."""
    if not checked(material):
        return {}
    return {mode: stable_range(material, mode) for mode in MODES}


def unstable_within(material: Material, ranges: dict[str, tuple[float, float]]
                    ) -> list[dict[str, Any]]:
    """The unstable intervals of each mode inside the stretch range given for it, as
    {"mode", "stretch_from", "stretch_to", "data_from", "data_to"}."""
    if not checked(material):
        return []
    out = []
    for mode, (lo, hi) in ranges.items():
        if not hi > lo:
            continue
        out += [{**r, "data_from": lo, "data_to": hi}
                for r in drucker_unstable(material, lo, hi, modes=(mode,))]
    return out


__all__ = ["stable_ranges", "unstable_within"]
