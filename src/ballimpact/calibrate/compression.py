"""Compression tests as calibration tests: a measured force-deflection curve of the ball (or of an
inner part, e.g. the core) squeezed between two platens, read from a CSV, compared with the
quasi-static FE curve of a design (`fe.compress`), and refined by Levenberg-Marquardt with a
finite-difference Jacobian.

The objective `compression` is the force NRMSE over the measured curve:

    NRMSE = sqrt(mean_k (F_model(D_k) - F_k)^2) / max_k F_k

with F_model the FE curve (`steps` equal increments up to the largest measured deflection D_K,
linearly interpolated) at the measured deflections D_k. No alignment: the deflection's zero is
the platens' first touch in both.

Why finite differences for the refinement: the FE curve comes from Newton solves on the host
(SciPy's sparse LU), outside JAX's trace, so there is no exact derivative through it; the
Newton solve converges to 1e-7 of the platen force, so a central difference of step `FD_STEP`
(unit coordinates) is exact to ~1e-3 relative, enough for Gauss-Newton steps and standard errors.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from ..errors import InputError, InputWarning, SimulationError
from ..fileio import read_table
from .gradient import Refinement, levenberg_marquardt, parameter_errors

#: unit headers of a compression CSV: column -> (quantity, factor to SI)
COLUMNS = {"deflection_m": ("deflection", 1.0), "deflection_mm": ("deflection", 1e-3),
           "force_n": ("force", 1.0), "force_kn": ("force", 1e3)}
#: equal deflection increments of the FE curve up to the largest measured deflection
DEFAULT_STEPS = 20
#: central-difference step of the refinement's Jacobian (unit coordinates: 1e-4 of the span)
FD_STEP = 1e-4
#: the comparison keys of a compression test (per-test columns of a search's evaluations)
COMPARISON_KEYS = ("compression_nrmse", "end_force_relative_error")


@dataclass(frozen=True)
class CompressionTest:
    """A measured force-deflection curve (SI). `layers`: the outermost layer of the tested part
    ("core" for a core compression test), None for the whole ball; `rate_m_s`: the platen speed
    for the Prony states (None: the long-term, fully relaxed curve); `steps`: increments of the
    FE curve; `source`: the file it came from (for messages)."""

    name: str
    deflection_m: np.ndarray
    force_n: np.ndarray
    layers: str | None = None
    rate_m_s: float | None = None
    steps: int = DEFAULT_STEPS
    source: str = ""
    #: the kind of test (`problem.kind_of`)
    kind: ClassVar[str] = "compression"

    def fe_run(self, ball, options, allow=(), progress=None):
        """The FE curve of `ball` for this test (`compression_run`; `allow` is the impact
        tests' and has no check to pass here)."""
        return compression_run(self, ball, options, progress)

    def check_against(self, ball) -> None:
        """`check_against_ball`: a curve the tested ball cannot be compressed to is refused."""
        check_against_ball(self, ball)

    @property
    def peak_force_n(self) -> float:
        return float(np.max(self.force_n))

    @property
    def max_deflection_m(self) -> float:
        return float(self.deflection_m[-1])


def is_compression(test) -> bool:
    return test.kind == "compression"


def read_compression_csv(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """(deflection_m, force_n) of a compression CSV: `#` comments, a header naming a deflection
    column (`deflection_m` or `deflection_mm`) and a force column (`force_n` or `force_kn`), at
    least 3 rows of finite numbers, deflections >= 0 and increasing. `InputError` naming the file
    and the line."""
    path = Path(path)
    header_line, names, rows, table = read_table(
        path, "rows",
        lambda names, line: [col for col, _, _ in _compression_columns(path, names, line)])
    if len(rows) < 3:
        raise InputError(f"{path}: {len(rows)} rows; a compression curve needs at least 3 "
                         "(deflection, force) points")
    columns = _compression_columns(path, names, header_line)
    values = np.column_stack([table[:, col] * factor for col, factor, _ in columns])
    for row, number in enumerate(rows):
        for k, (quantity, (col, _, name)) in enumerate(zip(("deflection", "force"), columns)):
            if values[row, k] < 0.0:
                raise InputError(f"{path}: line {number}, column {name}: {table[row, col]:g} is "
                                 f"negative (the {quantity} of a compression is >= 0)")
        if row > 0 and values[row, 0] <= values[row - 1, 0]:
            col, _, name = columns[0]
            raise InputError(f"{path}: line {number}, column {name}: {table[row, col]:g} does not "
                             "increase (the deflections must increase from row to row)")
    if not np.max(values[:, 1]) > 0.0:
        raise InputError(f"{path}: every force is 0; nothing to calibrate against")
    return values[:, 0], values[:, 1]


def _compression_columns(path: Path, names: list[str], line: int) -> list[tuple[int, float, str]]:
    """(index, factor to SI, name) of the deflection and the force column of the header on line
    `line`."""
    found: dict[str, tuple[int, float, str]] = {}
    for col, name in enumerate(names):
        if name not in COLUMNS:
            raise InputError(f"{path}: line {line}: unknown column {name!r}; a compression "
                             "curve has deflection_m or deflection_mm, and force_n or force_kn")
        quantity, factor = COLUMNS[name]
        if quantity in found:
            raise InputError(f"{path}: line {line}: the header names the {quantity} twice")
        found[quantity] = (col, factor, name)
    for quantity, allowed in (("deflection", "deflection_m or deflection_mm"),
                              ("force", "force_n or force_kn")):
        if quantity not in found:
            raise InputError(f"{path}: line {line}: no {quantity} column; add one of {allowed}")
    return [found["deflection"], found["force"]]


def check_against_ball(test: CompressionTest, ball) -> None:
    """`InputError` naming the file for a curve the tested ball cannot be compressed to: a
    deflection at or above its diameter (likely millimetres given as metres), or above its radius
    (`fe.compress` squeezes a ball to half its diameter at most); then `compress`'s own checks
    (`check_compression_input`: the platen rate, the increments); last a force whose implied
    stiffness is no sports ball's (`balls.checks.check_force_units`: kN given as N)."""
    d = test.max_deflection_m
    diameter, radius = 2.0 * ball.outer_radius_m, ball.outer_radius_m
    where = test.source or test.name
    part = f"layer {test.layers}" if test.layers else "the ball"
    if d >= diameter:
        hint = (f"; likely millimetres given as metres: name the column deflection_mm "
                f"({d:g} mm is {d * 1e-3:g} m)" if d * 1e-3 < radius else "")
        raise InputError(f"{where}: a deflection of {d:g} m is not below the diameter "
                         f"{diameter:g} m of {part}{hint}")
    if d > radius:
        raise InputError(f"{where}: a deflection of {d:g} m is above the radius {radius:g} m of "
                         f"{part}; the FE compression goes to half the diameter at most "
                         f"(allowed (0, {radius:g}] m)")
    from ..balls.checks import check_force_units
    from ..fe.compression import check_compression_input

    try:  # the rest (platen rate, increments) as `compress` checks it
        check_compression_input(ball, d, test.rate_m_s, test.steps)
    except InputError as error:
        raise InputError(f"{where}: {error}") from None
    # a force in kN under a force_n header (or N under force_kn): no sports ball's stiffness
    check_force_units(float(test.force_n[-1]), d, radius,
                      f"{where}: the force at the largest deflection")


def compression_run(test: CompressionTest, ball, options, progress=None):
    """The FE curve (`CompressionResult`) of `ball` for the test: to its largest deflection in
    `test.steps` increments, at its platen rate."""
    from ..fe.compression import compress

    return compress(ball, test.max_deflection_m, rate_m_s=test.rate_m_s, steps=test.steps,
                    options=options, progress=progress)


def force_residuals(test: CompressionTest, result) -> np.ndarray:
    """(F_model(D_k) - F_k) / (F_peak sqrt(K)) over the measured points: their sum of squares is
    the NRMSE squared."""
    scale = 1.0 / (test.peak_force_n * math.sqrt(len(test.force_n)))
    return (result.force_at(test.deflection_m) - test.force_n) * scale


def compare_compression(test: CompressionTest, result) -> dict[str, float]:
    """The comparison of an FE curve with the test: force NRMSE (fraction of the measured peak)
    and the relative error of the force at the largest deflection."""
    r = force_residuals(test, result)
    model_end = float(result.force_at(test.max_deflection_m))
    return {"compression_nrmse": float(math.sqrt(r @ r)),
            "end_force_relative_error": model_end / float(test.force_n[-1]) - 1.0
            if test.force_n[-1] > 0 else math.nan}


# ---- Levenberg-Marquardt with a finite-difference Jacobian ------------------------------------

def refine_compression(problem, options, start: np.ndarray | None = None,
                       max_evaluations: int = 30, progress=None):
    """Bounded Levenberg-Marquardt (`gradient.levenberg_marquardt`) on the force residuals of
    every compression test of `problem`, the Jacobian by central differences of step `FD_STEP`
    in the unit coordinates (one-sided, second order, on a bound). Standard errors as the impact
    refinement's (`identifiability.standard_errors`)."""
    from ..fe import load_ball
    from ..identifiability import correlation_factor, identification_notes, standard_errors
    from .problem import sub_ball

    started = time.perf_counter()
    u0 = np.clip(problem.start_unit() if start is None else np.asarray(start, float), 0.0, 1.0)
    counts = {"value": 0, "jacobian": 0, "solves": 0}
    history: list[float] = []
    size: dict[str, int] = {}

    def curves(u):
        spec = problem.spec(u)
        out = []
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", InputWarning)
            for test in problem.tests:
                ball = load_ball(sub_ball(spec, test.layers), allow=problem.allow)
                out.append(compression_run(test, ball, options))
                counts["solves"] += 1
        return out

    def raw(u):
        try:
            runs = curves(u)
        except (InputError, SimulationError):  # not a valid ball, or no equilibrium: rejected
            if "m" not in size:
                raise
            return np.full(size["m"], np.inf)
        r = np.concatenate([force_residuals(t, c) for t, c in zip(problem.tests, runs)])
        size["m"] = len(r)
        return r

    def residuals(u):
        counts["value"] += 1
        r = raw(u)
        history.append(float(r @ r))
        if progress is not None:
            progress(len(history), history[-1])
        return r

    def jacobian(u):
        counts["jacobian"] += 1
        columns = []
        for j in range(len(u)):
            e = np.zeros(len(u))
            e[j] = FD_STEP
            if u[j] - FD_STEP >= 0.0 and u[j] + FD_STEP <= 1.0:
                col = (raw(u + e) - raw(u - e)) / (2 * FD_STEP)
            elif u[j] - FD_STEP < 0.0:
                col = (-3 * raw(u) + 4 * raw(u + e) - raw(u + 2 * e)) / (2 * FD_STEP)
            else:
                col = (3 * raw(u) - 4 * raw(u - e) + raw(u - 2 * e)) / (2 * FD_STEP)
            columns.append(col)
        return np.stack(columns, axis=1)

    u, r, jac, message = levenberg_marquardt(residuals, jacobian, u0, max_evaluations)
    runs = curves(u)
    ends = np.cumsum([len(test.force_n) for test in problem.tests])[:-1]
    correlation = correlation_factor(np.split(r, ends))  # each curve's residuals in order
    sigma = standard_errors(jac, r, correlation=correlation)
    values = problem.values(u)
    error, interval = parameter_errors(problem, u, sigma)
    m, n = jac.shape
    notes = identification_notes(values, error, "the tests do not determine it" if m > n else
                                 f"{m} measured points for {n} parameters leave none to "
                                 "estimate the noise from")
    for note in notes.values():
        warnings.warn(note, InputWarning, stacklevel=2)
    return CompressionRefinement(
        u, values, float(r @ r), history[0], error, interval, counts["value"],
        counts["jacobian"], time.perf_counter() - started, history, message, runs, 1,
        list(notes), residual_correlation=correlation, jacobian_method="central differences",
        solves=counts["solves"])


@dataclass
class CompressionRefinement(Refinement):
    """A refinement against compression tests: its Jacobian by finite differences, so its FE
    runs are counted as the compression solves made (each Jacobian costs 2 per parameter and
    test)."""

    jacobian_method: str = "central differences"
    solves: int = 0

    @property
    def fe_runs(self) -> int:
        return self.solves

    def to_dict(self) -> dict[str, Any]:
        return {**super().to_dict(), "jacobian": self.jacobian_method, "fd_step_unit": FD_STEP}
