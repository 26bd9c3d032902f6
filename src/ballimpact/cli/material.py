"""`ballimpact material fit|check`: material tests to the constants of a ball's layer, and the
Drucker-stable stretch ranges of a ball's materials (docs/materials.md)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..fileio import check_distinct_files
from .common import check_output_folder, check_plot_path

#: models of `material fit`: the hyperelastic fits and the Prony series of viscoelastic tests
FIT_MODELS = ("neo_hookean", "mooney_rivlin", "yeoh", "ogden", "ogden_hyperfoam", "prony")
SHIFTS = ("wlf", "arrhenius")


def add_parser(verbs) -> None:
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
                          "relaxation, creep, dma")
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
    fit.add_argument("--json", action="store_true", help="print one JSON object")

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
    check.add_argument("--json", action="store_true", help="print one JSON object")


def run(args: argparse.Namespace) -> dict[str, Any]:
    from .common import use_compilation_cache

    use_compilation_cache()  # the fits' stresses and `check --speed-m-s`'s run are compiled
    return {"fit": _fit, "check": _check}[args.step](args)


# ---- fit ----------------------------------------------------------------------------------------
def _checked_fit_flags(args: argparse.Namespace) -> None:
    from ..material.hyperelastic import ERRORS, MAX_ORDER, OGDEN_MODELS

    if args.model not in FIT_MODELS:
        raise InputError(f"--model {args.model}: allowed {', '.join(FIT_MODELS)}")
    if args.error not in ERRORS:
        raise InputError(f"--error {args.error}: allowed {', '.join(ERRORS)}")
    if args.order is not None:
        if args.model not in OGDEN_MODELS:
            raise InputError(f"--order {args.order}: only for {' and '.join(OGDEN_MODELS)} (the "
                             f"number of terms); {args.model} has a fixed form")
        if not 1 <= args.order <= MAX_ORDER:
            raise InputError(f"--order {args.order}: allowed 1 to {MAX_ORDER} terms")
    if args.starts is not None and args.starts < 1:
        raise InputError(f"--starts {args.starts}: need an integer >= 1")
    prony_flags = [flag for flag, value in (
        ("--terms", args.terms), ("--shift", args.shift),
        ("--reference-temperature-c", args.reference_temperature_c), ("--merge", args.merge),
        ("--bulk-relaxation", args.bulk_relaxation or None)) if value is not None]
    if args.model != "prony" and prony_flags:
        raise InputError(f"{prony_flags[0]}: only with --model prony (a Prony series fit to "
                         "relaxation, creep or DMA tests)")
    if args.model == "prony":
        if args.terms is None:
            raise InputError("--model prony needs --terms N (the number of Prony terms)")
        if args.shift is not None and args.shift not in SHIFTS:
            raise InputError(f"--shift {args.shift}: allowed {', '.join(SHIFTS)}")
        if args.out is not None and args.merge is None:
            raise InputError("--out: a Prony series alone is not a material; give --merge "
                             "MATERIAL_JSON (the hyperelastic material it belongs to)")
    check_plot_path(args.plot)
    check_output_folder(args.out, "--out")


def _fit(args: argparse.Namespace) -> dict[str, Any]:
    from ..material.data import STRESS_MODES, VISCOELASTIC_MODES, parse_spec, read_test

    _checked_fit_flags(args)
    specs = [parse_spec(text) for text in args.tests]
    check_distinct_files([path for path, _ in specs], "FILE:MODE")
    prony = args.model == "prony"
    for path, mode in specs:
        if prony and mode not in VISCOELASTIC_MODES:
            raise InputError(f"{path}:{mode}: --model prony fits relaxation, creep or dma tests, "
                             f"not {mode} stress data (fit that with a hyperelastic model)")
        if not prony and mode not in STRESS_MODES:
            raise InputError(f"{path}:{mode}: a {mode} test is fitted with --model prony, not "
                             f"with {args.model}")
    tests = [read_test(path, mode) for path, mode in specs]
    if prony:
        return _fit_prony(args, tests)
    from ..material.hyperelastic import DEFAULT_STARTS, fit_hyperelastic

    fit = fit_hyperelastic(tests, args.model, order=args.order, error=args.error, seed=args.seed,
                           starts=args.starts or DEFAULT_STARTS)
    out = fit.to_dict()
    if args.out is not None:
        if not fit.usable:
            raise InputError(f"--out {args.out}: not written, the fitted set is not a valid ball "
                             f"material ({fit.notes[-1]})")
        _write_material(args.out, fit.material)
        out["out"] = str(args.out)
    if args.plot is not None:
        from ..material.plots import plot_fit
        out["plot"] = str(plot_fit(tests, fit, args.plot))
    if not args.json:
        _print_fit(out, tests)
    return out


def _write_material(path: Path, material: dict) -> None:
    from ..fileio import write_atomic
    write_atomic(path, json.dumps(material, indent=2) + "\n")


def _fit_prony(args: argparse.Namespace, tests) -> dict[str, Any]:
    from ..material import viscoelastic

    if len(tests) != 1:
        raise InputError(f"--model prony: give one relaxation, creep or dma test, got "
                         f"{len(tests)}")
    test = tests[0]
    c = test.columns
    if test.mode != "dma" and (args.shift is not None or args.reference_temperature_c is not None):
        raise InputError(f"--shift / --reference-temperature-c: only for a dma test, {test.path} "
                         f"is {test.mode}")
    # a modulus (compliance) column was normalised by its first value: the ratio is to the
    # value at the first time, which is the instantaneous one only when that time is 0
    normalised = "relaxation_modulus_pa" in c or "creep_compliance_per_pa" in c
    reference = float(c["time_s"][0]) if normalised and test.mode != "dma" else 0.0
    try:
        if test.mode == "relaxation":
            fit = viscoelastic.fit_relaxation(c["time_s"], c["relaxation_modulus_ratio"],
                                              args.terms, seed=args.seed,
                                              reference_time_s=reference)
        elif test.mode == "creep":
            fit = viscoelastic.fit_creep(c["time_s"], c["creep_compliance_ratio"], args.terms,
                                         seed=args.seed, reference_time_s=reference)
        else:
            fit = viscoelastic.fit_dma(c["frequency_hz"], c["storage_modulus_pa"],
                                       c["loss_modulus_pa"], args.terms,
                                       temperature_c=c.get("temperature_c"),
                                       shift=args.shift or "wlf",
                                       reference_c=args.reference_temperature_c, seed=args.seed)
    except InputError as error:  # the fit's messages name the column: add the file
        raise InputError(f"{test.path}: {error}") from None
    result = fit.to_dict()
    # k_i = 0 by default: a shear (or tension) relaxation test says nothing about the bulk
    prony = [{**term, "k": term["g"] if args.bulk_relaxation else 0.0}
             for term in result["terms"]]
    out: dict[str, Any] = {**result, "prony": prony, "model": "prony",
                           "bulk_relaxation": bool(args.bulk_relaxation)}
    if args.merge is not None:
        out["material"] = viscoelastic.merge_prony(_read_material(args.merge), prony,
                                                   bulk=args.bulk_relaxation,
                                                   where=str(args.merge))
    if args.out is not None:
        _write_material(args.out, out["material"])
        out["out"] = str(args.out)
    if not args.json:
        print(f"Prony series ({len(prony)} terms) fitted to {test.path} ({test.mode}), "
              f"R^2 = {fit.r2:.5f}")
        for term in prony:
            print(f"  g = {term['g']:.5g}  k = {term['k']:.5g}  tau_s = {term['tau_s']:.5g}")
    return out


def _print_fit(out: dict[str, Any], tests) -> None:
    print(f"{out['model']} fitted to {len(tests)} test(s), error {out['error']}")
    errors = out["standard_errors"]
    for key, value in out["constants"].items():
        print(f"  {key:<18} {value:>14.6g}  +/- {errors.get(key, 0.0):.3g}")
    print("  R^2: " + ", ".join(f"{Path(k).name if k != 'overall' else k} {v:.5f}"
                                for k, v in out["r2"].items()))
    for mode, (low, high) in out["stable_range"].items():
        print(f"  Drucker-stable {mode:<12} stretch {low:.4g} to {high:.4g}")
    for note in out["notes"]:
        print(f"  note: {note}")


# ---- check --------------------------------------------------------------------------------------
def _read_material(path: Path) -> dict:
    try:
        data = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(f"{path}: cannot read ({error})") from None
    except json.JSONDecodeError as error:
        raise InputError(f"{path}: not JSON ({error.msg}, line {error.lineno})") from None
    if isinstance(data, dict) and isinstance(data.get("material"), dict):
        data = data["material"]  # the JSON `material fit --json` prints
    if not isinstance(data, dict):
        raise InputError(f"{path}: expected a material object ({{\"model\": ...}})")
    return data


def _check(args: argparse.Namespace) -> dict[str, Any]:
    from ..fe.materials import material_from_dict
    from ..material.stability import stable_ranges

    if args.speed_m_s is not None and args.ball is None:
        raise InputError("--speed-m-s: only with --ball (a material alone is not run)")
    if args.speed_m_s is not None and not args.speed_m_s > 0:
        raise InputError(f"--speed-m-s {args.speed_m_s:g}: need an impact speed in m/s > 0")
    if args.material is not None:
        material = material_from_dict(_read_material(args.material), str(args.material))
        layers = [("material", material)]
        name = str(args.material)
    else:
        from ..fe import load_ball
        ball = load_ball(args.ball, impact_speed_m_s=args.speed_m_s)
        layers = [(layer.name, layer.material) for layer in ball.layers]
        name = ball.name
    out: dict[str, Any] = {"name": name, "layers": []}
    stretch = None
    if args.speed_m_s is not None:
        from ..fe import simulate
        result = simulate(ball, args.speed_m_s)
        stretch = result.stretch_range
        out["speed_m_s"] = args.speed_m_s
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
    if not args.json:
        _print_check(out)
    return out


def _print_check(out: dict[str, Any]) -> None:
    print(f"{out['name']}: Drucker-stable stretch ranges")
    for e in out["layers"]:
        if not e["checked"]:
            print(f"  {e['name']} ({e['model']}): not checked")
            continue
        for mode, (low, high) in e["stable_range"].items():
            inside = e.get("inside", {}).get(mode)
            tag = "" if inside is None else ("  run inside" if inside else "  RUN OUTSIDE")
            print(f"  {e['name']} ({e['model']}) {mode:<12} {low:.4g} to {high:.4g}{tag}")
    if "stretch_range" in out:
        lo, hi = out["stretch_range"]
        print(f"  run at {out['speed_m_s']:g} m/s reaches stretches {lo:.4g} to {hi:.4g}")
