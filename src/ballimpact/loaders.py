"""Reading impact tests: CSV with unit headers, WAV from a signal analyser, JSON side files.

CSV (DESIGN.md "Files"): lines starting with `#` are comments; the first other line is a header
naming each column with its unit: `time_s`/`time_ms`/`time_us`, `force_n`/`force_kn`, optional
`velocity_m_s` and `tangential_force_n`/`tangential_force_kn`. Values are converted to SI.

WAV: the sample rate comes from the file; samples are read as fractions of full scale (integer
PCM divided by its full-scale code, float samples as they are) times `full_scale_v`, then turned
into newtons by dividing by the sensor sensitivity (V/N) and the amplifier gain. The thesis' rig:
PCB 223A load cell, 94.42 mV/kN = 9.442e-5 V/N, charge amplifier gain 10.

Scalars (mass, speeds, and for WAV files the sensor settings) come from a JSON side file next to
the record (same name, `.json`) and from keyword arguments, which win.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
from scipy.io import wavfile

from .errors import InputError
from .records import ImpactRecord, check_positive

#: CSV column name -> (record field, factor to SI).
CSV_COLUMNS: dict[str, tuple[str, float]] = {
    "time_s": ("time_s", 1.0),
    "time_ms": ("time_s", 1e-3),
    "time_us": ("time_s", 1e-6),
    "force_n": ("force_n", 1.0),
    "force_kn": ("force_n", 1e3),
    "velocity_m_s": ("velocity_m_s", 1.0),
    "tangential_force_n": ("tangential_force_n", 1.0),
    "tangential_force_kn": ("tangential_force_n", 1e3),
}
#: Record field -> the quantity it holds, as a unit-less header would name it.
_QUANTITY = {"time_s": "time", "force_n": "force", "velocity_m_s": "velocity",
             "tangential_force_n": "tangential_force"}
#: Quantity -> the accepted column names, for error messages.
_UNITS_OF = {quantity: ", ".join(name for name, (f, _) in CSV_COLUMNS.items() if f == field)
             for field, quantity in _QUANTITY.items()}

#: Keys a JSON side file may hold, each a positive number.
SIDE_KEYS = ("mass_kg", "impact_speed_m_s", "rebound_speed_m_s", "sensitivity_v_per_n",
             "amplifier_gain", "full_scale_v")


def read_csv(path: str | Path) -> dict[str, np.ndarray]:
    """Columns of an impact CSV as SI arrays keyed by record field."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(f"{path}: cannot read ({error})") from None
    lines = [(number, line.strip()) for number, line in enumerate(text.splitlines(), start=1)]
    lines = [(number, line) for number, line in lines if line and not line.startswith("#")]
    if not lines:
        raise InputError(f"{path}: the file is empty (no header, no samples)")
    header_line, header = lines[0]
    names = [name.strip().lower() for name in header.split(",")]
    columns = [_column(path, name, names) for name in names]
    fields = [field for field, _ in columns]
    for required in ("time_s", "force_n"):
        if required not in fields:
            quantity = _QUANTITY[required]
            raise InputError(f"{path}: no {quantity} column; add one of {_UNITS_OF[quantity]}")
    if len(lines) < 2:
        raise InputError(f"{path}: the header has no samples below it")
    values = np.empty((len(lines) - 1, len(names)))
    for row, (number, line) in enumerate(lines[1:]):
        cells = line.split(",")
        if len(cells) != len(names):
            raise InputError(f"{path}: line {number} has {len(cells)} values, the header "
                             f"{len(names)}")
        for col, cell in enumerate(cells):
            try:
                value = float(cell)
            except ValueError:
                raise InputError(f"{path}: line {number}, column {names[col]}: "
                                 f"{cell.strip()!r} is not a number") from None
            if not math.isfinite(value):
                raise InputError(f"{path}: line {number}, column {names[col]}: "
                                 f"{cell.strip()!r} is not a finite number")
            values[row, col] = value
    return {field: values[:, col] * factor for col, (field, factor) in enumerate(columns)}


def _column(path: Path, name: str, names: list[str]) -> tuple[str, float]:
    if name in CSV_COLUMNS:
        field = CSV_COLUMNS[name][0]
        if sum(CSV_COLUMNS.get(other, ("",))[0] == field for other in names) > 1:
            raise InputError(f"{path}: header names {_QUANTITY[field]} twice")
        return CSV_COLUMNS[name]
    if _is_number(name):
        raise InputError(f"{path}: first line is not a header; name the columns with units "
                         f"(e.g. time_s,force_n)")
    if name in _UNITS_OF:
        raise InputError(f"{path}: column {name!r} has no unit; use one of {_UNITS_OF[name]}")
    raise InputError(f"{path}: unknown column {name!r}; allowed: {', '.join(CSV_COLUMNS)}")


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def read_wav(
    path: str | Path,
    *,
    sensitivity_v_per_n: float | None,
    amplifier_gain: float = 1.0,
    full_scale_v: float = 1.0,
    channel: int | None = None,
) -> dict[str, np.ndarray]:
    """Force samples of a WAV export as {time_s, force_n}, plus `full_scale_n`: the forces of the
    extreme codes (low, high), for the clipping check. A file with several channels needs
    `channel` (0 = first)."""
    path = Path(path)
    if sensitivity_v_per_n is None:
        raise InputError(f"{path}: sensitivity_v_per_n: a WAV file needs the load-cell "
                         "sensitivity in V/N (e.g. --sensitivity-v-per-n 9.442e-5 for a PCB 223A)")
    sensitivity = check_positive("sensitivity_v_per_n", sensitivity_v_per_n)
    gain = check_positive("amplifier_gain", amplifier_gain)
    full_scale = check_positive("full_scale_v", full_scale_v)
    try:
        rate, data = wavfile.read(path)
    except Exception as error:  # noqa: BLE001 - scipy raises many kinds on a malformed file
        raise InputError(f"{path}: not a readable WAV file ({type(error).__name__}: {error})") from None
    if data.ndim == 2:
        data = data[:, _channel(path, data, channel)]
    elif channel not in (None, 0):
        raise InputError(f"{path}: channel: the file has one channel, asked for {channel}")
    if data.size == 0:
        raise InputError(f"{path}: the file is empty (no samples)")
    newtons_per_unit = full_scale / (sensitivity * gain)
    if data.dtype == np.uint8:
        fraction = (data.astype(float) - 128.0) / 128.0
        extremes = (-1.0, 127 / 128)
    elif np.issubdtype(data.dtype, np.integer):
        codes = np.iinfo(data.dtype)
        fraction = data.astype(float) / float(codes.max + 1)
        extremes = (codes.min / (codes.max + 1), codes.max / (codes.max + 1))
    else:  # float samples may exceed 1: no known full scale (the flat-top test applies)
        return {"time_s": np.arange(data.size) / float(rate),
                "force_n": data.astype(float) * newtons_per_unit}
    return {"time_s": np.arange(data.size) / float(rate), "force_n": fraction * newtons_per_unit,
            "full_scale_n": tuple(level * newtons_per_unit for level in extremes)}


def _channel(path: Path, data: np.ndarray, channel: int | None) -> int:
    """The channel to read from a multi-channel WAV: given, or an error that describes them."""
    count = data.shape[1]
    if channel is None:
        scale = float(np.iinfo(data.dtype).max) if np.issubdtype(data.dtype, np.integer) else 1.0
        centre = 128.0 if data.dtype == np.uint8 else 0.0
        peaks = np.max(np.abs(data.astype(float) - centre), axis=0) / scale
        described = ", ".join(f"{k}: peak {peak:.1%} of full scale" for k, peak in enumerate(peaks))
        raise InputError(f"{path}: channel: the file has {count} channels ({described}); choose "
                         f"the load cell's with --channel N (channel=N in Python), N in "
                         f"0..{count - 1}")
    if isinstance(channel, bool) or not isinstance(channel, (int, np.integer)) or \
            not 0 <= channel < count:
        raise InputError(f"{path}: channel: {channel} out of range 0..{count - 1}")
    return int(channel)


def read_side_file(path: str | Path) -> dict[str, float]:
    """Scalars from a JSON side file; unknown keys and bad values are errors naming the file and
    the key. Values must be JSON numbers (not strings or booleans)."""
    path = Path(path)
    try:
        content = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise InputError(f"{path}: not a readable JSON file ({error})") from None
    if not isinstance(content, dict):
        raise InputError(f"{path}: expected a JSON object with keys {', '.join(SIDE_KEYS)}")
    scalars = {}
    for key, value in content.items():
        if key in ("comment", "source"):
            continue
        if key not in SIDE_KEYS:
            raise InputError(f"{path}: unknown key {key!r}; allowed: {', '.join(SIDE_KEYS)}")
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError(f"{path}: {key}: expected a JSON number, got {json.dumps(value)} "
                             f"({type(value).__name__})")
        try:
            scalars[key] = check_positive(key, value, allow_zero=key == "rebound_speed_m_s")
        except InputError as error:
            raise InputError(f"{path}: {error}") from None
    return scalars


def load_record(path: str | Path, **given: Any) -> ImpactRecord:
    """An `ImpactRecord` from a CSV or WAV test file.

    Scalars come from the side file `path.with_suffix('.json')` if it exists, overridden by the
    keyword arguments that are not None: `mass_kg`, `impact_speed_m_s`, `rebound_speed_m_s`, and for
    WAV files `sensitivity_v_per_n`, `amplifier_gain`, `full_scale_v`, `channel`.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a folder; give a test record file (.csv, .txt or .wav)")
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    side = path.with_suffix(".json")
    scalars: dict[str, Any] = read_side_file(side) if side.is_file() else {}
    scalars.update({key: value for key, value in given.items() if value is not None})
    unknown = set(scalars) - set(SIDE_KEYS) - {"channel"}
    if unknown:
        raise TypeError(f"load_record: unexpected arguments {sorted(unknown)}")
    suffix = path.suffix.lower()
    if suffix == ".wav":
        columns = read_wav(
            path,
            sensitivity_v_per_n=scalars.get("sensitivity_v_per_n"),
            amplifier_gain=scalars.get("amplifier_gain", 1.0),
            full_scale_v=scalars.get("full_scale_v", 1.0),
            channel=scalars.get("channel"),
        )
    elif suffix in (".csv", ".txt"):
        columns = read_csv(path)
    else:
        raise InputError(f"{path}: unknown file type {suffix!r}; expected .csv or .wav")
    full_scale = columns.pop("full_scale_n", None)
    metadata = {"source": str(path)} | ({} if full_scale is None else {"full_scale_n": full_scale})
    try:
        return ImpactRecord(
            **columns,
            mass_kg=scalars.get("mass_kg"),
            impact_speed_m_s=scalars.get("impact_speed_m_s"),
            rebound_speed_m_s=scalars.get("rebound_speed_m_s"),
            metadata=metadata,
        )
    except InputError as error:
        raise InputError(f"{path}: {error}") from None
