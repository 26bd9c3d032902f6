"""Identify a lumped model from a measured impact: a genetic algorithm or differential evolution
(pymoo) over the whole search box, then a bounded least-squares polish.

Fitness (minimised): sqrt(NRMSE^2 + (w_cor dCOR)^2 + (w_tc dT_c / T_c)^2), with NRMSE the RMS
force error over the comparison window (and the zero force after it) divided by the measured peak
force; with the default zero
weights it is the NRMSE of the force curve (the thesis' RMSE fitness, made dimensionless).

The comparison window runs from just before the measured contact start to a quarter of the contact
time after its end, on the record's own samples, so a model pulse that is too long is penalised;
beyond it, to the end of the model's grid (1.6 contact times), the model's force is compared with
zero at the record's spacing (the test's ball has left), so that a pulse cannot run on unseen.
The model's first contact (`onset_s`) is searched too, within 5% of the contact time (at least
two samples) of the measured start: a sampled record locates it only to within a sample, and noise
raises the contact threshold, which moves the measured start by several.

Parameters are searched in a box mapped to [0, 1]: `linear` or `log` between bounds, power-law
stiffnesses as the force k y_ref^alpha at the measured maximum compression y_ref (their scale
otherwise changes by orders of magnitude with the exponent), unit masses as shares of the ball mass
still to give out. Bounds given by the user are in the parameter's own units (unit masses take
none: fix one in kg or leave it free) and a stiffness with user bounds is searched as log k
directly; `FitResult.bounds` reports the searched box in the same units, so it can be passed back.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import least_squares

from ..checks import check_integer, check_range, shown
from ..errors import InputError, InputWarning
from ..identifiability import identification_notes, standard_errors
from ..records.pipeline import ProcessedImpact, process
from ..records.record import ImpactRecord, sample_rate_hz
from .base import BatchResult, LumpedModel, Scale
from .registry import get_model
from .simulate import sample_on

METHODS = ("ga", "de")
#: integration steps per measured contact time (RK4: relative error ~1e-8; linear interpolation
#: between steps ~1e-4 of the peak), and the grid's length in contact times
FIT_STEPS_PER_CONTACT = 250
FIT_GRID_CONTACTS = 1.6
TAIL_FRACTION = 0.25  # of the contact time, compared after the measured end
ONSET_SLACK_FRACTION = 0.05  # of the contact time: model onset searched this far around the start
_FD_STEP = 1e-6  # finite-difference step in the unit box
#: fitness of a model that has not left the surface by the end of its grid (see `_Objective`)
STUCK_PENALTY = 0.1


@dataclass(frozen=True)
class Gene:
    name: str
    low: float
    high: float
    kind: str  # linear | log | stiffness | mass_share
    exponent: str | float | None = None

    def value(self, u: np.ndarray) -> np.ndarray:
        if self.kind in ("log", "stiffness"):
            return np.exp(np.log(self.low) + u * (np.log(self.high) - np.log(self.low)))
        return self.low + u * (self.high - self.low)


@dataclass
class FitResult:
    """A fitted model. `params` and `units` in SI; `standard_errors` what the record's noise
    leaves uncertain in each parameter (linearised, same units; inf for a parameter the pulse does
    not determine at all, 0 for a fixed one); `not_identified` the parameters whose standard
    error is inf or larger than their value, with a note each (`notes`); `rmse_n` the RMS force
    error (N) and `nrmse` it divided by the measured peak force; `history_best` /
    `history_mean` the best and the mean fitness of each generation; `fitted_force_n` the
    model's force on the record's samples. `bounds` is the searched box in the parameters' own
    units (see `reported_bounds`), which `bounds=` takes back."""

    model: str
    params: dict[str, float]
    units: dict[str, str]
    standard_errors: dict[str, float]
    rmse_n: float
    nrmse: float
    fitness: float
    onset_s: float
    contact_time_s: float
    cor: float
    peak_force_n: float
    measured: dict[str, float]
    method: str
    seed: int
    population: int
    generations: int
    evaluations: int
    polished: bool
    history_best: list[float]
    history_mean: list[float]
    bounds: dict[str, dict[str, Any]]
    weights: dict[str, float]
    wall_time_s: float
    time_s: np.ndarray = field(repr=False)
    measured_force_n: np.ndarray = field(repr=False)
    fitted_force_n: np.ndarray = field(repr=False)
    reproduction: bool = False
    #: parameter -> "k1: not identified (standard error ... > value ...)"
    #: (`identifiability.identification_notes`)
    notes: dict[str, str] = field(default_factory=dict)

    @property
    def not_identified(self) -> list[str]:
        return list(self.notes)

    def to_dict(self) -> dict[str, Any]:
        """JSON-able, with the command-line contract's keys (`model`, `params`, `units`, `rmse_n`,
        `nrmse`, `wall_time_s`)."""
        return {
            "model": self.model, "params": self.params, "units": self.units,
            "standard_errors": self.standard_errors, "not_identified": self.not_identified,
            "notes": list(self.notes.values()),
            "rmse_n": self.rmse_n, "nrmse": self.nrmse, "fitness": self.fitness,
            "wall_time_s": self.wall_time_s, "onset_s": self.onset_s,
            "contact_time_s": self.contact_time_s, "cor": self.cor,
            "peak_force_n": self.peak_force_n, "measured": self.measured,
            "method": self.method, "seed": self.seed, "population": self.population,
            "generations": self.generations, "evaluations": self.evaluations,
            "polished": self.polished, "weights": self.weights, "bounds": self.bounds,
            "history": {"best_fitness": self.history_best, "mean_fitness": self.history_mean},
            "reproduction": self.reproduction,
        }


def _number(label: str, value: Any) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{label}: must be a number in SI, got {shown(value)}") from None
    if not np.isfinite(number):
        raise InputError(f"{label}: must be finite, got {shown(value)}")
    return number


def _pair(label: str, value: Any) -> tuple[float, float]:
    if isinstance(value, (str, bytes)) or np.ndim(value) != 1 or len(value) != 2:
        raise InputError(f"{label}: must be a (low, high) pair in SI, got {shown(value)}")
    return _number(label, value[0]), _number(label, value[1])


def _checked(model: LumpedModel, probe: dict[str, float], label: str) -> None:
    try:
        model.check(probe, None)
    except InputError as error:
        raise InputError(f"{label}: {error}") from None


def search_genes(model: LumpedModel, scale: Scale, bounds: dict | None, fixed: dict | None):
    """The searched genes and the fixed values, checked against the model's parameters and
    ranges (a fixed value or a bound that the model refuses is an error naming it)."""
    bounds = {name: _pair(f"bounds.{name}", v) for name, v in (bounds or {}).items()}
    fixed = {name: _number(f"fixed.{name}", v) for name, v in (fixed or {}).items()}
    names = set(model.parameter_names)
    for label, given in (("bounds", bounds), ("fixed", fixed)):
        unknown = sorted(set(given) - names)
        if unknown:
            raise InputError(f"{label}: unknown parameter(s) {', '.join(unknown)} for model "
                             f"{model.name!r}; it has {', '.join(model.parameter_names)}")
    both = sorted(set(bounds) & set(fixed))
    if both:
        raise InputError(f"bounds: {', '.join(both)} cannot be both bounded and fixed")
    masses = [p for p in model.parameters if p.search in ("mass_share", "mass_rest")]
    for p in masses:
        if p.search == "mass_rest" and (p.name in bounds or p.name in fixed):
            label = "bounds" if p.name in bounds else "fixed"
            raise InputError(f"{label}.{p.name}: the last unit mass is the rest of the ball mass; "
                             "fix the others (kg) or leave them free")
        if p.name in bounds:
            raise InputError(f"bounds.{p.name}: unit masses are searched as shares of the ball "
                             "mass; fix one in kg or leave it free")
    given_mass = sum(fixed.get(p.name, 0.0) for p in masses)
    if masses and given_mass >= scale.mass_kg:
        raise InputError(f"fixed: unit masses of {given_mass:.6g} kg leave nothing of the ball "
                         f"mass {scale.mass_kg:.6g} kg for the last unit")
    defaults = model.default_bounds(scale)
    genes, probe = [], {}
    free_masses = [p for p in masses if p.name not in fixed]
    for p in model.parameters:
        if p in free_masses:
            probe[p.name] = (scale.mass_kg - given_mass) / len(free_masses)
        if p.name in fixed or p.search == "mass_rest" or (p.fixed and p.name not in bounds):
            if p.search != "mass_rest":
                fixed.setdefault(p.name, p.default)
                probe[p.name] = fixed[p.name]
            continue
        kind = p.search
        if p.name in bounds:
            low, high = bounds[p.name]
            kind = "log" if kind == "stiffness" else kind
        else:
            low, high = defaults[p.name]
        if not low < high:
            raise InputError(f"bounds.{p.name}: need low < high, got {shown((low, high))}")
        if kind in ("log", "stiffness"):
            check_range(f"bounds.{p.name} low", low, 0.0, low_open=True,
                        note="searched on a log scale")
        if kind != "mass_share":
            probe[p.name] = 1.0 if kind == "stiffness" else 0.5 * (low + high)
        genes.append(Gene(p.name, low, high, kind, p.exponent))
    if not genes:
        raise InputError("fixed: every parameter is fixed; nothing to fit")
    _checked(model, probe, "fixed")
    for name, ends in bounds.items():
        for end in ends:
            _checked(model, {**probe, name: end}, f"bounds.{name}")
    return genes, fixed


def reported_bounds(model: LumpedModel, genes: list[Gene], params: dict[str, float],
                    scale: Scale) -> dict[str, dict[str, Any]]:
    """The searched box in each parameter's own units (those of `model.units`, the units that
    `bounds` takes), so that it can be passed back: a power-law stiffness searched as the force
    at the reference compression y_ref has the force bounds divided by y_ref^alpha at the fitted
    exponent (the force bounds and y_ref are given too); a unit mass is searched as a share of
    the mass still to give out, so its bounds are shares (unit "share")."""
    units = model.units
    reported = {}
    for gene in genes:
        entry = {"low": float(gene.low), "high": float(gene.high), "search": gene.kind,
                 "unit": units[gene.name]}
        if gene.kind == "stiffness":
            exponent = gene.exponent if isinstance(gene.exponent, float) \
                else params[gene.exponent]
            reference = float(scale.max_compression_m) ** exponent
            entry.update(low=entry["low"] / reference, high=entry["high"] / reference,
                         force_low_n=entry["low"], force_high_n=entry["high"],
                         reference_compression_m=float(scale.max_compression_m))
        elif gene.kind == "mass_share":
            entry["unit"] = "share"
        reported[gene.name] = entry
    return reported


def decode(model: LumpedModel, genes: list[Gene], fixed: dict[str, float], u: np.ndarray,
           scale: Scale) -> np.ndarray:
    """Unit-box points (B, len(genes)) -> parameter vectors (B, P) in the model's order."""
    u = np.atleast_2d(u)
    values: dict[str, np.ndarray] = {k: np.full(u.shape[0], v) for k, v in fixed.items()}
    for j, gene in enumerate(genes):
        if gene.kind in ("linear", "log"):
            values[gene.name] = gene.value(u[:, j])
    remaining = np.full(u.shape[0], scale.mass_kg)
    for p in model.parameters:  # unit masses in order, then the rest
        if p.search == "mass_share":
            if p.name not in values:
                j = next(i for i, g in enumerate(genes) if g.name == p.name)
                values[p.name] = remaining * genes[j].value(u[:, j])
            remaining = remaining - values[p.name]
        elif p.search == "mass_rest":
            values[p.name] = remaining
    for j, gene in enumerate(genes):
        if gene.kind == "stiffness":
            exponent = gene.exponent if isinstance(gene.exponent, float) else values[gene.exponent]
            values[gene.name] = gene.value(u[:, j]) / scale.max_compression_m**exponent
    return np.stack([values[name] for name in model.parameter_names], axis=1)


class _Objective:
    """Residuals of a batch of unit-box points against the measured pulse."""

    def __init__(self, model, processed: ProcessedImpact, genes, fixed, scale, weights):
        self.model, self.genes, self.fixed, self.scale = model, genes, fixed, scale
        self.weights = weights
        record, features = processed.filtered, processed.features
        window = features.window
        self.peak = features.values["P6"]
        self.contact = features.values["P1"]
        self.cor = features.values["P17"]
        # noise raises the contact threshold, which can move the measured start by samples
        slack = max(2.0 / sample_rate_hz(record), ONSET_SLACK_FRACTION * self.contact)
        self.onset = (window.start_s - slack, window.start_s + slack)
        keep = ((record.time_s >= self.onset[0])
                & (record.time_s <= window.end_s + TAIL_FRACTION * self.contact))
        self.time, self.force = record.time_s[keep], record.force_n[keep]
        self.step = self.contact / FIT_STEPS_PER_CONTACT
        self.steps = int(FIT_GRID_CONTACTS * FIT_STEPS_PER_CONTACT)
        # after the window the test's ball has left: the model's force there, at the record's
        # spacing up to the end of the model's grid, is compared with zero. Without it a model
        # whose pulse runs on at a few percent of the peak beyond the window (a soft unit of the
        # three-element model) fits as well as one that ends, and its COR is far off.
        spacing = 1.0 / sample_rate_hz(record)
        self.after = np.arange(self.time[-1] + spacing,
                               self.onset[0] + FIT_GRID_CONTACTS * self.contact, spacing)
        self.evaluations = 0

    def split(self, u: np.ndarray):
        u = np.atleast_2d(u)
        onset = self.onset[0] + u[:, -1] * (self.onset[1] - self.onset[0])
        return decode(self.model, self.genes, self.fixed, u[:, :-1], self.scale), onset

    def run(self, u: np.ndarray) -> tuple[BatchResult, np.ndarray, np.ndarray]:
        params, onset = self.split(u)
        batch = self.model.run_batch(params, self.scale.mass_kg, self.scale.impact_speed_m_s,
                                     self.step, self.steps)
        self.evaluations += params.shape[0]
        force = sample_on(batch, self.time[None, :] - onset[:, None])
        return batch, force, onset

    def residuals(self, u: np.ndarray) -> np.ndarray:
        batch, force, onset = self.run(u)
        norm = self.peak * np.sqrt(self.force.size)
        scaled = (force - self.force) / norm
        after = sample_on(batch, self.after[None, :] - onset[:, None]) / norm
        # a run that has not left the surface within the grid counts as a unit error
        errors = {"cor": batch.rebound_speed_m_s / self.scale.impact_speed_m_s - self.cor,
                  "contact_time": batch.contact_time_s / self.contact - 1.0}
        extra = [(self.weights[k] * np.where(np.isfinite(e), e, 1.0))[:, None]
                 for k, e in errors.items()]
        # a unit still touching at the grid's end would bring an impulse the fit never sees (a
        # light soft unit returns m v_in (1 + e) however small its force): it costs as much as
        # an NRMSE of STUCK_PENALTY, enough to be avoided, small enough to leave the search
        # informed (a unit cost flattens the landscape and worsened fits)
        stuck = STUCK_PENALTY * np.where(batch.separated, 0.0, 1.0)[:, None]
        residual = np.concatenate([scaled, after, stuck] + extra, axis=1)
        return np.where(np.isfinite(residual), residual, 1.0)

    def fitness(self, u: np.ndarray) -> np.ndarray:
        return np.sqrt(np.sum(self.residuals(u) ** 2, axis=1))


def _search(objective: _Objective, dimension: int, method: str, population: int,
            generations: int, seed: int):
    from pymoo.algorithms.soo.nonconvex.de import DE
    from pymoo.algorithms.soo.nonconvex.ga import GA
    from pymoo.core.callback import Callback
    from pymoo.core.problem import Problem
    from pymoo.operators.sampling.lhs import LHS
    from pymoo.optimize import minimize

    class _Problem(Problem):
        def __init__(self):
            super().__init__(n_var=dimension, n_obj=1, xl=0.0, xu=1.0)

        def _evaluate(self, x, out, *args, **kwargs):
            out["F"] = objective.fitness(x)

    class _History(Callback):
        def __init__(self):
            super().__init__()
            self.best, self.mean = [], []

        def notify(self, algorithm):
            self.best.append(float(algorithm.opt.get("F").min()))
            self.mean.append(float(np.mean(algorithm.pop.get("F"))))

    if method == "ga":
        algorithm = GA(pop_size=population, sampling=LHS(), eliminate_duplicates=True)
    else:
        algorithm = DE(pop_size=population, sampling=LHS(), variant="DE/rand/1/bin", CR=0.9,
                       F=0.6, dither="vector")
    history = _History()
    result = minimize(_Problem(), algorithm, ("n_gen", generations), seed=seed, callback=history,
                      verbose=False)
    return np.atleast_1d(result.X), history


def _difference_points(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Forward-difference steps (backward at the box's upper edge) and the batch [x, x + steps]."""
    steps = np.where(x + _FD_STEP <= 1.0, _FD_STEP, -_FD_STEP)
    return steps, np.vstack([x, x + np.diag(steps)])


def _polish(objective: _Objective, start: np.ndarray) -> np.ndarray:
    """Bounded least squares (trust-region reflective) from the search's best point; the
    Jacobian is a forward difference evaluated as one batch."""
    cache: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def evaluate(x):
        key = x.tobytes()
        if key not in cache:
            steps, points = _difference_points(x)
            rows = objective.residuals(points)
            cache.clear()
            cache[key] = (rows[0], ((rows[1:] - rows[0]) / steps[:, None]).T)
        return cache[key]

    x0 = np.clip(start, 1e-9, 1.0 - 1e-9)
    solution = least_squares(lambda x: evaluate(x)[0], x0, jac=lambda x: evaluate(x)[1],
                             bounds=(0.0, 1.0), method="trf", x_scale="jac", max_nfev=200,
                             ftol=1e-12, xtol=1e-12, gtol=1e-12)
    return solution.x


def _standard_errors(objective: _Objective, best: np.ndarray,
                     names: tuple[str, ...]) -> dict[str, float]:
    """Standard errors of the parameters (SI) at the unit-box point `best` (the onset included
    as a coordinate, so its trade-off with the parameters counts): `identifiability.
    standard_errors` of the force on the record's samples, mapped from the unit box to the
    parameters."""
    steps, points = _difference_points(best)
    _, force, _ = objective.run(points)
    jacobian = ((force[1:] - force[0]) / steps[:, None]).T  # (M, d) in N per unit box
    params = objective.split(points)[0]
    mapping = ((params[1:] - params[0]) / steps[:, None]).T  # (P, d)
    errors = standard_errors(jacobian, force[0] - objective.force, mapping)
    return dict(zip(names, (float(e) for e in errors)))


def fit(
    record: ImpactRecord | ProcessedImpact,
    model: str | LumpedModel = "single_element",
    *,
    method: str = "ga",
    population: int | None = None,
    generations: int | None = None,
    seed: int = 0,
    polish: bool = True,
    bounds: dict[str, tuple[float, float]] | None = None,
    fixed: dict[str, float] | None = None,
    cor_weight: float = 0.0,
    contact_time_weight: float = 0.0,
    filter: str = "none",
) -> FitResult:
    """Fit `model` to a measured impact (an `ImpactRecord`, processed here with `filter`, or an
    already `ProcessedImpact`). `method` is `ga` (pymoo GA: SBX crossover, polynomial mutation) or
    `de` (pymoo DE/rand/1/bin); `seed` makes it reproducible. `bounds` and `fixed` override the
    search box per parameter (SI; see the module notes); `cor_weight` and `contact_time_weight`
    add the COR error and the relative contact-time error to the fitness. `population` defaults to
    4 per searched quantity (at least 32), `generations` to 8 (at least 40)."""
    started = time.perf_counter()
    model = get_model(model)
    if method not in METHODS:
        raise InputError(f"method: must be one of {', '.join(METHODS)}, got {method!r}")
    searched = len(model.parameters) + 1  # with the onset; an upper bound when some are fixed
    population = max(32, 4 * searched) if population is None else population
    generations = max(40, 8 * searched) if generations is None else generations
    population = check_integer("population", population, 4)
    generations = check_integer("generations", generations, 1)
    seed = check_integer("seed", seed, 0)
    for name, value in (("cor_weight", cor_weight), ("contact_time_weight", contact_time_weight)):
        check_range(name, value, 0.0)
    processed = record if isinstance(record, ProcessedImpact) else process(record, filter=filter)
    features = processed.features
    scale = Scale(features.mass_kg, features.values["P15"], features.values["P1"],
                  features.values["P6"], features.max_compression_m)
    genes, fixed_values = search_genes(model, scale, bounds, fixed)
    weights = {"cor": float(cor_weight), "contact_time": float(contact_time_weight)}
    objective = _Objective(model, processed, genes, fixed_values, scale, weights)

    best, history = _search(objective, len(genes) + 1, method, int(population), int(generations),
                            int(seed))
    if polish:
        polished = _polish(objective, best)
        if objective.fitness(polished)[0] <= objective.fitness(best)[0]:
            best = polished
    batch, force, onset = objective.run(best)
    vector = objective.split(best)[0][0]
    params = dict(zip(model.parameter_names, (float(x) for x in vector)))
    errors = _standard_errors(objective, best, model.parameter_names)
    if not batch.separated[0]:
        warnings.warn(f"fit: the fitted {model.name} ball does not leave the surface within "
                      f"{FIT_GRID_CONTACTS:g} measured contact times; its COR and contact time "
                      "are not available", InputWarning, stacklevel=2)
    error = force[0] - objective.force
    rmse = float(np.sqrt(np.mean(error**2)))
    return FitResult(
        model=model.name, params=params, units=model.units, standard_errors=errors, rmse_n=rmse,
        nrmse=rmse / objective.peak, fitness=float(objective.fitness(best)[0]),
        onset_s=float(onset[0]), contact_time_s=float(batch.contact_time_s[0]),
        cor=float(batch.rebound_speed_m_s[0] / scale.impact_speed_m_s),
        peak_force_n=float(np.max(batch.force_n[0])),
        measured={"peak_force_n": objective.peak, "contact_time_s": objective.contact,
                  "cor": objective.cor, "impact_speed_m_s": scale.impact_speed_m_s,
                  "mass_kg": scale.mass_kg},
        method=method, seed=int(seed), population=int(population), generations=int(generations),
        evaluations=objective.evaluations, polished=bool(polish),
        history_best=history.best, history_mean=history.mean,
        bounds=reported_bounds(model, genes, params, scale),
        weights=weights, wall_time_s=time.perf_counter() - started,
        time_s=objective.time, measured_force_n=objective.force, fitted_force_n=force[0],
        reproduction=model.reproduction,
        notes=identification_notes(params, errors, "the record does not determine it"),
    )
