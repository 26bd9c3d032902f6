"""The main job on built-in defaults (`ballimpact demo`, README), as library functions: the two
cricket-ball presets' FE impacts on a rigid plane, their summaries with a note where the figures
should not be read as a model of the real ball, and the built-in sample test identified as a
universal ball with the built-in model."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from ..errors import InputWarning
from ..fileio import check_plot_path

#: (preset, impact speed in m/s) of the demo's impacts
DEMO_IMPACTS = (("cricket-universal", 25.0), ("cricket-3layer", 20.8))
#: notes on demo impacts whose figures should not be read as a model of the real ball
DEMO_NOTES = {"cricket-3layer": (
    "thesis chapter 5 constants as printed: COR far above the measured 0.5-0.6, because only "
    "the core relaxes; the thesis' calibrated values cannot be reproduced from them "
    "(docs/fe.md, Limits and notes)")}
#: The built-in sample's exact contact time (s) and peak force (N): its header, written by
#: examples/make_sample_record.py.
SAMPLE_CONTACT_TIME_S = 1.09704e-3
SAMPLE_PEAK_FORCE_N = 11219.9
SAMPLE_FILE = "sample_impact.csv"


def demo_impacts(announce: Callable[[str, float], None] | None = None,
                 plot_path: Path | None = None) -> list:
    """The `DEMO_IMPACTS` on a rigid plane with the default mesh (`fe.simulate`), in order;
    `announce(preset, speed_m_s)` is called before each; with `plot_path` (PNG, checked first:
    `InputError`) their pulses are drawn in one figure (`plotting.plot_fe`)."""
    from ..fe import load_ball, simulate  # the package's, looked up at call time

    check_plot_path(plot_path)
    results = []
    for name, speed in DEMO_IMPACTS:
        if announce is not None:
            announce(name, speed)
        results.append(simulate(load_ball(name, impact_speed_m_s=speed), speed))
    if plot_path is not None:
        from ..plotting import plot_fe

        plot_fe(results, plot_path, title="ballimpact demo: cricket balls on a rigid plane (FE)")
    return results


def demo_summaries(results) -> list[dict[str, Any]]:
    """Each demo impact's `summary()`, with its `DEMO_NOTES` entry as "note" where it has one."""
    impacts = [r.summary() for r in results]
    for (name, _), impact in zip(DEMO_IMPACTS, impacts):
        if name in DEMO_NOTES:
            impact["note"] = DEMO_NOTES[name]
    return impacts


@dataclass(frozen=True)
class SampleIdentification:
    """The built-in sample test identified (SI): its contact time and uncertainty with the default
    processing, its peak force, the identification (`universal.Identification`) and the notes
    that identify's warnings became (`identify_sample`)."""

    contact_time_s: float
    contact_time_uncertainty_s: float
    peak_force_n: float
    found: Any
    notes: list[str]

    def to_dict(self) -> dict[str, Any]:
        return {"file": f"{SAMPLE_FILE} (built-in, synthetic)",
                "sample_contact_time_s": self.contact_time_s,
                "sample_contact_time_uncertainty_s": self.contact_time_uncertainty_s,
                "sample_exact_contact_time_s": SAMPLE_CONTACT_TIME_S, **self.found.to_dict(),
                "notes": self.notes}


def identify_sample() -> SampleIdentification:
    """The built-in sample test processed with the defaults and identified as a universal ball
    with the built-in model (its FE check included). Warnings are about a user's own data
    (issue 24): the package's sample and model are ours, so what identify would warn about (a
    C01 interval on its training bound) becomes a note; any other warning goes on as one."""
    from ..records.loaders import load_record
    from ..records.pipeline import process
    from . import identify, load_model

    sample = Path(str(resources.files("ballimpact") / "data" / SAMPLE_FILE))
    model = load_model()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InputWarning)
        test = process(load_record(sample))
        found = identify(test, model, options=model.solver_options())
    notes = [str(w.message).removeprefix(f"{sample}: ") for w in caught
             if issubclass(w.category, InputWarning)]
    for w in caught:
        if not issubclass(w.category, InputWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    values, uncertainty = test.features.values, test.features.uncertainty or {}
    return SampleIdentification(values["P1"], uncertainty.get("P1", 0.0), values["P6"], found,
                                notes)
