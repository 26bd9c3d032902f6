"""The tests a report compares models against: files given by the user, or a built-in set.

Built-in sets (both SYNTHETIC, made by scripts in `examples/`, documented in docs/report.md):

- `sample`: the built-in sample test (a Hunt-Crossley ball at 20.8 m/s dressed as a load-cell
  record; `examples/make_sample_record.py`);
- `speeds`: a three-layer FE ball at the thesis' speeds 5.5, 10, 20.8 and 25 m/s, 100 kHz with 1%
  noise (`examples/make_speed_set.py`); its generating ball is `speed_set/synthetic-3layer.json`.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from ..errors import InputError
from ..records.pipeline import ProcessedImpact
from ..records.record import ImpactRecord

BUILTIN_SETS = ("sample", "speeds")


@dataclass(frozen=True)
class ReportTest:
    """One processed test of the report: `label` names it in tables and figures."""

    label: str
    file: str
    processed: ProcessedImpact

    @property
    def speed_m_s(self) -> float:
        return float(self.processed.features.values["P15"])


def data_folder() -> Path:
    return Path(str(resources.files("ballimpact") / "data"))


def builtin_files(name: str) -> list[Path]:
    """The record files of a built-in set (see the module notes)."""
    if name == "sample":
        return [data_folder() / "sample_impact.csv"]
    if name == "speeds":
        return sorted((data_folder() / "speed_set").glob("synthetic_*.csv"))
    raise InputError(f"builtin: {name!r} is not a built-in test set; allowed "
                     f"{', '.join(BUILTIN_SETS)}")


def builtin_ball(name: str) -> Path | None:
    """The ball that generated a built-in set, where it is an FE ball (else None)."""
    return data_folder() / "speed_set" / "synthetic-3layer.json" if name == "speeds" else None


def label_tests(files: list[str], processed: list[ProcessedImpact]) -> list[ReportTest]:
    """Tests ordered by impact speed, labelled by speed ("20.8 m/s"), with the file name added
    where two share a speed."""
    speeds = [f"{p.features.values['P15']:g} m/s" for p in processed]
    labels = [s if speeds.count(s) == 1 else f"{s} ({Path(f).name})" for s, f in zip(speeds, files)]
    tests = [ReportTest(label, file, p) for label, file, p in zip(labels, files, processed)]
    return sorted(tests, key=lambda t: (t.speed_m_s, t.label))


def check_test_record(record: ImpactRecord, path: Path, count: int = 1) -> ImpactRecord:
    """`record` (loaded from `path`, one of `count` tests), which must carry its impact speed
    and the ball mass (a report compares tests at their speeds), else `InputError` naming the
    side file to give them in (and, for a single test, the flags)."""
    missing = [name for name, value in (("impact_speed_m_s", record.impact_speed_m_s),
                                        ("mass_kg", record.mass_kg)) if value is None]
    if missing:
        flags = " or --" + " and --".join(m.replace("_", "-") for m in missing)
        raise InputError(
            f"{path}: no {' and no '.join(missing)}; a report compares tests at their speeds: "
            f"give them in the side file {path.with_suffix('.json').name} (e.g. {{\"mass_kg\": "
            f"0.16, \"impact_speed_m_s\": 25}}){flags if count == 1 else ''}")
    return record


def builtin_note(name: str, generating_ball: Path | None = None) -> str:
    """The note at the top of a report on the built-in set `name`: its tests are synthetic;
    with `generating_ball` (`builtin_ball`, among the models), that ball's errors are the floor
    set by the noise and the mesh."""
    note = f"SYNTHETIC tests (the built-in set '{name}', see docs/report.md), not measurements."
    if generating_ball is not None:
        note += (f" The model 'FE {generating_ball.stem}' is the ball that generated them, run "
                 "on the default mesh (the tests used one twice as fine): its errors are the "
                 "floor set by the noise and the mesh.")
    return note
