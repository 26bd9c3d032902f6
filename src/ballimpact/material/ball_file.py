"""A ball file from fitted materials (`ballimpact material ball`): the materials that
`material fit --out` writes, one per layer from the centre out, plus the ball's diameter and
mass (and the layers' outer radii and densities), as the ball specification `fe.load_ball`
reads (docs/balls.md). Nobody writes ball JSON by hand.

Densities: one layer gets mass / volume; several layers take their densities
(`densities_kg_m3`), of which one may be None ('auto' on the command line) and is then solved
from the mass; with every density given, a mass is only checked (to `MASS_TOLERANCE`).
Errors are `InputError`s that name the argument and its command-line flag.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..checks import check_positive
from ..fileio import check_distinct_files, check_output_folder, write_atomic
from ..balls.checks import BALL_RANGES, ball_unit_slip, check_ball_diameter, check_ball_mass
from .files import read_material, read_prony_terms

#: largest relative difference between a given mass and the one the densities give
MASS_TOLERANCE = 0.01


def _shell_volume_m3(inner_m: float, outer_m: float) -> float:
    return 4.0 / 3.0 * math.pi * (outer_m ** 3 - inner_m ** 3)


def _layer_radii(layer_radii_m: Sequence[float] | None, n: int, outer_m: float) -> list[float]:
    """The outer radius of each layer: `layer_radii_m` lists the inner layers' (n - 1 values)
    or all n (the last equal to the ball's radius)."""
    what = "layer_radii_m (--layer-radii-m)"
    if layer_radii_m is None:
        if n > 1:
            raise InputError(f"{what}: {n} materials make {n} layers; give the outer radii of "
                             f"the inner {n - 1} (m, from the centre out; the last layer ends at "
                             f"the ball's radius {outer_m:g} m)")
        return [outer_m]
    radii = [check_positive(what, r) for r in layer_radii_m]
    if len(radii) == n and math.isclose(radii[-1], outer_m, rel_tol=1e-9):
        radii = radii[:-1]
    if len(radii) != n - 1:
        raise InputError(f"{what}: {len(layer_radii_m)} radii for {n} layers; give the outer "
                         f"radii of the inner {n - 1} (m, from the centre out)")
    radii.append(outer_m)
    for i in range(1, n):
        if not radii[i] > radii[i - 1]:
            inner = i - 1
            mm = (radii[inner] > outer_m and ball_unit_slip("outer radius", radii[inner]))
            hint = (f": it looks like millimetres (use {radii[inner] * 1e-3:g})" if mm else
                    f": the radii must increase from the centre out and stay below the ball's "
                    f"radius {outer_m:g} m (--diameter-m / 2)")
            raise InputError(f"{what}: layer {inner} ends at {radii[inner]:g} m, layer {i} at "
                             f"{radii[i]:g} m{hint}")
    return radii


def _densities(densities_kg_m3: Sequence[float | None] | None, mass_kg: float | None,
               volumes: list[float]) -> list[float]:
    what = "densities_kg_m3 (--densities-kg-m3)"
    n = len(volumes)
    if densities_kg_m3 is None:
        if n > 1:
            raise InputError(f"{what}: {n} layers need a density each (kg/m^3, from the centre "
                             "out); one of them may be 'auto', solved from --mass-kg")
        densities_kg_m3 = [None]
    if len(densities_kg_m3) != n:
        raise InputError(f"{what}: {len(densities_kg_m3)} values for {n} layers (one each, from "
                         "the centre out; one may be 'auto')")
    given = [None if d is None else check_positive(what, d) for d in densities_kg_m3]
    auto = [i for i, d in enumerate(given) if d is None]
    if len(auto) > 1:
        raise InputError(f"{what}: {len(auto)} layers are 'auto'; at most one density can be "
                         "solved from the mass")
    low, high, unit = BALL_RANGES["density"]
    for i, d in enumerate(given):
        if d is not None and not low <= d <= high:
            slip = ball_unit_slip("density", d)
            hint = f": it looks like {slip[1]} (use {d * slip[0]:g})" if slip else ""
            raise InputError(f"{what}: layer {i}'s {d:g} {unit} is outside {low:g}..{high:g} "
                             f"{unit}, the densities of solid sports balls{hint}")
    if auto:
        if mass_kg is None:
            raise InputError(f"mass_kg (--mass-kg): needed to solve the 'auto' density of layer "
                             f"{auto[0]}")
        i = auto[0]
        rest = sum(d * v for d, v in zip(given, volumes) if d is not None)
        density = (mass_kg - rest) / volumes[i]
        if not low <= density <= high:
            others = f" (the other layers weigh {rest:g} kg)" if n > 1 else ""
            raise InputError(f"mass_kg (--mass-kg) = {mass_kg:g} kg in {volumes[i]:.4g} m^3 "
                             f"makes layer {i}'s density {density:.4g} {unit}, outside "
                             f"{low:g}..{high:g} {unit}{others}: check --mass-kg (kg) and "
                             "--diameter-m (m)")
        given[i] = density
    elif mass_kg is not None:
        total = sum(d * v for d, v in zip(given, volumes))
        if abs(total - mass_kg) > MASS_TOLERANCE * mass_kg:
            raise InputError(f"mass_kg (--mass-kg) = {mass_kg:g} kg, but the densities give "
                             f"{total:.5g} kg ({(total / mass_kg - 1) * 100:+.1f}%, allowed "
                             f"{MASS_TOLERANCE * 100:g}%): correct one, or give one density as "
                             "'auto'")
    return given  # type: ignore[return-value]


def ball_from_materials(materials: Sequence[dict], diameter_m: float, *,
                        mass_kg: float | None = None,
                        layer_radii_m: Sequence[float] | None = None,
                        densities_kg_m3: Sequence[float | None] | None = None,
                        names: Sequence[str] | None = None, name: str = "ball",
                        description: str = "", source: str = "") -> dict[str, Any]:
    """The ball specification (a dict for `fe.load_ball`, checked by it) of layers made of
    `materials` (material objects, as `material fit --out` writes them), from the centre out.

    `diameter_m`: the ball's outer diameter (m). `layer_radii_m`: the outer radii of the inner
    layers (n - 1 values, or n with the last the ball's radius). `mass_kg`: the ball's mass
    (kg): one layer's density is mass / volume; with `densities_kg_m3` (one per layer, None
    for the one to solve from the mass) it fills that layer, or, all given, is checked to
    `MASS_TOLERANCE`. `names`: the layers' names (default core, layer1, ...; one layer: ball).
    """
    from ..fe import load_ball

    n = len(materials)
    if n == 0:
        raise InputError("materials: at least one material (one per layer)")
    diameter_m = check_ball_diameter(diameter_m, "diameter_m (--diameter-m)")
    if mass_kg is not None:
        mass_kg = check_ball_mass(mass_kg, "mass_kg (--mass-kg)")
    elif densities_kg_m3 is None or any(d is None for d in densities_kg_m3):
        raise InputError("mass_kg (--mass-kg): needed (kg) unless every layer's density is "
                         "given (--densities-kg-m3)")
    radii = _layer_radii(layer_radii_m, n, diameter_m / 2.0)
    inner = [0.0, *radii[:-1]]
    volumes = [_shell_volume_m3(r0, r1) for r0, r1 in zip(inner, radii)]
    densities = _densities(densities_kg_m3, mass_kg, volumes)
    if names is None:
        names = ["ball"] if n == 1 else ["core", *(f"layer{i}" for i in range(1, n))]
    names = list(names)
    if len(names) != n or len(set(names)) != n or not all(
            isinstance(x, str) and x.strip() for x in names):
        raise InputError(f"names (--layer-names) = {','.join(map(str, names))}: {n} distinct, "
                         "non-empty names, one per layer")
    spec: dict[str, Any] = {"name": name}
    if description:
        spec["description"] = description
    if source:
        spec["source"] = source
    spec["layers"] = [{"name": layer_name, "outer_radius_m": r, "density_kg_m3": rho,
                       "material": dict(material)}
                      for layer_name, r, rho, material in zip(names, radii, densities, materials)]
    load_ball(spec)  # every check a ball file gets: materials, radii, plausibility
    return spec


def _with_prony(materials: list[dict], names: list[str], layer: str | None,
                file: str | Path) -> None:
    """The Prony terms of `file` into the material of `layer` (None: the only layer), for
    --prony [LAYER=]FILE."""
    from ..constitutive import material_from_dict

    text = str(file) if layer is None else f"{layer}={file}"
    if layer is None:
        if len(names) != 1:
            raise InputError(f"--prony {text}: {len(names)} layers; name the layer as LAYER=FILE "
                             f"(layers: {', '.join(names)})")
        layer = names[0]
    elif layer not in names:
        raise InputError(f"--prony {text}: no layer {layer!r}; layers: {', '.join(names)}")
    terms = read_prony_terms(Path(file))
    i = names.index(layer)
    merged = {**materials[i], "prony": [
        {key: term.get(key) for key in ("g", "k", "tau_s") if key in term} for term in terms]}
    material_from_dict(merged, f"--prony {text}")
    materials[i] = merged


def write_ball(out: Path, material_files: Sequence[Path], diameter_m: float, *,
               mass_kg: float | None = None, layer_radii_m: Sequence[float] | None = None,
               densities_kg_m3: Sequence[float | None] | None = None,
               layer_names: Sequence[str] | None = None,
               prony: Sequence[tuple[str | None, str | Path]] = (),
               name: str | None = None) -> dict[str, Any]:
    """Write to `out` (.json) the ball file (`ball_from_materials`) of the material files
    `material_files` (`material fit --out`, or its JSON), one per layer from the centre out,
    named `layer_names` (default the files' stems); `prony`: (layer name or None for the only
    layer, file) pairs whose Prony terms (`files.read_prony_terms`) go into that layer's
    material; `name`: the ball's (default the file's stem). Returns the JSON of `material
    ball`: the ball's name, diameter and mass, and each layer's radius, density, mass, model and
    number of Prony terms."""
    from ..fe import load_ball

    out = Path(out)
    check_output_folder(out, "--out")
    if out.suffix.lower() != ".json":
        raise InputError(f"--out {out}: a ball file ends in .json")
    files = [Path(path) for path in material_files]
    check_distinct_files(files, "MATERIAL_JSON")
    materials = [read_material(path) for path in files]
    names = list(layer_names) if layer_names is not None else [path.stem for path in files]
    if len(set(names)) != len(names) and layer_names is None:
        raise InputError(f"MATERIAL_JSON: two files named {names[0]!r}; give --layer-names")
    for layer, file in prony:
        _with_prony(materials, names, layer, file)
    spec = ball_from_materials(
        materials, diameter_m, mass_kg=mass_kg, layer_radii_m=layer_radii_m,
        densities_kg_m3=densities_kg_m3, names=names, name=name or out.stem,
        source="ballimpact material ball " + " ".join(path.name for path in files))
    write_atomic(out, json.dumps(spec, indent=2) + "\n")
    ball = load_ball(spec)
    return {"name": ball.name, "out": str(out), "diameter_m": 2 * ball.outer_radius_m,
            "mass_kg": ball.mass_kg,
            "layers": [{"name": layer.name, "outer_radius_m": layer.outer_radius_m,
                        "density_kg_m3": layer.density_kg_m3, "mass_kg": mass,
                        "model": layer.material.model, "prony_terms": len(layer.material.prony)}
                       for layer, mass in zip(ball.layers, ball.layer_masses_kg)]}


__all__ = ["MASS_TOLERANCE", "ball_from_materials", "write_ball"]
