"""Hyperelastic constants from material tests: least squares on the nominal stresses of
`modes.py`, so that a fitted constant means exactly what the FE ball does with it.

- neo-Hookean, Mooney-Rivlin, Yeoh: the stress is linear in the constants, so the design matrix
  is the stress of each constant alone (its energy with that constant = 1, the others 0) and the
  fit is the exact linear least squares (numpy lstsq).
- Ogden (N = 1..3 terms) and Ogden hyperfoam (N = 1..3, a common Poisson ratio): for fixed
  exponents alpha_i (and nu) the stress is linear in the mu_i (hyperfoam: with a common nu each
  term alone has zero stress across its free axes at the same free stretch, so terms superpose).
  The mu_i come from a non-negative least squares that keeps each term's sign rule of the FE
  model (`mu_signs`): Ogden's sufficient condition for stability, mu_i > 0 for the rubber law in
  this (ABAQUS) form, 2 mu_i / alpha_i^2 (...), and mu_i alpha_i > 0 for hyperfoam; the alpha_i
  (and nu) from scipy's least_squares on that projected problem, from seeded starts spread over
  |alpha| in [0.5, 10] of either sign.
- Error "absolute": residuals in Pa. "relative": each residual divided by its measured stress,
  points with zero measured stress skipped.
- Rubber laws are fitted incompressible (deviatoric energy). A volumetric test gives their
  bulk modulus, p = K (1 - J), linear again: d1_per_pa = 2 / K; without one, d1_per_pa = 0 (the
  ball then takes K0 = 20 mu0). Hyperfoam takes volumetric tests in the fit itself; without one
  its nu is fixed at 0 (ABAQUS does the same), with a note.

Standard errors: `identifiability.standard_errors` of the Jacobian of the (weighted) residuals in
the constants (JAX through the energies). R^2 = 1 - SS_res / SS_tot on the stresses in Pa, per
test and over all points pooled.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import least_squares, nnls

from ..checks import check_integer
from ..errors import InputError, InputWarning
from ..constitutive import material_from_dict
from ..identifiability import standard_errors
from .data import MaterialTest
from .modes import COMPRESSIBLE, deformation_stress, term_stresses
from ..constitutive.stability import MODES as STABLE_MODES
from .stability import stable_ranges, unstable_within
from .viscoelastic import r_squared

LINEAR_KEYS = {"neo_hookean": ("c10_pa",), "mooney_rivlin": ("c10_pa", "c01_pa"),
               "yeoh": ("c10_pa", "c20_pa", "c30_pa")}
OGDEN_MODELS = ("ogden", "ogden_hyperfoam")
MODELS = (*LINEAR_KEYS, *OGDEN_MODELS)
MAX_ORDER = 3
DEFAULT_ORDER = {"ogden": 3, "ogden_hyperfoam": 1}
ERRORS = ("absolute", "relative")
DEFAULT_STARTS = 14
#: bounds of the searched exponents |alpha| and the common Poisson ratio of hyperfoam
ALPHA_BOUNDS = (1e-3, 25.0)  # |alpha| -> 0 is a valid limit (W -> mu sum ln^2 l)
START_ALPHA = (0.5, 10.0)
NU_BOUNDS = (-0.45, 0.495)
_TOL = 1e-12


@dataclass(frozen=True)
class _Block:
    """The stress values of one test, flattened (biaxial: P1 then P2 per point)."""

    test: MaterialTest
    deformation: str
    x1: np.ndarray
    x2: np.ndarray | None
    y: np.ndarray
    weight: np.ndarray  # 1 (absolute) or 1/|y| (relative); 0 skips a point

    def predict(self, model: str, constants) -> np.ndarray:
        return np.ravel(deformation_stress(model, constants, self.deformation, self.x1, self.x2))


@dataclass(frozen=True)
class HyperelasticFit:
    """A fitted material and how well it fits. `material` is the object a ball's layer holds
    (loads with `constitutive.material_from_dict`); `constants` and `standard_errors` are keyed
    by the constant's path in it (`c10_pa`, `terms[0].alpha`, `terms.nu` for hyperfoam's common
    Poisson ratio); `residuals` are model minus measured stress (Pa) per test file."""

    model: str
    error: str
    material: dict[str, Any]
    constants: dict[str, float]
    standard_errors: dict[str, float]
    r2: dict[str, float]
    residuals: dict[str, np.ndarray]
    stable_range: dict[str, tuple[float, float]]
    unstable: list[dict[str, Any]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    usable: bool = True

    def to_dict(self) -> dict[str, Any]:
        """The JSON of `material fit --json` (residuals as lists)."""
        return {"model": self.model, "error": self.error, "material": self.material,
                "constants": self.constants, "standard_errors": self.standard_errors,
                "r2": self.r2, "stable_range": {m: list(r) for m, r in self.stable_range.items()},
                "unstable_in_data": self.unstable, "usable": self.usable, "notes": self.notes,
                "residuals_pa": {k: v.tolist() for k, v in self.residuals.items()}}


def _blocks(tests: list[MaterialTest], error: str, volumetric: bool) -> list[_Block]:
    out = []
    for test in tests:
        if (test.deformation == "volumetric") != volumetric:
            continue
        c = test.columns
        if test.deformation == "volumetric":
            x1, x2, y = c["volume_ratio"], None, c["pressure_pa"]
        elif test.deformation == "biaxial":
            x1, x2 = c["stretch_1"], c["stretch_2"]
            y = np.stack([c["nominal_stress_1_pa"], c["nominal_stress_2_pa"]], axis=-1).ravel()
        else:
            x1, x2, y = c["stretch"], None, c["nominal_stress_pa"]
        if error == "relative":
            weight = np.where(y != 0.0, 1.0 / np.where(y != 0.0, np.abs(y), 1.0), 0.0)
        else:
            weight = np.ones_like(y)
        out.append(_Block(test, test.deformation, x1, x2, y, weight))
    return out


def _check_request(tests, model, order, error, starts) -> tuple[int, int]:
    """The request checked: (order, starts), whole numbers."""
    if model not in MODELS:
        raise InputError(f"model {model!r}: allowed {', '.join(MODELS)}")
    if error not in ERRORS:
        raise InputError(f"error {error!r}: allowed {', '.join(ERRORS)}")
    if order is not None and model not in OGDEN_MODELS:
        raise InputError(f"order {order}: only for {' and '.join(OGDEN_MODELS)} (their number of "
                         f"terms); {model} has a fixed form")
    order = DEFAULT_ORDER.get(model, 0) if order is None else order
    if model in OGDEN_MODELS:
        order = check_integer("order", order, 1, MAX_ORDER, note="the number of terms")
    starts = check_integer("starts", starts, 1)
    stress = [t for t in tests if t.deformation != "volumetric"]
    other = [t for t in tests if t.mode not in ("uniaxial", "biaxial", "planar", "volumetric")]
    if other:
        raise InputError(f"{other[0].path}: a {other[0].mode} test is fitted by a Prony series "
                         "(model prony), not by a hyperelastic model")
    if not stress:
        raise InputError("no stress-stretch test (uniaxial, biaxial or planar) to fit "
                         f"{model} to; volumetric tests alone give only the bulk modulus")
    names = [str(t.path) for t in tests]
    if len(set(names)) != len(names):
        raise InputError(f"{names[0]}: the same test is given twice")
    return order, starts


def fit_hyperelastic(tests: list[MaterialTest], model: str, order: int | None = None,
                     error: str = "absolute", seed: int = 0,
                     starts: int = DEFAULT_STARTS) -> HyperelasticFit:
    """Fit `model` (neo_hookean, mooney_rivlin, yeoh, ogden, ogden_hyperfoam) to stress tests.

    `order`: terms of ogden (default 3) and ogden_hyperfoam (default 1), 1 to 3. `starts`: seeded
    starts of the exponent search (ogden models). Warns (`InputWarning`) when the fitted set is
    Drucker-unstable inside the stretch range of a test's mode, and when the set is not one a
    ball accepts (`usable` False; e.g. Mooney-Rivlin with C10 + C01 <= 0)."""
    tests = list(tests)
    order, starts = _check_request(tests, model, order, error, starts)
    notes: list[str] = []
    volumetric = _blocks(tests, error, True)
    if model in COMPRESSIBLE:
        blocks = _blocks(tests, error, False) + volumetric
        fit_nu = bool(volumetric)
        if not fit_nu:
            notes.append("no volumetric test: hyperfoam nu fixed at 0 (no lateral contraction), "
                         "as ABAQUS does; add a volumetric test to fit it")
        params, names, evaluate, to_material = _ogden_fit(blocks, model, order, fit_nu,
                                                          seed, starts, notes)
    else:
        blocks = _blocks(tests, error, False)
        if model in LINEAR_KEYS:
            params, names, evaluate, to_material = _linear_fit(blocks, model)
        else:
            params, names, evaluate, to_material = _ogden_fit(blocks, model, order, False,
                                                              seed, starts, notes)
    material = to_material(params)
    values = dict(zip(names, map(float, params)))
    flat, jacobian = evaluate(params)
    errors = dict(zip(names, _standard_errors(blocks, flat, jacobian)))
    ends = np.cumsum([b.y.size for b in blocks])[:-1]
    predictions = {id(b): part for b, part in zip(blocks, np.split(flat, ends))}
    if model not in COMPRESSIBLE:
        d1, d1_error = _bulk_fit(volumetric, model, predictions, notes)
        material["d1_per_pa"] = d1
        values["d1_per_pa"] = d1
        errors["d1_per_pa"] = d1_error
        blocks = blocks + volumetric
    usable = _usable(material, notes)
    residuals = {str(b.test.path): predictions[id(b)] - b.y for b in blocks}
    r2 = _r_squared(blocks, predictions)
    for name, value in r2.items():
        if name != "overall" and value < 0.0:
            message = (f"{name}: R^2 = {value:.3g} < 0, the fit does not describe this test "
                       "(worse than its mean); with tests of very different stress levels (a "
                       "volumetric test's pressures against shear stresses) try --error relative")
            notes.append(message)
            warnings.warn(message, InputWarning, stacklevel=2)
    ranges, unstable = _stability(material, tests) if usable else ({}, [])
    for r in unstable:
        warnings.warn(f"fitted {model} is Drucker-unstable in {r['mode']} deformation for "
                      f"stretches {r['stretch_from']:.4g} to {r['stretch_to']:.4g}, inside the "
                      f"tests' range {r['data_from']:.4g} to {r['data_to']:.4g}", InputWarning,
                      stacklevel=2)
    return HyperelasticFit(model=model, error=error, material=material, constants=values,
                           standard_errors=errors, r2=r2, residuals=residuals,
                           stable_range=ranges, unstable=unstable, notes=notes, usable=usable)


def _usable(material: dict, notes: list[str]) -> bool:
    """Whether a ball accepts the fitted set (a least-squares optimum may not: Mooney-Rivlin on
    large uniaxial stretches can give C10 + C01 <= 0); if not, the reason goes to the notes and
    a warning is given, and the fit is still returned."""
    try:
        material_from_dict(material, f"fitted {material['model']}")
    except InputError as error:
        message = f"{error}: the fitted set is not a valid ball material (fit another model or " \
                  "a narrower stretch range)"
        notes.append(message)
        warnings.warn(message, InputWarning, stacklevel=3)
        return False
    return True


# ---- linear models ------------------------------------------------------------------------------
def _linear_constants(model: str):
    keys = LINEAR_KEYS[model]

    def constants_of(x):
        # k_pa: the volumetric part does not act in an isochoric state (fitted separately)
        return {**{k: x[i] for i, k in enumerate(keys)}, "k_pa": 0.0}
    return keys, constants_of


def design_matrix(blocks: list[_Block], model: str) -> np.ndarray:
    """Stress of each constant alone (Pa per Pa of constant), rows as the blocks' values."""
    keys, constants_of = _linear_constants(model)
    columns = []
    for i in range(len(keys)):
        unit = np.zeros(len(keys))
        unit[i] = 1.0
        columns.append(np.concatenate([b.predict(model, constants_of(unit)) for b in blocks]))
    return np.stack(columns, axis=1)


def _linear_fit(blocks, model):
    keys, _ = _linear_constants(model)
    a = design_matrix(blocks, model)
    w = np.concatenate([b.weight for b in blocks])
    y = np.concatenate([b.y for b in blocks])
    x = np.linalg.lstsq(a * w[:, None], y * w, rcond=None)[0]

    def to_material(p):
        return {"model": model, **{k: float(v) for k, v in zip(keys, p)}, "moduli": "long_term"}
    return x, list(keys), lambda p: (a @ p, a), to_material


# ---- Ogden and hyperfoam ------------------------------------------------------------------------
def _term_columns(blocks, model, alphas, nu):
    """(values, terms): the stress of each term alone with mu = 1."""
    n = len(alphas)
    beta = None if model == "ogden" else np.full(n, nu / (1.0 - 2.0 * nu))
    return term_stresses(model, tuple(b.deformation for b in blocks), np.ones(n), alphas, beta,
                         tuple((b.x1, b.x2) for b in blocks)).T


def _sign_patterns(model: str, order: int) -> list[np.ndarray]:
    """Signs of the exponents, all positive first. Hyperfoam needs mu_i alpha_i > 0 and
    mu0 = sum mu_i > 0, so an all-negative pattern is no material there."""
    patterns = [np.array([1.0 if (k >> i) & 1 else -1.0 for i in range(order)])
                for k in range(2 ** order)]
    if model == "ogden_hyperfoam":
        patterns = [p for p in patterns if (p > 0).any()]
    return patterns[::-1]


def mu_signs(model: str, alpha_signs: np.ndarray) -> np.ndarray:
    """The sign each mu_i must have: + for the Ogden rubber law (mu_i > 0), that of alpha_i
    for hyperfoam (mu_i alpha_i > 0)."""
    return alpha_signs if model == "ogden_hyperfoam" else np.ones_like(alpha_signs)


def _ogden_fit(blocks, model, order, fit_nu, seed, starts, notes):
    w = np.concatenate([b.weight for b in blocks])
    y = np.concatenate([b.y for b in blocks]) * w
    rng = np.random.default_rng(seed)

    def unpack(z, signs):
        return signs * np.exp(z[:order]), (z[order] if fit_nu else 0.0)

    def solve(z, signs, constrained):
        """mu (linear least squares at these exponents) and the weighted residuals. Constrained:
        mu_i sign(alpha_i) >= 0 by NNLS; else plain lstsq (smooth in the exponents)."""
        alphas, nu = unpack(z, signs)
        a = _term_columns(blocks, model, alphas, nu) * w[:, None]
        if constrained:
            s, _ = nnls(a * mu_signs(model, signs), y)
            mu = s * mu_signs(model, signs)
        else:
            mu = np.linalg.lstsq(a, y, rcond=None)[0]
        return mu, a @ mu - y

    def search(z0, signs, constrained):
        result = least_squares(lambda z: solve(z, signs, constrained)[1], z0,
                               bounds=(lower, upper), xtol=_TOL, ftol=_TOL, gtol=_TOL,
                               max_nfev=200 * (order + 1))
        mu, r = solve(result.x, signs, constrained)
        return result.x, mu, r

    lower = [math.log(ALPHA_BOUNDS[0])] * order + ([NU_BOUNDS[0]] if fit_nu else [])
    upper = [math.log(ALPHA_BOUNDS[1])] * order + ([NU_BOUNDS[1]] if fit_nu else [])
    patterns = _sign_patterns(model, order)
    best = None
    for k in range(starts):
        signs = patterns[k % len(patterns)]
        z0 = np.log(rng.uniform(*START_ALPHA, size=order))
        if fit_nu:
            z0 = np.append(z0, rng.uniform(0.0, 0.4))
        with np.errstate(all="ignore"):
            try:
                z, mu, r = search(z0, signs, False)
                if not (np.all(mu * mu_signs(model, signs) > 0) and np.all(np.isfinite(r))):
                    # the free optimum breaks the sign rule: search again with the constraint
                    z, mu, r = search(z, signs, True)
            except (ValueError, np.linalg.LinAlgError):  # a start whose stresses overflow
                continue
        if not np.all(np.isfinite(r)):
            continue
        # all terms alive first, then the misfit
        key = (-int(np.sum(mu * mu_signs(model, signs) > 0)), float(r @ r))
        if best is None or key < best[0]:
            best = (key, z, signs, mu)
    if best is None:
        raise InputError(f"{model}: no start of the fit gave finite stresses; check the tests' "
                         "units (stresses in Pa)")
    _, z, signs, mu = best
    alphas, nu = unpack(z, signs)
    alive = mu * mu_signs(model, signs) > 0
    if not alive.any():
        raise InputError(f"{model}: the fit found no term with a positive modulus (the stresses "
                         "may have the wrong sign for the mode)")
    if not alive.all():
        notes.append(f"{model}: {int((~alive).sum())} of {order} terms came out with mu = 0 in "
                     f"every start; fitted with {int(alive.sum())} terms")
        alphas, mu, order = alphas[alive], mu[alive], int(alive.sum())
    for i, a in enumerate(alphas):
        if np.isclose(abs(a), ALPHA_BOUNDS, rtol=1e-6).any():
            notes.append(f"{model}: term {i} has |alpha| at the search bound {abs(a):g} (the "
                         "optimum under the sign rule lies at the edge; its standard error "
                         "is only indicative)")
    params = np.concatenate([mu, alphas] + ([[nu]] if fit_nu else []))
    names = [f"terms[{i}].{k}" for k in ("mu_pa", "alpha") for i in range(order)]
    names += ["terms.nu"] if fit_nu else []
    def evaluate(p):
        """Stresses (unweighted) and their Jacobian in (mu_i, alpha_i[, nu]): exact in mu (the
        columns), central differences in the exponents (errors ~1e-10 relative)."""
        mu, alphas = p[:order], p[order:2 * order]
        nu = p[2 * order] if fit_nu else 0.0
        cols = _term_columns(blocks, model, alphas, nu)
        jac = [cols]
        for i in range(order):
            h = 1e-5 * abs(alphas[i])
            up, down = alphas.copy(), alphas.copy()
            up[i] += h
            down[i] -= h
            diff = (_term_columns(blocks, model, up, nu) - _term_columns(blocks, model, down, nu))
            jac.append((diff[:, i] * mu[i] / (2 * h))[:, None])
        if fit_nu:
            h = 1e-6
            diff = (_term_columns(blocks, model, alphas, nu + h)
                    - _term_columns(blocks, model, alphas, nu - h)) @ mu
            jac.append((diff / (2 * h))[:, None])
        return cols @ mu, np.concatenate(jac, axis=1)

    def to_material(p):
        terms = [{"mu_pa": float(p[i]), "alpha": float(p[order + i])} for i in range(order)]
        if model == "ogden_hyperfoam":
            for t in terms:
                t["nu"] = float(p[2 * order]) if fit_nu else 0.0
        return {"model": model, "terms": terms, "moduli": "long_term"}
    return params, names, evaluate, to_material


# ---- bulk modulus of the rubber laws -------------------------------------------------------------
def _bulk_fit(volumetric, model, predictions, notes) -> tuple[float, float]:
    """d1_per_pa = 2 / K from the volumetric tests (p = K (1 - J) by the model's energy), and
    its standard error; 0 with a note when there is none."""
    if not volumetric:
        notes.append(f"no volumetric test: {model} d1_per_pa = 0 (the ball then takes the bulk "
                     "modulus K0 = 20 mu0, Poisson ratio 0.475)")
        return 0.0, 0.0
    unit = {**{k: 0.0 for k in LINEAR_KEYS.get(model, ())}, "k_pa": 1.0}
    if model == "ogden":
        unit.update(mu_pa=np.zeros(1), alpha=np.ones(1))
    col = np.concatenate([b.predict(model, unit) for b in volumetric])
    w = np.concatenate([b.weight for b in volumetric])
    y = np.concatenate([b.y for b in volumetric])
    a = (col * w)[:, None]
    k = float(np.linalg.lstsq(a, y * w, rcond=None)[0][0])
    if not k > 0:
        raise InputError(f"{volumetric[0].test.path}: the volumetric tests give a bulk modulus "
                         f"{k:g} Pa <= 0")
    for b in volumetric:
        predictions[id(b)] = b.predict(model, {**unit, "k_pa": k})
    k_error = float(standard_errors(a, a[:, 0] * k - y * w)[0])
    return 2.0 / k, 2.0 * k_error / k ** 2  # delta method for D1 = 2 / K


# ---- statistics ---------------------------------------------------------------------------------
def _standard_errors(blocks, flat, jacobian) -> list[float]:
    """Of the weighted residuals (points skipped by the relative error left out)."""
    w = np.concatenate([b.weight for b in blocks])
    y = np.concatenate([b.y for b in blocks])
    keep = w > 0
    return [float(e) for e in standard_errors((jacobian * w[:, None])[keep],
                                              ((flat - y) * w)[keep])]


def _r_squared(blocks, predictions) -> dict[str, float]:
    """R^2 per test and pooled (`viscoelastic.r_squared`: NaN for a test of constant stress)."""
    res = {str(b.test.path): predictions[id(b)] - b.y for b in blocks}
    out = {str(b.test.path): r_squared(res[str(b.test.path)], b.y) for b in blocks}
    out["overall"] = r_squared(np.concatenate(list(res.values())),
                               np.concatenate([b.y for b in blocks]))
    return out


def _stability(material: dict, tests: list[MaterialTest]):
    """Stable range per mode, and the unstable intervals that overlap a test's stretch range."""
    built = material_from_dict(material, "fitted material")
    ranges = stable_ranges(built)
    data: dict[str, tuple[float, float]] = {}
    for t in tests:
        if t.deformation in STABLE_MODES:
            lo, hi = t.stretch_range()
            old = data.get(t.deformation, (lo, hi))
            data[t.deformation] = (min(lo, old[0]), max(hi, old[1]))
    return ranges, unstable_within(built, data)




def energy_constants(material: dict) -> dict[str, Any]:
    """The constants `energy` takes for a fitted material dict (long-term, no Prony), built
    without the ball's validation (so that an unusable fit can still be drawn)."""
    model = material["model"]
    if model in LINEAR_KEYS:
        return {**{k: float(material.get(k, 0.0)) for k in LINEAR_KEYS[model]}, "k_pa": 0.0}
    mu = np.array([t["mu_pa"] for t in material["terms"]])
    alpha = np.array([t["alpha"] for t in material["terms"]])
    if model == "ogden":
        return {"mu_pa": mu, "alpha": alpha, "k_pa": 0.0}
    nu = np.array([t["nu"] for t in material["terms"]])
    return {"mu_pa": mu, "alpha": alpha, "beta": nu / (1.0 - 2.0 * nu)}


__all__ = ["DEFAULT_ORDER", "DEFAULT_STARTS", "ERRORS", "LINEAR_KEYS", "MAX_ORDER", "MODELS",
           "HyperelasticFit", "design_matrix", "energy_constants", "fit_hyperelastic"]
