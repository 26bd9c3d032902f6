"""Material test files to a fitted material, as `ballimpact material fit` does: the tests read and
checked against the model (a hyperelastic model fits stress tests, `prony` one relaxation, creep
or DMA test), the fit, and the material it gives (docs/materials.md)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..checks import check_integer
from ..errors import InputError
from ..fileio import check_distinct_files, check_output_folder, check_plot_path
from .data import SIGNED_MODES, STRESS_MODES, VISCOELASTIC_MODES, MaterialTest, base_mode, read_test
from .files import read_material

#: models of `material fit`: the hyperelastic fits and the Prony series of viscoelastic tests
FIT_MODELS = ("neo_hookean", "mooney_rivlin", "yeoh", "ogden", "ogden_hyperfoam", "prony")


@dataclass
class MaterialFit:
    """A fit of `material fit`: the `tests` read, the `fit` (`HyperelasticFit` or
    `viscoelastic.PronyFit`), `result` (the JSON of `material fit --json`), `material` (what
    --out writes: the fitted material, or the merged one of a Prony fit; None without one) and
    `unusable` (why the fitted set is not a valid ball material; empty when it is)."""

    tests: list[MaterialTest]
    fit: Any
    result: dict[str, Any]
    material: dict | None
    unusable: str = ""


def read_tests(specs: Sequence[tuple[Path, str]], model: str,
               compression_positive: bool = False) -> list[MaterialTest]:
    """The tests of (path, mode) pairs (`data.parse_spec`), each file once and each mode one
    that `model` fits (`prony`: relaxation, creep, dma; the others: stress tests)."""
    check_distinct_files([path for path, _ in specs], "FILE:MODE")
    prony = model == "prony"
    if compression_positive and not any(base_mode(m) in SIGNED_MODES for _, m in specs):
        raise InputError("--compression-positive: only for uniaxial, biaxial and planar tests "
                         "(a volumetric test's pressure is positive in compression already)")
    for path, declared in specs:
        mode = base_mode(declared)
        if prony and mode not in VISCOELASTIC_MODES:
            raise InputError(f"{path}:{mode}: --model prony fits relaxation, creep or dma tests, "
                             f"not {mode} stress data (fit that with a hyperelastic model)")
        if not prony and mode not in STRESS_MODES:
            raise InputError(f"{path}:{mode}: a {mode} test is fitted with --model prony, not "
                             f"with {model}")
    return [read_test(path, mode, compression_positive=compression_positive)
            for path, mode in specs]


def fit_prony_test(test: MaterialTest, terms: int, *, seed: int = 0, shift: str | None = None,
                   reference_temperature_c: float | None = None, bulk_relaxation: bool = False,
                   merge: Path | None = None):
    """A Prony series of `terms` terms fitted to one relaxation, creep or DMA test: (the fit,
    its JSON with `prony` (k_i = g_i with `bulk_relaxation`, else 0) and, with `merge` (a
    material file), `material`: that material with the fitted terms)."""
    from . import viscoelastic

    c = test.columns
    if test.mode != "dma" and (shift is not None or reference_temperature_c is not None):
        raise InputError(f"--shift / --reference-temperature-c: only for a dma test, {test.path} "
                         f"is {test.mode}")
    # a modulus (compliance) column was normalised by its first value: the ratio is to the
    # value at the first time, which is the instantaneous one only when that time is 0
    normalised = "relaxation_modulus_pa" in c or "creep_compliance_per_pa" in c
    reference = float(c["time_s"][0]) if normalised and test.mode != "dma" else 0.0
    try:
        if test.mode == "relaxation":
            fit = viscoelastic.fit_relaxation(c["time_s"], c["relaxation_modulus_ratio"], terms,
                                              seed=seed, reference_time_s=reference)
        elif test.mode == "creep":
            fit = viscoelastic.fit_creep(c["time_s"], c["creep_compliance_ratio"], terms,
                                         seed=seed, reference_time_s=reference)
        else:
            fit = viscoelastic.fit_dma(c["frequency_hz"], c["storage_modulus_pa"],
                                       c["loss_modulus_pa"], terms,
                                       temperature_c=c.get("temperature_c"), shift=shift or "wlf",
                                       reference_c=reference_temperature_c, seed=seed)
    except InputError as error:  # the fit's messages name the column: add the file
        raise InputError(f"{test.path}: {error}") from None
    result = fit.to_dict()
    # k_i = 0 by default: a shear (or tension) relaxation test says nothing about the bulk
    prony = [{**term, "k": term["g"] if bulk_relaxation else 0.0} for term in result["terms"]]
    out: dict[str, Any] = {**result, "prony": prony, "model": "prony",
                           "bulk_relaxation": bool(bulk_relaxation)}
    if merge is not None:
        out["material"] = viscoelastic.merge_prony(read_material(merge), prony,
                                                   bulk=bulk_relaxation, where=str(merge))
    return fit, out


def fit_material(specs: Sequence[tuple[Path, str]], model: str, *,
                 compression_positive: bool = False, order: int | None = None,
                 error: str = "absolute", seed: int = 0, starts: int | None = None,
                 terms: int | None = None, shift: str | None = None,
                 reference_temperature_c: float | None = None, bulk_relaxation: bool = False,
                 merge: Path | None = None) -> MaterialFit:
    """`model` (a hyperelastic model of `hyperelastic.MODELS`, or `prony` with `terms`) fitted
    to the tests of (path, mode) pairs: `material fit`'s fit and JSON (`MaterialFit`)."""
    tests = read_tests(specs, model, compression_positive)
    if model == "prony":
        if len(tests) != 1:
            raise InputError(f"--model prony: give one relaxation, creep or dma test, got "
                             f"{len(tests)}")
        fit, result = fit_prony_test(tests[0], terms, seed=seed, shift=shift,
                                     reference_temperature_c=reference_temperature_c,
                                     bulk_relaxation=bulk_relaxation, merge=merge)
        return MaterialFit(tests, fit, result, result.get("material"))
    from .hyperelastic import DEFAULT_STARTS, fit_hyperelastic

    fit = fit_hyperelastic(tests, model, order=order, error=error, seed=seed,
                           starts=starts or DEFAULT_STARTS)
    return MaterialFit(tests, fit, fit.to_dict(), fit.material,
                       "" if fit.usable else fit.notes[-1])


def _check_fit_options(model: str, *, order: int | None = None, error: str = "absolute",
                       starts: int | None = None, terms: int | None = None,
                       shift: str | None = None, reference_temperature_c: float | None = None,
                       bulk_relaxation: bool = False, merge: Path | None = None,
                       out_path: Path | None = None, plot_path: Path | None = None) -> None:
    """`InputError` naming the flag of `material fit` for a model not in `FIT_MODELS`, an
    error measure, order or start count the model does not take, Prony options without
    `model` prony, prony with a plot (`plot_path`) or without `terms`, a `shift` not in `viscoelastic.SHIFTS`, and a Prony
    series to be written (`out_path`) without the material it belongs to (`merge`)."""
    from .hyperelastic import ERRORS, MAX_ORDER, OGDEN_MODELS
    from .viscoelastic import SHIFTS

    if model not in FIT_MODELS:
        raise InputError(f"--model {model}: allowed {', '.join(FIT_MODELS)}")
    if error not in ERRORS:
        raise InputError(f"--error {error}: allowed {', '.join(ERRORS)}")
    if order is not None:
        if model not in OGDEN_MODELS:
            raise InputError(f"--order {order}: only for {' and '.join(OGDEN_MODELS)} (the "
                             f"number of terms); {model} has a fixed form")
        check_integer("--order", order, 1, MAX_ORDER, note="the number of terms")
    if starts is not None:
        check_integer("--starts", starts, 1)
    prony_flags = [flag for flag, value in (
        ("--terms", terms), ("--shift", shift),
        ("--reference-temperature-c", reference_temperature_c), ("--merge", merge),
        ("--bulk-relaxation", bulk_relaxation or None)) if value is not None]
    if model != "prony" and prony_flags:
        raise InputError(f"{prony_flags[0]}: only with --model prony (a Prony series fit to "
                         "relaxation, creep or DMA tests)")
    if model == "prony":
        if plot_path is not None:
            raise InputError("--plot: drawn for the hyperelastic fits; a Prony fit prints its "
                             "terms and R^2 (leave --plot out with --model prony)")
        if terms is None:
            raise InputError("--model prony needs --terms N (the number of Prony terms)")
        if shift is not None and shift not in SHIFTS:
            raise InputError(f"--shift {shift}: allowed {', '.join(SHIFTS)}")
        if out_path is not None and merge is None:
            raise InputError("--out: a Prony series alone is not a material; give --merge "
                             "MATERIAL_JSON (the hyperelastic material it belongs to)")


def fit_material_files(tests: Sequence[str], model: str, *, compression_positive: bool = False,
                       order: int | None = None, error: str = "absolute", seed: int = 0,
                       starts: int | None = None, terms: int | None = None,
                       shift: str | None = None, reference_temperature_c: float | None = None,
                       bulk_relaxation: bool = False, merge: Path | None = None,
                       out_path: Path | None = None,
                       plot_path: Path | None = None) -> MaterialFit:
    """`ballimpact material fit`: the tests given as FILE:MODE texts (`data.parse_spec`) fitted
    by `fit_material` (options checked by `_check_fit_options` first); with `out_path` the
    material written there (`files.write_material`; a Prony fit: the `merge` material with its
    terms), with `plot_path` a PNG of data and fit per mode (hyperelastic models only, refused
    for prony: `plots.plot_fit`). The result's JSON gets the paths written (`out`, `plot`). Raises
    `InputError` on bad options or paths (naming the flag), on tests the model cannot fit, and
    when a fitted set that is not a valid ball material would be written."""
    from .data import parse_spec
    from .files import write_material

    _check_fit_options(model, order=order, error=error, starts=starts, terms=terms, shift=shift,
                       reference_temperature_c=reference_temperature_c,
                       bulk_relaxation=bulk_relaxation, merge=merge, out_path=out_path,
                       plot_path=plot_path)
    check_plot_path(plot_path)
    check_output_folder(out_path, "--out")
    run = fit_material([parse_spec(text) for text in tests], model,
                       compression_positive=compression_positive, order=order, error=error,
                       seed=seed, starts=starts, terms=terms, shift=shift,
                       reference_temperature_c=reference_temperature_c,
                       bulk_relaxation=bulk_relaxation, merge=merge)
    if out_path is not None:
        if run.unusable:
            raise InputError(f"--out {out_path}: not written, the fitted set is not a valid ball "
                             f"material ({run.unusable})")
        write_material(out_path, run.material)
        run.result["out"] = str(out_path)
    if plot_path is not None:
        from .plots import plot_fit

        run.result["plot"] = str(plot_fit(run.tests, run.fit, plot_path))
    return run


__all__ = ["FIT_MODELS", "MaterialFit", "fit_material", "fit_material_files", "fit_prony_test",
           "read_tests"]
