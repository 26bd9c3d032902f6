"""Material test files to a fitted material, as `ballimpact material fit` does: the tests read and
checked against the model (a hyperelastic model fits stress tests, `prony` one relaxation, creep
or DMA test), the fit, and the material it gives (docs/materials.md)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..fileio import check_distinct_files
from .data import SIGNED_MODES, STRESS_MODES, VISCOELASTIC_MODES, MaterialTest, base_mode, read_test
from .files import read_material


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


__all__ = ["MaterialFit", "fit_material", "fit_prony_test", "read_tests"]
