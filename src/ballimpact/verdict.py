"""The verdict of a model against a test: force NRMSE, COR, contact time and peak force together.

A model "passes" a test only when every criterion does. Each criterion's miss is allowed up to its
tolerance plus, for COR, contact time and peak force, the test's own 90% uncertainty of that
feature (`ImpactFeatures.uncertainty`: a noisy record cannot demand more than it measures; the
force NRMSE has none). The default tolerances are about twice the
90th percentiles of the built-in universal model's own noisy closed loop (docs/universal.md:
force NRMSE 2.6%, COR 0.017, contact time 1.9%, peak force about 1.5%), so that a model as good as
the universal ball is on its own FE pulses passes, and one clearly worse does not
(docs/features.md, "Verdicts").
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

from .checks import check_fraction

#: Two-sided 90% interval of a normal distribution, in standard uncertainties.
Z90 = 1.6448536269514722


@dataclass(frozen=True)
class Tolerances:
    """Allowed misses (SI fractions): `force_nrmse` of the test's peak force, `cor` absolute,
    `contact_time` and `peak_force` relative."""

    force_nrmse: float = 0.05
    cor: float = 0.03
    contact_time: float = 0.04
    peak_force: float = 0.04

    def __post_init__(self) -> None:
        for name, flag in FLAGS.items():
            check_fraction(f"max_{name} ({flag})", getattr(self, name))

    def to_dict(self) -> dict[str, float]:
        return asdict(self)


#: Allowed force NRMSE of a compression test (a fraction of its largest force) where `identify`
#: judges one (`universal.compression_check`): the 5% within which a preset gives back its
#: specification's compression (issue 42).
COMPRESSION_TOLERANCE = 0.05

#: The command-line flag of each tolerance.
FLAGS = {"force_nrmse": "--max-nrmse", "cor": "--max-cor-error",
         "contact_time": "--max-contact-time-error", "peak_force": "--max-peak-force-error"}
#: What each criterion reads from `comparison.compare` and the feature of its uncertainty.
_CRITERIA = {"force_nrmse": ("force_nrmse", None, None),
             "cor": ("cor_error", "P17", "cor_measured"),
             "contact_time": ("contact_time_relative_error", "P1", "contact_time_measured_s"),
             "peak_force": ("peak_force_relative_error", "P6", "peak_force_measured_n")}


def add_tolerance_flags(parser) -> None:
    """The four `--max-*` flags (defaults `Tolerances()`)."""
    defaults = Tolerances()
    words = {"force_nrmse": "force NRMSE, a fraction of the test's peak force",
             "cor": "absolute COR error", "contact_time": "relative contact-time error",
             "peak_force": "relative peak-force error"}
    for name, flag in FLAGS.items():
        parser.add_argument(flag, type=float, default=None, metavar="X",
                            dest=f"max_{name}",
                            help=f"largest {words[name]} the model check allows"
                                 + ("" if name == "force_nrmse" else
                                    ", plus the test's 90%% uncertainty of it")
                                 + f" (default {getattr(defaults, name):g})")


def tolerances_from(args) -> Tolerances:
    """`Tolerances` from the parsed `--max-*` flags (the defaults where not given)."""
    given = {name: getattr(args, f"max_{name}") for name in FLAGS}
    return Tolerances(**{k: v for k, v in given.items() if v is not None})


def given_flags(args) -> list[str]:
    """The `--max-*` flags given on the command line."""
    return [flag for name, flag in FLAGS.items() if getattr(args, f"max_{name}") is not None]


def judge(comparison: dict[str, Any], tolerances: Tolerances = Tolerances(),
          uncertainty: dict[str, float] | None = None) -> dict[str, Any]:
    """The verdict of `comparison` (`comparison.compare`'s dict): per criterion the miss, the
    allowed miss (tolerance + 1.645 x the test's standard uncertainty, relative for the relative
    criteria) and whether it passed; `passed` when all do (a NaN misses); `missed` in words."""
    uncertainty = uncertainty or {}
    criteria, missed = {}, []
    for name, (key, feature, measured_key) in _CRITERIA.items():
        value = float(comparison[key])
        allowed = getattr(tolerances, name)
        u = uncertainty.get(feature) if feature else None
        if u is not None and math.isfinite(u):
            scale = 1.0 if name == "cor" else abs(float(comparison[measured_key]))
            allowed += Z90 * u / scale if scale > 0 else 0.0
        passed = bool(abs(value) <= allowed)  # NaN fails
        criteria[name] = {"value": value, "allowed": allowed, "tolerance": getattr(tolerances, name),
                          "passed": passed}
        if not passed:
            missed.append(miss_words(name, value, allowed))
    return {"passed": not missed, "criteria": criteria, "missed": missed,
            "tolerances": tolerances.to_dict()}


def miss_words(name: str, value: float, allowed: float) -> str:
    """One missed criterion and by how much."""
    if not math.isfinite(value):
        return f"{name.replace('_', ' ')} is {value:g} (allowed {allowed:.3g})"
    if name == "force_nrmse":
        return f"force NRMSE {value:.1%} > {allowed:.1%} ({FLAGS[name]})"
    if name == "cor":
        return f"COR off by {value:+.3f}, beyond +-{allowed:.3f} ({FLAGS[name]})"
    what = name.replace("_", " ")
    return f"{what} off by {value:+.1%}, beyond +-{allowed:.1%} ({FLAGS[name]})"


def verdict_line(verdict: dict[str, Any]) -> str:
    """'passed' or 'FAILED: <each miss>'."""
    return "passed" if verdict["passed"] else "FAILED: " + "; ".join(verdict["missed"])


def raise_if_missed(checks: list, result: Any, check: str, subject: str) -> None:
    """`CheckFailed` (exit 3, `result` printed all the same) naming each test of `checks`,
    (label, `judge`'s verdict or None where none ran), whose `check` ("FE check", "model
    check") missed and what it missed; `subject` is what does not reproduce the test."""
    from .errors import CheckFailed

    missed = [(label, verdict) for label, verdict in checks
              if verdict is not None and not verdict["passed"]]
    if missed:
        words = "; ".join(f"{label}: {', '.join(verdict['missed'])}" for label, verdict in missed)
        raise CheckFailed(f"the {check} missed for {len(missed)} of {len(checks)} tests: "
                          f"{words}; {subject} does not reproduce the test (see --plot)", result)
