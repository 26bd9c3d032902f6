"""Parameters as functions of the impact speed (thesis tables 7-1, 7-2): fit one record per row,
then interpolate linearly in speed between the fitted rows (no extrapolation). Repeated tests at
one speed keep one row each (their scatter stays visible); interpolation uses their mean."""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from importlib import resources
from typing import Any, Sequence

import numpy as np

from ..checks import check_positive, shown
from ..errors import InputError
from ..fileio import table_text
from ..records.pipeline import ProcessedImpact
from ..records.record import ImpactRecord
from .fit import FitResult, fit
from .registry import get_model
from .simulate import simulate


@dataclass(frozen=True)
class SpeedTable:
    """Rows of one model's parameters at non-decreasing impact speeds (m/s), SI units; a speed
    may repeat (repeated tests, one row each). `labels` optionally names each row's test (the
    command line puts the file there)."""

    model: str
    speeds_m_s: tuple[float, ...]
    params: dict[str, tuple[float, ...]]
    note: str = ""
    labels: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        model = get_model(self.model)
        speeds = np.asarray(self.speeds_m_s, dtype=float)
        if (speeds.size < 1 or not np.all(np.isfinite(speeds)) or np.any(np.diff(speeds) < 0)
                or np.any(speeds <= 0)):
            raise InputError("speeds_m_s: need positive speeds in increasing order (repeats "
                             f"allowed), got {shown(self.speeds_m_s)}")
        if self.labels and len(self.labels) != speeds.size:
            raise InputError(f"labels: {len(self.labels)} labels for {speeds.size} speeds")
        for name in model.parameter_names:
            if name not in self.params and not any(p.name == name and p.fixed
                                                   for p in model.parameters):
                raise InputError(f"params: the table has no column {name!r} for {self.model}")
        for name, column in self.params.items():
            if len(column) != speeds.size:
                raise InputError(f"params.{name}: {len(column)} values for {speeds.size} speeds")
            if not np.all(np.isfinite(column)):
                raise InputError(f"params.{name}: values must be finite, got {shown(column)}")

    @property
    def units(self) -> dict[str, str]:
        return get_model(self.model).units

    def params_at(self, impact_speed_m_s: float) -> dict[str, float]:
        """The parameters at a speed inside the table's range, linear in speed between rows;
        rows repeated at one speed count by their mean."""
        speed = check_positive("impact_speed_m_s", impact_speed_m_s)
        low, high = self.speeds_m_s[0], self.speeds_m_s[-1]
        if not low <= speed <= high:
            raise InputError(f"impact_speed_m_s: {speed:g} is outside the table's range "
                             f"[{low:g}, {high:g}] m/s")
        speeds, row_speed = np.unique(self.speeds_m_s, return_inverse=True)
        repeats = np.bincount(row_speed)
        return {name: float(np.interp(speed, speeds,
                                      np.bincount(row_speed, weights=column) / repeats))
                for name, column in self.params.items()}

    def simulate(self, impact_speed_m_s: float, mass_kg: float | None = None, **options):
        """`lumped.simulate` with the parameters interpolated at `impact_speed_m_s`."""
        return simulate(self.model, self.params_at(impact_speed_m_s),
                        impact_speed_m_s=impact_speed_m_s, mass_kg=mass_kg, **options)

    def to_dict(self) -> dict[str, Any]:
        return {"model": self.model, "speeds_m_s": list(self.speeds_m_s),
                "params": {k: list(v) for k, v in self.params.items()}, "units": self.units,
                "note": self.note, "labels": list(self.labels)}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> SpeedTable:
        try:
            return cls(data["model"], tuple(float(s) for s in data["speeds_m_s"]),
                       {k: tuple(float(x) for x in v) for k, v in data["params"].items()},
                       data.get("note", ""), tuple(str(x) for x in data.get("labels", ())))
        except KeyError as missing:
            raise InputError(f"speed table: missing key {missing}") from None
        except (TypeError, ValueError, AttributeError) as error:
            raise InputError(f"speed table: speeds_m_s and params must hold numbers ({error})") \
                from None

    def to_csv(self) -> str:
        """One row per test: impact_speed_m_s, the parameters (units in the header), then the
        row's label if the table has labels (`fileio.table_text`)."""
        names = list(self.params)
        units = self.units
        header = ["impact_speed_m_s", *(f"{n} [{units.get(n, '')}]" for n in names)]
        return table_text(header + (["label"] if self.labels else []),
                          ([f"{speed:g}", *(self.params[n][i] for n in names),
                            *self.labels[i:i + 1]] for i, speed in enumerate(self.speeds_m_s)))


def fit_speed_table(
    records: Sequence[ImpactRecord | ProcessedImpact], model: str, *, progress: bool = True,
    labels: Sequence[str] | None = None, **fit_options,
) -> tuple[SpeedTable, list[FitResult]]:
    """Fit `model` to each record (see `fit` for the options) and collect the parameters into a
    `SpeedTable` ordered by impact speed, one row per record: repeated tests at one speed keep
    a row each, in the given order (`labels`, one per record, name them). Progress goes to
    stderr."""
    if not records:
        raise InputError("records: need at least one record")
    labels = tuple(str(label) for label in labels) if labels is not None else ()
    if labels and len(labels) != len(records):
        raise InputError(f"labels: {len(labels)} labels for {len(records)} records")
    results = []
    for i, record in enumerate(records, 1):
        result = fit(record, model, **fit_options)
        if progress:
            name = f" ({labels[i - 1]})" if labels else ""
            print(f"fit {i}/{len(records)}{name}: {result.measured['impact_speed_m_s']:g} m/s, "
                  f"NRMSE {result.nrmse:.4f}, {result.wall_time_s:.2f} s", file=sys.stderr)
        results.append(result)
    order = sorted(range(len(results)), key=lambda i: results[i].measured["impact_speed_m_s"])
    results = [results[i] for i in order]
    names = get_model(model).parameter_names
    table = SpeedTable(get_model(model).name,
                       tuple(float(r.measured["impact_speed_m_s"]) for r in results),
                       {n: tuple(r.params[n] for r in results) for n in names},
                       note=f"fitted by ballimpact ({results[0].method})",
                       labels=tuple(labels[i] for i in order) if labels else ())
    return table, results


def thesis_tables() -> dict[str, SpeedTable]:
    """Thesis tables 7-1 (single element) and 7-2 (three elements) as `SpeedTable`s of the
    reproduction models; see the note on what their c means."""
    data = json.loads((resources.files("ballimpact") / "data" / "thesis_lumped_tables.json")
                      .read_text())
    return {key: SpeedTable.from_dict({**table, "note": data["note"]})
            for key, table in data["tables"].items()}
