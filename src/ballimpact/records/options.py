"""How every verb that reads tests loads and processes a record file: one typed value
(`RecordOptions`) in place of a loader and a processor passed around separately, so that the
functions of the verbs (`records.summaries.features_of_files`, `lumped.fit_records.fit_files`,
`universal.by_speed.identify_files`, `report.build.report_files`,
`calibrate.files.calibrate_from_files`) take the same options, with the library's defaults."""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from .features import DEFAULT_IMPULSE_TOLERANCE
from .loaders import load_record
from .pipeline import DEFAULT_DAMPING_RATIO, ProcessedImpact, process
from .record import ImpactRecord

#: the fields of `RecordOptions` that are `loaders.load_record`'s keyword arguments
LOADING_FIELDS = ("mass_kg", "impact_speed_m_s", "rebound_speed_m_s", "sensitivity_v_per_n",
                  "amplifier_gain", "full_scale_v", "channel", "time_column", "force_column")
#: the fields of `RecordOptions` that are `pipeline.process`'s keyword arguments
PROCESSING_FIELDS = ("filter", "window_s", "resample_hz", "impulse_tolerance", "pulse", "allow",
                     "warn_noisy", "method", "uncertainty", "ringing", "resonance_hz",
                     "damping_ratio")


@dataclass(frozen=True)
class RecordOptions:
    """How a test record file is loaded (`load`: `loaders.load_record`) and processed
    (`process`: `pipeline.process`); the defaults are theirs.

    Loading (None: the record's side file `FILE.json`, else the loader's default):
    `mass_kg` (kg), `impact_speed_m_s` and `rebound_speed_m_s` (m/s; the rebound speed from the
    impulse when neither gives it), and for WAV files, or a CSV force column in volts,
    `sensitivity_v_per_n` (V/N) and `amplifier_gain` (default 1); for WAV files `full_scale_v`
    (V at digital full scale, default 1) and `channel` (0-based; needed with several); for CSV
    files `time_column` and `force_column` (a header name or a 0-based position).

    Processing: `filter` (`filters.apply_filter`'s name, or cfc<N>) with its window `window_s`
    (s; None: 10% of the contact time), `resample_hz` (Hz; None: as recorded),
    `impulse_tolerance` (relative misfit allowed between impulse and m (v_in + v_out)), `pulse`
    (1 = the first of several; None: the record must hold one), `allow` (the plausibility checks
    that only warn, `checks.CHECKS`), `warn_noisy`, `method` ("fit" or "samples") and
    `uncertainty`, `ringing`, `resonance_hz` (Hz; None: found in the record) and
    `damping_ratio` of the load cell: as `pipeline.process` takes them."""

    mass_kg: float | None = None
    impact_speed_m_s: float | None = None
    rebound_speed_m_s: float | None = None
    sensitivity_v_per_n: float | None = None
    amplifier_gain: float | None = None
    full_scale_v: float | None = None
    channel: int | None = None
    time_column: str | int | None = None
    force_column: str | int | None = None
    filter: str = "none"
    window_s: float | None = None
    resample_hz: float | None = None
    impulse_tolerance: float = DEFAULT_IMPULSE_TOLERANCE
    pulse: int | None = None
    allow: Collection[str] = ()
    warn_noisy: bool | None = None
    method: str = "fit"
    uncertainty: bool = True
    ringing: bool = True
    resonance_hz: float | None = None
    damping_ratio: float = DEFAULT_DAMPING_RATIO

    def allowing(self, allow: Collection[str]) -> "RecordOptions":
        """These options with the checks `allow` names allowed too: a function's own `allow`
        reaches the processing of its records (one set of allowed checks, not two)."""
        return replace(self, allow=tuple(sorted({*self.allow, *allow})))

    def loading(self) -> dict[str, Any]:
        """The loading options as `loaders.load_record`'s keyword arguments."""
        return {name: getattr(self, name) for name in LOADING_FIELDS}

    def processing(self) -> dict[str, Any]:
        """The processing options as `pipeline.process`'s keyword arguments."""
        return {name: getattr(self, name) for name in PROCESSING_FIELDS}

    def load(self, path: str | Path) -> ImpactRecord:
        """The record of the file `path` (`loaders.load_record`; `builtin:NAME` too)."""
        return load_record(path, **self.loading())

    def process(self, record: ImpactRecord) -> ProcessedImpact:
        """`record` processed (`pipeline.process`): checked, offset removed, filtered, its
        features extracted."""
        return process(record, **self.processing())


__all__ = ["LOADING_FIELDS", "PROCESSING_FIELDS", "RecordOptions"]
