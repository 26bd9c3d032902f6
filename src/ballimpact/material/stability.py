"""Drucker-stable stretch ranges of a fitted (or given) material per deformation mode, and the
unstable intervals that fall inside the stretches a test (or an impact) reaches. A thin layer
over `constitutive.stability`, which checks the material's own energy."""

from __future__ import annotations

from typing import Any

from ..checks import check_range
from ..errors import InputError
from ..constitutive import Material
from ..constitutive.stability import MODES, checked, drucker_unstable, stable_range


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


def stability_report(*, ball=None, material_file=None, speed_m_s: float | None = None
                     ) -> dict[str, Any]:
    """The JSON of `material check`: each layer's stable range per mode (`stable_ranges`) of
    `ball` (a preset, a ball file or specification) or of the material in `material_file`, and,
    with `speed_m_s` (m/s, a ball only), the stretch range an FE run of the ball at that speed
    reaches and whether it stays inside each mode's range."""
    from ..fe import load_ball, simulate
    from ..constitutive import material_from_dict
    from .files import read_material

    if speed_m_s is not None and ball is None:
        raise InputError("--speed-m-s: only with --ball (a material alone is not run)")
    if speed_m_s is not None:
        check_range("--speed-m-s", speed_m_s, 0.0, low_open=True, unit="m/s",
                    note="the impact speed")
    if material_file is not None:
        material = material_from_dict(read_material(material_file), str(material_file))
        layers, name = [("material", material)], str(material_file)
    else:
        loaded = load_ball(ball, impact_speed_m_s=speed_m_s)
        layers, name = [(layer.name, layer.material) for layer in loaded.layers], loaded.name
    out: dict[str, Any] = {"name": name, "layers": []}
    stretch = None
    if speed_m_s is not None:
        stretch = simulate(loaded, speed_m_s).stretch_range
        out["speed_m_s"] = speed_m_s
        out["stretch_range"] = list(stretch)
    for layer_name, material in layers:
        ranges = stable_ranges(material)
        entry: dict[str, Any] = {"name": layer_name, "model": material.model,
                                 "checked": bool(ranges),
                                 "stable_range": {m: list(r) for m, r in ranges.items()}}
        if stretch is not None and ranges:
            entry["inside"] = {m: bool(lo <= stretch[0] and stretch[1] <= hi)
                               for m, (lo, hi) in ranges.items()}
        out["layers"].append(entry)
    if stretch is not None:
        out["stable_at_speed"] = all(all(e.get("inside", {}).values()) for e in out["layers"])
    return out


__all__ = ["stability_report", "stable_ranges", "unstable_within"]
