"""Gradients of a smooth misfit through the whole explicit run, and a bounded Levenberg-Marquardt
refinement with them.

Why a separate misfit: contact time, separation and the peak are picked from the run by
thresholds and maxima, so they are piecewise constant or kinked in the parameters. The smooth
misfit compares the whole force curve on a fixed time window instead, with a fixed number of steps
of a fixed increment, per test:

    residuals = [(F_model(t_k + s) - F_test(t_k)) / (F_test,peak sqrt(K)) for the test's samples
                 t_k in [-5%, WINDOW] x its contact time]   (sum of squares: an NRMSE^2)
              + [COR_WEIGHT (v_model(T) / v_in - COR_test)]   (v the centre-of-mass velocity)

with s the time shift between the two pulses' zeros, fitted with the parameters. A pulse too long
or too short, or too high, misses the test's samples, so contact time and peak force are in the
force residuals; COR is a residual of its own (the centre-of-mass velocity after separation is
constant, so it is smooth in the parameters). Only the objectives asked for enter: the force
residuals with any of nrmse/contact_time/peak_force, COR with cor.

The increment is held fixed (the standard solver shrinks it in 2% levels as the ball stiffens,
which would make the misfit jump): the smallest increment of the start design's run, scaled down
by `INCREMENT_MARGIN`. A step to a design so much stiffer that this increment is unstable blows
the misfit up and is rejected; when the refined design needs a smaller increment, another pass
starts from it with its own (at most `PASSES`). Every other per-ball array of the step (masses,
contact and hourglass stiffnesses, bulk viscosity, the instantaneous constants) follows the
parameters: their map from the parameters (closed-form, NumPy) enters by its value and its
Jacobian (central differences, exact to ~1e-9 relative in float64), the FE run by JAX.

Derivatives: forward mode (`jax.jacfwd`, one tangent per parameter, memory of one state each) for
the Gauss-Newton Jacobian; reverse mode (`jax.grad`) for the scalar misfit, with each chunk of
`CHUNK_STEPS` steps under `jax.checkpoint` so that only the chunk boundaries are stored.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
from jax.flatten_util import ravel_pytree

from ..errors import InputError, InputWarning, SimulationError
from ..identifiability import correlation_factor, identification_notes, standard_errors
from ..comparison import max_shift_s
from ..fe.driver import fixed_increment_run
from ..fe.axi.kernel import HISTORY
from .problem import CalibrationProblem, CalibrationTest, sub_ball

CHUNK_STEPS = 100
#: the history's columns the misfit reads: contact force (N), centre-of-mass velocity (m/s)
COLUMNS = (HISTORY.index("contact_force_n"), HISTORY.index("centre_velocity_z_m_s"))
#: the misfit's window, as a multiple of the test's contact time
WINDOW = 1.25
#: COR error counted like this fraction of force NRMSE (1: a COR error of 0.01 as 1% NRMSE)
COR_WEIGHT = 1.0
#: step of the central differences of the parameter map (unit coordinates)
MAP_STEP = 1e-6
#: the fixed increment as a fraction of the smallest increment of the design's standard run
INCREMENT_MARGIN = 0.9
#: at most this many passes of Levenberg-Marquardt, each with the increment of its start design
PASSES = 3


@dataclass(frozen=True, eq=False)
class SmoothMisfit:
    """The smooth misfit of one test: fixed increment and window, the test sampled on it."""

    problem: CalibrationProblem
    test: CalibrationTest
    options: Any
    increment_s: float
    n_chunks: int
    times_s: np.ndarray      # the test's samples in the window (from contact start)
    force_n: np.ndarray      # the test's force there
    use_force: bool
    use_cor: bool
    _fn: dict = field(default_factory=dict, repr=False)

    @cached_property
    def kernel(self):
        """The compiled-program data of the test's ball (one structure for every design)."""
        from ..fe.engine import Axisymmetric, kernel_for

        return kernel_for(self._ball(self.problem.start_unit()), Axisymmetric(self.options))[0]

    def _ball(self, u):
        from ..fe import load_ball

        return load_ball(sub_ball(self.problem.spec(u), self.test.layers),
                         allow=self.problem.allow)

    def _flat_params(self, u) -> np.ndarray:
        from ..fe.axi.kernel import ball_arrays

        arrays = ball_arrays(self._ball(u), self.kernel.geom, self.options)
        return np.asarray(ravel_pytree(arrays)[0], np.float64)

    def linearised(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(value, Jacobian (n_values, n_free)) of the flattened per-ball arrays at u."""
        p0 = self._flat_params(u)
        columns = []
        for j in range(len(u)):
            e = np.zeros(len(u))
            e[j] = MAP_STEP
            if u[j] + MAP_STEP <= 1.0 and u[j] - MAP_STEP >= 0.0:
                col = (self._flat_params(u + e) - self._flat_params(u - e)) / (2 * MAP_STEP)
            elif u[j] - MAP_STEP < 0.0:  # one-sided, second order, at the lower bound
                col = (-3 * p0 + 4 * self._flat_params(u + e)
                       - self._flat_params(u + 2 * e)) / (2 * MAP_STEP)
            else:
                col = (3 * p0 - 4 * self._flat_params(u - e)
                       + self._flat_params(u - 2 * e)) / (2 * MAP_STEP)
            columns.append(col)
        return p0, np.stack(columns, axis=1)

    def residual_function(self):
        """residuals(du, p0, jacobian) -> (m,) in JAX, at u = u0 + du (p0, jacobian at u0)."""
        if "residuals" in self._fn:
            return self._fn["residuals"]
        kernel = self.kernel
        from ..fe.axi.kernel import ball_arrays

        template = ball_arrays(self._ball(self.problem.start_unit()), kernel.geom, self.options)
        unravel = ravel_pytree(template)[1]
        dt = self.increment_s
        speed = self.test.impact_speed_m_s
        values = self.test.features.values
        peak, cor = float(values["P6"]), float(values["P17"])
        scale = 1.0 / (peak * math.sqrt(len(self.times_s)))
        times = jnp.asarray(self.times_s)
        measured = jnp.asarray(self.force_n)
        n_steps = self.n_chunks * CHUNK_STEPS
        grid = jnp.arange(n_steps + 1) * dt
        use_force, use_cor = self.use_force, self.use_cor

        def residuals(du, p0, jacobian):
            # du: the parameters' change (unit coordinates), then the pulses' time shift (s)
            params = unravel(p0 + jacobian @ du[:-1])
            force, v_cm = fixed_increment_run(kernel, params, [speed], dt, self.n_chunks,
                                              CHUNK_STEPS, COLUMNS).T
            v_end = v_cm[-1]
            out = []
            if use_force:
                model = jnp.interp(times + du[-1], grid, jnp.concatenate([jnp.zeros(1), force]))
                out.append((model - measured) * scale)
            if use_cor:
                out.append(COR_WEIGHT * jnp.atleast_1d(v_end / speed - cor))
            return jnp.concatenate(out)

        self._fn["residuals"] = residuals
        return residuals

    def compiled(self, kind: str):
        """Jitted 'value' (residuals), 'jacobian' (jacfwd, with the residuals) or 'grad'
        (reverse-mode gradient of the sum of squares, with it)."""
        if kind not in self._fn:
            r = self.residual_function()
            if kind == "value":
                fn = r
            elif kind == "jacobian":
                def fn(du, p0, jac):
                    return r(du, p0, jac), jax.jacfwd(r)(du, p0, jac)
            else:
                fn = jax.value_and_grad(lambda du, p0, jac: jnp.sum(r(du, p0, jac) ** 2))
            self._fn[kind] = jax.jit(fn)
        return self._fn[kind]

    def evaluate(self, u: np.ndarray, kind: str = "value", shift_s: float = 0.0):
        """At unit coordinates u and a time shift (s) of the test's samples in the run's time:
        residuals; (residuals, Jacobian d r / d (u, shift)); or (sum of squares, its gradient
        d / d (u, shift)) -- NumPy, float64."""
        with jax.enable_x64(True):
            u = np.asarray(u, np.float64)
            if kind == "value":  # no derivatives: the parameter map's value is enough
                p0 = self._flat_params(u)
                jac = np.zeros((len(p0), len(u)))
            else:
                p0, jac = self.linearised(u)
            du = jnp.zeros(len(u) + 1).at[-1].set(shift_s)
            out = self.compiled(kind)(du, jnp.asarray(p0), jnp.asarray(jac))
            return jax.tree_util.tree_map(lambda x: np.asarray(x, np.float64), out)


def central_differences(misfit: SmoothMisfit, u: np.ndarray, h: float = 1e-5) -> np.ndarray:
    """Central differences (step h in unit coordinates) of a misfit's sum of squares: the check
    of its derivatives."""
    out = []
    for j in range(len(u)):
        e = np.zeros(len(u))
        e[j] = h
        plus, minus = misfit.evaluate(u + e), misfit.evaluate(u - e)
        out.append((plus @ plus - minus @ minus) / (2 * h))
    return np.array(out)


def standard_runs(problem: CalibrationProblem, u: np.ndarray, options) -> list:
    """The FE runs (standard solver) of the design at unit coordinates u, one per test: the
    quasi-static curve (`fe.compress`) of a compression test."""
    from ..fe import load_ball

    spec = problem.spec(u)
    return [test.fe_run(load_ball(sub_ball(spec, test.layers), allow=problem.allow), options,
                        allow=problem.allow) for test in problem.tests]


def smooth_misfits(problem: CalibrationProblem, options, runs: list) -> list[SmoothMisfit]:
    """One `SmoothMisfit` per test, its increment `INCREMENT_MARGIN` times the smallest of the
    design's standard run (`runs`, one per test). The test's times count from its contact start
    as its processing found it, the run's from the first touch; the time shift between them is
    the aligned NRMSE's (`comparison.aligned_nrmse`)."""
    if options.precision != "float64":
        raise InputError("gradient refinement: needs precision float64 (gradients in float32 "
                         "are dominated by round-off over thousands of steps)")
    use_force = any(o in problem.objectives for o in ("nrmse", "contact_time", "peak_force"))
    use_cor = "cor" in problem.objectives
    out = []
    for test, fe in zip(problem.tests, runs):
        dt = INCREMENT_MARGIN * fe.final_time_increment_s
        t_pulse, f_pulse = test.pulse
        window = WINDOW * float(test.features.values["P1"])
        spacing = float(np.median(np.diff(t_pulse)))
        first = -int(math.ceil(max_shift_s(test) / spacing))  # samples before the start too
        times = np.arange(first, int(window / spacing) + 1) * spacing
        force = np.interp(times, t_pulse, f_pulse, left=0.0, right=0.0)
        # the run covers the window at any shift
        n_chunks = int(math.ceil((window + max_shift_s(test)) / dt / CHUNK_STEPS))
        out.append(SmoothMisfit(problem, test, options, dt, n_chunks, times, force,
                                use_force, use_cor))
    return out


@dataclass
class Refinement:
    """A Levenberg-Marquardt refinement's result."""

    unit: np.ndarray
    values: dict[str, float]
    misfit: float                 # sum of squares of the residuals
    start_misfit: float
    standard_error: dict[str, float]   # SI, from s^2 (J^T J)^-1; inf where undetermined
    interval_95: dict[str, tuple[float, float]]
    residual_evaluations: int     # runs of every test (one each)
    jacobian_evaluations: int     # forward-mode runs of every test
    wall_time_s: float
    history: list[float] = field(default_factory=list)
    message: str = ""
    runs: list = field(default_factory=list, repr=False)  # standard FE runs of the result
    passes: int = 1
    #: parameters with an infinite standard error or one larger than their value
    not_identified: list[str] = field(default_factory=list)
    #: the factor on the variances for correlated residuals (`identifiability.correlation_factor`)
    residual_correlation: float = 1.0

    @property
    def fe_runs(self) -> int:
        """FE runs of every test: fixed-increment misfits, forward-mode Jacobians (each counted
        as one run, though it carries a tangent per parameter and the time shift: compare wall
        times too), and the standard runs at the start and after each pass."""
        n_tests = len(self.runs)
        return (self.residual_evaluations + self.jacobian_evaluations + self.passes + 1) * n_tests

    def to_dict(self) -> dict[str, Any]:
        return {"values": self.values, "misfit": self.misfit, "start_misfit": self.start_misfit,
                "standard_error": self.standard_error, "not_identified": self.not_identified,
                "interval_95": {k: list(v) for k, v in self.interval_95.items()},
                "residual_evaluations": self.residual_evaluations,
                "jacobian_evaluations": self.jacobian_evaluations,
                "fe_runs": self.fe_runs, "passes": self.passes,
                "wall_time_s": self.wall_time_s,
                "misfit_history": self.history, "message": self.message,
                "residual_correlation": self.residual_correlation}


def refine(problem: CalibrationProblem, options, start: np.ndarray | None = None,
           max_evaluations: int = 30, progress=None) -> Refinement:
    """Bounded Levenberg-Marquardt on the smooth misfit of every test from `start` (unit
    coordinates; default the problem's start), with the Jacobian from forward-mode derivatives
    through the FE runs. `progress(evaluation, misfit)` after each misfit evaluation."""
    started = time.perf_counter()
    u = np.clip(problem.start_unit() if start is None else np.asarray(start, float), 0.0, 1.0)
    counts = {"value": 0, "jacobian": 0}
    history: list[float] = []
    runs = standard_runs(problem, u, options)
    start_misfit = None
    n = len(u)
    w = np.full(len(problem.tests), 0.5)  # the time shifts, in unit coordinates of +/- max
    for passes in range(1, PASSES + 1):
        misfits = smooth_misfits(problem, options, runs)
        shifts = np.array([max_shift_s(m.test) for m in misfits])
        size = {}

        def residuals(x, misfits=misfits, shifts=shifts, size=size):
            counts["value"] += 1
            try:
                r = np.concatenate([m.evaluate(x[:n], "value", (2 * w - 1) * s)
                                    for m, w, s in zip(misfits, x[n:], shifts)])
            except InputError:  # not a valid ball (e.g. C10 + C01 <= 0): a rejected step
                if "m" not in size:
                    raise
                return np.full(size["m"], np.inf)
            size["m"] = len(r)
            history.append(float(r @ r))
            if progress is not None:
                progress(len(history), history[-1])
            return r

        def jacobian(x, misfits=misfits, shifts=shifts):
            counts["jacobian"] += 1
            blocks = []
            for i, (m, w, s) in enumerate(zip(misfits, x[n:], shifts)):
                j = m.evaluate(x[:n], "jacobian", (2 * w - 1) * s)[1]
                block = np.zeros((len(j), n + len(misfits)))
                block[:, :n] = j[:, :-1]
                block[:, n + i] = 2 * s * j[:, -1]
                blocks.append(block)
            return np.concatenate(blocks)

        budget = max_evaluations - counts["value"]
        x, r, jac, message = levenberg_marquardt(residuals, jacobian, np.concatenate([u, w]),
                                                 max(budget, 1))
        u, w = x[:n], x[n:]
        start_misfit = history[0] if start_misfit is None else start_misfit
        runs = standard_runs(problem, u, options)
        # the increment used stays within 5% of the refined design's own: done
        if all(m.increment_s <= 0.95 * fe.final_time_increment_s
               for m, fe in zip(misfits, runs)) or counts["value"] >= max_evaluations:
            break
    correlation = correlation_factor(force_residuals(misfits, r))
    # the time shifts are in the covariance
    sigma_u = standard_errors(jac, r, correlation=correlation)[:len(u)]
    values = problem.values(u)
    error, interval = parameter_errors(problem, u, sigma_u)
    m, n_unknowns = jac.shape
    notes = identification_notes(values, error, "the tests do not determine it"
                                 if m > n_unknowns else f"{m} residuals for {n_unknowns} "
                                 "unknowns (parameters and time shifts) leave none to estimate "
                                 "the noise from")
    for note in notes.values():  # the calibration's result has no other place for the note
        warnings.warn(note, InputWarning, stacklevel=2)
    return Refinement(u, values, float(r @ r), start_misfit, error, interval, counts["value"],
                      counts["jacobian"], time.perf_counter() - started, history, message, runs,
                      passes, list(notes), residual_correlation=correlation)


def force_residuals(misfits: list, r: np.ndarray) -> list[np.ndarray]:
    """Each test's force residuals (its pulse's samples in time) out of the concatenated
    residuals of `misfits` (each: its force residuals if it uses them, then its COR one)."""
    blocks, start = [], 0
    for m in misfits:
        n_force = len(m.times_s) if m.use_force else 0
        blocks.append(r[start:start + n_force])
        start += n_force + int(m.use_cor)
    return [b for b in blocks if b.size]


def parameter_errors(problem: CalibrationProblem, u: np.ndarray, sigma_u: np.ndarray
                     ) -> tuple[dict[str, float], dict[str, tuple[float, float]]]:
    """Standard errors (SI) and 95% intervals of the parameters from the standard errors
    `sigma_u` of their unit coordinates `u`."""
    values = problem.values(u)
    error, interval = {}, {}
    for p, s, x in zip(problem.free, sigma_u, u):
        value = values[p.path]
        # d value / d u: the span for a linear scale, value ln(high/low) for a log one
        slope = value * math.log(p.high / p.low) if p.scale == "log" else p.high - p.low
        error[p.path] = float(abs(slope) * s)
        # the interval in unit coordinates (a log-scale one stays positive; an undetermined
        # parameter's is unbounded)
        with np.errstate(invalid="ignore", over="ignore"):
            interval[p.path] = (float(p.from_unit(x - 1.96 * s)),
                                float(p.from_unit(x + 1.96 * s)))
    return error, interval


def levenberg_marquardt(residuals, jacobian, u0: np.ndarray, max_evaluations: int,
                        tolerance: float = 1e-5):
    """Bounded Levenberg-Marquardt in unit coordinates: steps solve (J^T J + lambda D) du =
    -J^T r with D = diag(J^T J) (Marquardt's scaling, which follows the narrow valleys of
    parameters that trade off against each other) for the coordinates not held on a bound,
    projected onto [0, 1]; lambda shrinks after an
    accepted step and grows after a rejected one (which costs no new Jacobian).
    Returns (u, residuals, Jacobian at u, why it stopped)."""
    u = u0.copy()
    r = residuals(u)
    if not np.all(np.isfinite(r)):
        raise SimulationError("gradient refinement: the start design's fixed-increment run is "
                              "not finite")
    evaluations, lam = 1, 1e-2
    jac = jacobian(u)
    while True:
        grad = jac.T @ r
        normal = jac.T @ jac
        scale = np.maximum(np.diag(normal), 1e-12 * max(np.max(np.diag(normal)), 1e-300))
        # projected gradient: the first-order optimality at the bounds
        projected = u - np.clip(u - grad, 0.0, 1.0)
        if np.max(np.abs(projected)) < 1e-10 * max(r @ r, 1e-300):
            return u, r, jac, "gradient zero (first-order optimal within the bounds)"
        if evaluations >= max_evaluations:
            return u, r, jac, f"stopped at {max_evaluations} misfit evaluations"
        # coordinates on a bound that the gradient pushes outward stay there (active set):
        # projecting a step that moves them would not be a descent step of the model
        free = ~(((u <= 0.0) & (grad > 0)) | ((u >= 1.0) & (grad < 0)))
        step = np.zeros_like(u)
        step[free] = np.linalg.solve((normal + lam * np.diag(scale))[np.ix_(free, free)],
                                     -grad[free])
        trial = np.clip(u + step, 0.0, 1.0)
        r_trial = residuals(trial)
        evaluations += 1
        if np.all(np.isfinite(r_trial)) and r_trial @ r_trial < r @ r:
            gain = (r @ r - r_trial @ r_trial) / (r @ r)
            moved = np.max(np.abs(trial - u))
            u, r = trial, r_trial
            lam = max(lam / 3.0, 1e-9)
            if gain < tolerance or moved < tolerance:
                return u, r, jacobian(u), "converged (relative misfit change or step < 1e-5)"
            jac = jacobian(u)
        else:
            lam *= 4.0
            if lam > 1e8:
                return u, r, jac, "no decrease along the steepest descent (lambda > 1e8)"
