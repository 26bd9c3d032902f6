"""The models a report compares, and one model run against one test.

A model is named on the command line as
- a lumped model (`ballimpact models`): fitted to each test by the GA (`lumped.fit`);
- `universal`: identified from each test by the universal model (`universal.identify`), built-in
  unless another is given, and its FE ball run at the test's speed;
- a ball preset or ball file: run in the FE engine at each test's speed as it is (a calibrated
  "detailed" model: nothing is fitted).

Every model's pulse is compared with the test's as a calibration compares an FE run with a test
(`calibrate.evaluate`): the force NRMSE (`comparison.pulse_nrmse`, a fraction of the
test's peak) with the model's pulse from its first touch at the best time shift within 5% of the
test's contact time (a noisy test's contact start is uncertain by tens of microseconds), and the
peak force, contact time and COR of the model's pulse measured as the test's was (resampled at
its rate, linearly, and windowed at its threshold; see `measured_like`).
"""

from __future__ import annotations

import difflib
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..errors import InputError, InputWarning
from ..calibrate.problem import CalibrationTest
from ..comparison import best_alignment, compare, measured_like
from .inputs import ReportTest

@dataclass(frozen=True)
class ModelSpec:
    """`kind` lumped, universal or ball; `name` the lumped model, `universal`, or the ball
    preset or file; `label` how tables and figures name it."""

    kind: str
    name: str
    label: str


@dataclass
class ModelRun:
    """One model against one test. Times in s, forces in N, parameters in SI.

    `identification_s`: the fit or the identification (0 for a ball run as it is);
    `simulation_s`: the model's run at the test's speed (the first run of a model includes JAX
    compilation: the report's cost table times a second run, see `rerun`);
    `parameters` and `uncertainty` (standard errors of a lumped fit, or [low, high] 90% intervals
    of a universal identification)."""

    model: str
    kind: str
    test: str
    impact_speed_m_s: float
    features: dict[str, float]
    comparison: dict[str, float]
    parameters: dict[str, float]
    units: dict[str, str]
    uncertainty: dict[str, Any]
    identification_s: float
    simulation_s: float
    time_s: np.ndarray = field(repr=False)
    force_n: np.ndarray = field(repr=False)
    rerun: Callable[[], float] | None = field(default=None, repr=False)
    check: dict[str, Any] = field(default_factory=dict)  # `verdict.judge`, by `build_report`

    @property
    def not_identified(self) -> list[str]:
        """The parameters of a lumped fit whose standard error is inf or larger than the
        value."""
        return list(self.uncertainty.get("not_identified", []))

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.model, "kind": self.kind, "test": self.test,
                "impact_speed_m_s": self.impact_speed_m_s,
                "peak_force_n": self.features["P6"], "contact_time_s": self.features["P1"],
                "cor": self.features["P17"], "features": self.features,
                "comparison": self.comparison, "parameters": self.parameters,
                "units": self.units, "uncertainty": self.uncertainty,
                "identification_s": self.identification_s, "simulation_s": self.simulation_s,
                "check": self.check}


def parse_models(text: str) -> list[ModelSpec]:
    """Comma-separated model names (see the module notes) -> specs, in the order given."""
    from ..fe import PRESETS
    from ..lumped import MODELS

    parts = [part.strip() for part in text.split(",")]
    if not any(parts):
        raise InputError(f"--models: no model named in {text!r}; give one or more, comma-"
                         "separated, e.g. single_element,three_element,universal")
    specs: list[ModelSpec] = []
    for name in parts:
        if not name:
            raise InputError(f"--models: empty name in {text!r}")
        if name in MODELS:
            spec = ModelSpec("lumped", name, name)
        elif name == "universal":
            spec = ModelSpec("universal", name, "universal FE")
        elif name in PRESETS:
            spec = ModelSpec("ball", name, f"FE {name}")
        elif Path(name).suffix.lower() in (".json", ".toml"):
            if not Path(name).is_file():
                raise InputError(f"--models: ball file {name} does not exist")
            spec = ModelSpec("ball", name, f"FE {Path(name).stem}")
        else:
            known = [*MODELS, "universal", *PRESETS]
            nearest = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
            hint = f" (did you mean {nearest[0]}?)" if nearest else ""
            raise InputError(f"--models: unknown model {name!r}{hint}; allowed: lumped models "
                             f"({', '.join(MODELS)}), universal, a ball preset "
                             f"({', '.join(PRESETS)}) or a ball file (.json, .toml)")
        if any(s.label == spec.label for s in specs):
            raise InputError(f"--models: {name!r} is named twice")
        specs.append(spec)
    return specs


def check_balls(specs: list[ModelSpec], impact_speed_m_s: float, allow=()) -> None:
    """Load each ball model once before anything runs, so that a ball file that is not a ball
    is refused up front, naming it, instead of failing at every test. `allow`: the plausibility
    checks that only warn (`checks.CHECKS`, e.g. "ball-units")."""
    from ..fe import load_ball

    for spec in specs:
        if spec.kind == "ball":
            try:
                load_ball(spec.name, impact_speed_m_s=impact_speed_m_s, allow=allow)
            except InputError as error:  # its message names the file, or else add it
                where = "" if spec.name in str(error) else f"{spec.name}: "
                raise InputError(f"--models: {where}{error}") from None


def run_model(spec: ModelSpec, test: ReportTest, *, seed: int = 0, universal_model=None,
              options=None, allow=()) -> ModelRun:
    """Fit, identify or run `spec` for `test` and compare its pulse with the test's. `allow`:
    the plausibility checks that only warn in the FE runs and identifications (`--allow`)."""
    runner = {"lumped": _lumped, "universal": _universal, "ball": _ball}[spec.kind]
    return runner(spec, test, seed=seed, universal_model=universal_model, options=options,
                  allow=allow)


def _compared(spec: ModelSpec, test: ReportTest, run, pulse: tuple[np.ndarray, np.ndarray],
              **fields) -> ModelRun:
    """`run`: the model's `ImpactRecord` or FE run; `pulse`: its force (N) against time (s) from
    first touch."""
    reference = CalibrationTest(test.label, test.processed.features)
    simulated = measured_like(reference, run)
    nrmse, shift = best_alignment(reference, *pulse)
    return ModelRun(model=spec.label, kind=spec.kind, test=test.label,
                    impact_speed_m_s=test.speed_m_s, features=dict(simulated.values),
                    comparison=compare(reference.features.values, simulated.values, nrmse),
                    time_s=np.asarray(pulse[0]) + shift, force_n=np.asarray(pulse[1]), **fields)


def _lumped(spec, test, *, seed, **_):
    from ..lumped import fit, get_model, simulate

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fitted = fit(test.processed, spec.name, seed=seed)
    for caution in caught:  # a report fits many: say which
        warnings.warn(f"{spec.label} at {test.label}: {caution.message}", caution.category,
                      stacklevel=2)

    def run():
        return simulate(spec.name, fitted.params, impact_speed_m_s=test.speed_m_s,
                        mass_kg=test.processed.features.mass_kg)

    started = time.perf_counter()
    record = run()
    simulation_s = time.perf_counter() - started
    return _compared(spec, test, record, (record.time_s, record.force_n),
                     parameters=dict(fitted.params),
                     units=dict(get_model(spec.name).units),
                     uncertainty={"standard_error": dict(fitted.standard_errors),
                                  "not_identified": fitted.not_identified},
                     identification_s=fitted.wall_time_s, simulation_s=simulation_s,
                     rerun=_timed(run))


def _universal(spec, test, *, universal_model, options, allow, **_):
    from ..fe import load_ball, simulate
    from ..universal.identify import identify
    from ..universal.model import TARGET_UNITS

    options = options or universal_model.solver_options()
    found = identify(test.processed, universal_model, verify=True, options=options,
                     allow=allow)
    fe = found.simulated
    return _compared(spec, test, fe, _fe_pulse(fe), parameters=dict(found.params),
                     units=dict(TARGET_UNITS),
                     uncertainty={"interval_90": dict(found.interval_90)},
                     identification_s=max(found.wall_time_s - fe.wall_time_s, 0.0),
                     simulation_s=fe.wall_time_s,
                     rerun=_timed(lambda: simulate(load_ball(found.ball, allow=allow),
                                                   test.speed_m_s, options, allow=allow)))


def _ball(spec, test, *, options, allow, **_):
    from ..fe import SolverOptions, load_ball, simulate

    options = options or SolverOptions()
    ball = load_ball(spec.name, impact_speed_m_s=test.speed_m_s, allow=allow)
    mass = test.processed.features.mass_kg
    if abs(ball.mass_kg / mass - 1.0) > 0.02:
        warnings.warn(f"{spec.name}: the ball's mass {ball.mass_kg:.4g} kg differs from the test's "
                      f"{mass:.4g} kg ({test.label}) by more than 2%", InputWarning, stacklevel=2)
    fe = simulate(ball, test.speed_m_s, options, allow=allow)
    return _compared(spec, test, fe, _fe_pulse(fe), parameters={}, units={},
                     uncertainty={}, identification_s=0.0, simulation_s=fe.wall_time_s,
                     rerun=_timed(lambda: simulate(ball, test.speed_m_s, options, allow=allow)))


def _fe_pulse(fe) -> tuple[np.ndarray, np.ndarray]:
    return fe.history["time_s"], fe.history["contact_force_n"]


def _timed(run: Callable[[], Any]) -> Callable[[], float]:
    def timed() -> float:
        started = time.perf_counter()
        run()
        return time.perf_counter() - started
    return timed

