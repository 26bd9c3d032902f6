"""`ballimpact material fit|check|ball`: material tests to the constants of a ball's layer, the
Drucker-stable stretch ranges of a ball's materials, and a ball file from fitted materials
(docs/materials.md)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from ..errors import InputError
from .common import add_json, print_lines, use_compilation_cache


def add_parser(verbs) -> None:
    from ..material.fitting import FIT_MODELS

    material = verbs.add_parser(
        "material", help="fit material constants to material tests; check a ball's materials",
        description="Fit hyperelastic constants (or a Prony series) to material tests given as "
                    "FILE:MODE, or check the Drucker-stable stretch range of a ball's materials.")
    steps = material.add_subparsers(dest="step", required=True, metavar="STEP")

    fit = steps.add_parser(
        "fit", help="fit a model to material tests",
        description="Least squares on the nominal stresses of uniaxial, biaxial, planar and "
                    "volumetric tests (hyperelastic models), or a Prony series to relaxation, "
                    "creep or DMA tests (--model prony).")
    fit.add_argument("tests", nargs="+", metavar="FILE:MODE",
                     help="test CSV and its mode: uniaxial, biaxial, planar, volumetric, "
                          "relaxation, creep, dma; compression or tension: a uniaxial test of "
                          "that branch (checked)")
    fit.add_argument("--compression-positive", action="store_true",
                     help="the files' strains and nominal stresses are positive in compression "
                          "(the common lab sign): negate them (uniaxial, biaxial, planar tests; "
                          "a stretch column is kept)")
    fit.add_argument("--model", required=True, help=f"one of {', '.join(FIT_MODELS)}")
    fit.add_argument("--order", type=int, help="terms of ogden (default 3) or ogden_hyperfoam "
                                               "(default 1): 1 to 3")
    fit.add_argument("--error", default="absolute", help="absolute (Pa, default) or relative")
    fit.add_argument("--seed", type=int, default=0,
                     help="seed of the Ogden starts and the Prony fits (default 0)")
    fit.add_argument("--starts", type=int, help="starts of the Ogden exponent search (default 14)")
    fit.add_argument("--terms", type=int, help="prony: number of Prony terms")
    fit.add_argument("--shift", help="prony with DMA at several temperatures: wlf or arrhenius")
    fit.add_argument("--reference-temperature-c", type=float,
                     help="prony with DMA: reference temperature of the master curve (C)")
    fit.add_argument("--merge", type=Path, metavar="MATERIAL_JSON",
                     help="prony: a hyperelastic material file; the output is that material "
                          "with the fitted prony list")
    fit.add_argument("--bulk-relaxation", action="store_true",
                     help="prony: the bulk modulus relaxes as the shear modulus (k_i = g_i); "
                          "default k_i = 0")
    fit.add_argument("--out", type=Path, help="write the material JSON here (atomically)")
    fit.add_argument("--plot", type=Path, help="PNG: data and fit per mode")
    add_json(fit)

    ball = steps.add_parser(
        "ball", help="a ball file from fitted materials, a diameter and a mass",
        description="Write the ball specification (docs/balls.md) of layers made of the given "
                    "materials (as `material fit --out` writes them), from the centre out, with "
                    "the ball's diameter and mass: one layer's density is mass / volume; "
                    "several layers need their outer radii and densities (one may be 'auto', "
                    "solved from the mass). The file is checked as any ball file is.")
    ball.add_argument("materials", nargs="+", type=Path, metavar="MATERIAL_JSON",
                      help="material files, one per layer from the centre out (`material fit "
                           "--out`, or the JSON `material fit --json` prints)")
    ball.add_argument("--diameter-m", type=float, required=True, help="ball diameter (m)")
    ball.add_argument("--mass-kg", type=float,
                      help="ball mass (kg): sets the density of one layer (or the 'auto' one); "
                           "checked to 1%% when every density is given")
    ball.add_argument("--layer-radii-m", metavar="R1,R2,...",
                      help="outer radii of the inner layers (m, from the centre out); the last "
                           "layer ends at the ball's radius")
    ball.add_argument("--densities-kg-m3", metavar="RHO1,RHO2,...",
                      help="each layer's density (kg/m^3, from the centre out); one may be "
                           "'auto' (from --mass-kg)")
    ball.add_argument("--layer-names", metavar="NAME1,NAME2,...",
                      help="layer names (default: the material files' names)")
    ball.add_argument("--prony", action="append", default=[], metavar="[LAYER=]FILE",
                      help="Prony terms for a layer (by name; the only layer without one): the "
                           "JSON `material fit --model prony --json` prints, or a material with "
                           "a prony list; repeatable")
    ball.add_argument("--name", help="the ball's name (default: the --out file's name)")
    ball.add_argument("--out", type=Path, required=True, help="the ball file to write (.json)")
    add_json(ball)

    check = steps.add_parser(
        "check", help="Drucker-stable stretch ranges of a ball's materials",
        description="Each layer's stable stretch range per mode (uniaxial, equibiaxial, planar) "
                    "and, with a speed, whether the stretches an FE run of the ball reaches stay "
                    "inside them.")
    source = check.add_mutually_exclusive_group(required=True)
    source.add_argument("--ball", help="ball preset or file")
    source.add_argument("--material", type=Path, help="material JSON (as `material fit --out`)")
    check.add_argument("--speed-m-s", type=float, dest="speed_m_s",
                       help="impact speed (m/s): run the ball and check its stretch range")
    add_json(check)


def run(args: argparse.Namespace) -> dict[str, Any]:
    if args.step == "ball":
        return _ball(args)  # nothing compiled
    use_compilation_cache()  # the fits' stresses and `check --speed-m-s`'s run are compiled
    return {"fit": _fit, "check": _check}[args.step](args)


# ---- fit ----------------------------------------------------------------------------------------
def _fit(args: argparse.Namespace) -> dict[str, Any]:
    from ..material.fitting import fit_material_files
    from ..material.text import fit_lines

    run = fit_material_files(
        args.tests, args.model, compression_positive=args.compression_positive,
        order=args.order, error=args.error, seed=args.seed, starts=args.starts, terms=args.terms,
        shift=args.shift, reference_temperature_c=args.reference_temperature_c,
        bulk_relaxation=args.bulk_relaxation, merge=args.merge, out_path=args.out,
        plot_path=args.plot)
    if not args.json:
        print_lines(fit_lines(run))
    return run.result


# ---- ball ---------------------------------------------------------------------------------------
def _numbers(text: str | None, flag: str, auto: bool = False) -> list | None:
    """'a,b,c' -> floats (and None for 'auto' where allowed); `InputError` naming `flag`."""
    if text is None:
        return None
    values: list = []
    for item in text.split(","):
        item = item.strip()
        if auto and item.lower() == "auto":
            values.append(None)
            continue
        try:
            value = float(item)
        except ValueError:
            value = math.nan
        if not math.isfinite(value):
            raise InputError(f"{flag} {text}: {item!r} is not a finite number"
                             + (" (or 'auto')" if auto else "") + "; give comma-separated SI "
                             "values")
        values.append(value)
    return values


def _ball(args: argparse.Namespace) -> dict[str, Any]:
    from ..material.ball_file import write_ball
    from ..material.text import ball_file_lines

    prony = []
    for text in args.prony:  # [LAYER=]FILE
        layer, sep, file = text.rpartition("=")
        prony.append((layer if sep else None, file))
    out = write_ball(
        args.out, args.materials, args.diameter_m, mass_kg=args.mass_kg,
        layer_radii_m=_numbers(args.layer_radii_m, "--layer-radii-m"),
        densities_kg_m3=_numbers(args.densities_kg_m3, "--densities-kg-m3", auto=True),
        layer_names=None if args.layer_names is None else [
            n.strip() for n in args.layer_names.split(",")], prony=prony, name=args.name)
    if not args.json:
        print_lines(ball_file_lines(out, args.out))
    return out


# ---- check --------------------------------------------------------------------------------------
def _check(args: argparse.Namespace) -> dict[str, Any]:
    from ..material.stability import stability_report
    from ..material.text import stability_lines

    out = stability_report(ball=args.ball, material_file=args.material, speed_m_s=args.speed_m_s)
    if not args.json:
        print_lines(stability_lines(out))
    return out
