"""Reading impact tests: CSV with unit headers, WAV from a signal analyser, JSON side files.

CSV (docs/features.md): lines starting with `#` are comments; the first other line is a header
naming each column with its unit: `time_s`/`time_ms`/`time_us`, `force_n`/`force_kn`, optional
`velocity_m_s` and `tangential_force_n`/`tangential_force_kn`; or as labs write them, the unit
after the name (`Time (ms)`, `Force [kN]`, `Fz (lbf)`, `t/us`, `fz_lbf`; any case): times in s, ms,
us; forces in N, kN, lbf, kgf; velocity in m/s; a load-cell voltage (`ch1 (V)`, `Voltage (mV)`,
`ch1_v`) turned into newtons by the sensitivity and gain, as a WAV file's. Values are converted
to SI. A column that is not needed (another channel) is left out with a warning; where two could
be the time or the force, `time_column` / `force_column` choose (a name or a 0-based position).
The histories `simulate --csv` writes load too: their force column is `contact_force_n` (either
geometry; `normal_force_n` in 3D files written before issue 40), their other columns are left
out, and since
they start at first contact the zero-force samples before it are put back (as
`fe.ImpactResult.record()` does).

WAV: the sample rate comes from the file; samples are read as fractions of full scale (integer
PCM divided by its full-scale code, float samples as they are) times `full_scale_v`, then turned
into newtons by dividing by the sensor sensitivity (V/N) and the amplifier gain. The thesis' rig:
PCB 223A load cell, 94.42 mV/kN = 9.442e-5 V/N, charge amplifier gain 10.

Scalars (mass, speeds, and for WAV files the sensor settings) come from a JSON side file next to
the record (same name, `.json`) and from keyword arguments, which win. The speeds are the
components normal to the surface (the load cell measures the normal force): a side file may give
them as `impact_speed_m_s`, or explicitly with their tangential and total parts (as `video
--side-file` writes them; docs/video.md). The JSON that `simulate --json` prints, and the one
`video --json` prints, are read as side files too.
"""

from __future__ import annotations

import json
import math
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError, InputWarning
from ..fileio import is_number, read_table
from ..checks import check_positive
from .datasets import DATA
from .datasets import resolve as resolve_builtin
from .record import ImpactRecord

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
    # the force columns of `simulate --csv`: either geometry, and --solver 3d before issue 40
    "contact_force_n": ("force_n", 1.0),
    "normal_force_n": ("force_n", 1.0),
}
#: Force columns that mark an FE history written by `simulate --csv`.
FE_FORCE_COLUMNS = ("contact_force_n", "normal_force_n")
#: Zero-force samples put back before first contact in an FE history: this fraction of its
#: samples, at least 3 (as `fe.ImpactResult.record()`).
FE_LEAD_FRACTION = 0.05
#: Record field -> the quantity it holds, as a unit-less header would name it.
_QUANTITY = {"time_s": "time", "force_n": "force", "velocity_m_s": "velocity",
             "tangential_force_n": "tangential_force"}
#: Quantity -> the accepted column names, for error messages.
_UNITS_OF = {quantity: ", ".join(name for name, (f, _) in CSV_COLUMNS.items() if f == field)
             for field, quantity in _QUANTITY.items()}

#: Columns of the tables of results other verbs write (`fit --table`, `identify --table`,
#: `report`), which are not test records.
RESULT_TABLE_COLUMNS = {"impact_speed_m_s", "speed_m_s", "model", "test", "parameter", "label"}

#: Keys a JSON side file may hold, each a positive number (the sensitivity may be negative: an
#: inverted load cell). The speeds are the components normal to the surface.
SIDE_KEYS = ("mass_kg", "impact_speed_m_s", "rebound_speed_m_s", "sensitivity_v_per_n",
             "amplifier_gain", "full_scale_v")
#: The speeds' parts a side file may also give (`video --side-file` writes them): of each phase
#: the normal and tangential components (m/s), the total speed (m/s) and the angle from the
#: surface normal (deg). The normal component wins over `impact_speed_m_s`; without it, the
#: total speed and the angle (or the tangential component) give it.
PHASES = ("impact", "rebound")
COMPONENT_KEYS = tuple(f"{phase}_{part}" for phase in PHASES for part in (
    "speed_normal_m_s", "speed_tangential_m_s", "speed_total_m_s", "angle_deg"))
#: Keys that describe a side file and are not read.
NOTE_KEYS = ("comment", "source")
#: Two speed parts that disagree by more than this fraction of the total speed are an error.
COMPONENT_TOLERANCE = 0.01


#: Force units a header may name -> newtons: 1 lbf = 4.4482216152605 N (exact: 0.45359237 kg times
#: standard gravity), 1 kgf = 9.80665 N.
LBF_N = 4.4482216152605
KGF_N = 9.80665
#: quantity -> unit as a header writes it (lower case) -> factor to SI. `volts` is a load-cell
#: signal, turned into newtons by the sensitivity (V/N) and the amplifier gain.
UNITS: dict[str, dict[str, float]] = {
    "time": {"s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6, "\u00b5s": 1e-6, "\u03bcs": 1e-6},
    "force": {"n": 1.0, "kn": 1e3, "lbf": LBF_N, "kgf": KGF_N},
    "velocity": {"m/s": 1.0, "m_s": 1.0},
    "volts": {"v": 1.0, "mv": 1e-3},
}
UNITS["tangential_force"] = UNITS["force"]
#: The names (lower case, words joined by `_`) that say which quantity a column holds; a header
#: gives its unit after the name: `name_unit`, `Name (unit)`, `Name [unit]` or `Name/unit`.
#: Load-cell channels (`ch1`, `channel2`, `ai0`) are voltages.
QUANTITY_NAMES: dict[str, tuple[str, ...]] = {
    "time": ("time", "t"),
    "force": ("force", "f", "fz", "fn", "load", "normal_force", "normal_load", "contact_force",
              "impact_force", "force_z"),
    "tangential_force": ("tangential_force", "tangential", "ft", "fx", "fy", "force_x",
                         "force_y", "shear_force", "friction_force", "tangential_load"),
    "velocity": ("velocity", "vel", "speed"),
    "volts": ("voltage", "volts", "signal"),
}
#: The flags that choose a column, by the quantity they choose.
CHOICE_FLAGS = {"time": "--time-column", "force": "--force-column"}
_RECORD_FIELD = {"time": "time_s", "force": "force_n", "tangential_force": "tangential_force_n",
                 "velocity": "velocity_m_s"}
_UNIT_LIST = {"time": "s, ms, us", "force": "N, kN, lbf, kgf",
              "tangential_force": "N, kN, lbf, kgf", "velocity": "m/s",
              "volts": "V, mV (with --sensitivity-v-per-n)"}


def _word(text: str) -> str:
    """A column's name as one word: lower case, spaces, dots and hyphens as `_`."""
    return re.sub(r"[\s.\-]+", "_", text.strip().lower()).strip("_")


def _named_quantity(word: str) -> str | None:
    for quantity, names in QUANTITY_NAMES.items():
        if word in names:
            return quantity
    if re.fullmatch(r"(ch|channel_?|ai)\d+", word):
        return "volts"
    return None


def _split_unit(name: str) -> tuple[str, str | None]:
    """A header cell as (name as one word, unit or None): `Name (unit)`, `Name [unit]`,
    `Name/unit`, or `name_unit` where the name is a known quantity's (any name for volts)."""
    bracket = re.fullmatch(r"(.*?)\s*[(\[]\s*([^()\[\]]*?)\s*[)\]]", name)
    if bracket:
        return _word(bracket[1]), bracket[2].strip().lower()
    if "/" in name:
        word, _, unit = name.partition("/")
        return _word(word), unit.strip().lower()
    word = _word(name)
    suffixes = sorted({u for units in UNITS.values() for u in units}, key=len, reverse=True)
    for unit in suffixes:
        stem = word[:-len(unit) - 1]
        if word.endswith("_" + unit) and stem and (
                _named_quantity(stem) is not None or unit in UNITS["volts"]):
            return stem, unit
    # a known name with a unit that is not known (force_kip): named, so the error can say so
    for known in sorted((n for names in QUANTITY_NAMES.values() for n in names if len(n) > 1),
                        key=len, reverse=True):
        rest = word[len(known) + 1:]
        if word.startswith(known + "_") and _named_quantity(word) is None and \
                re.fullmatch(r"[a-z\u00b5\u03bc]{1,4}", rest):
            return known, rest
    return word, None


@dataclass(eq=False)
class _Column:
    """A header cell read: `quantity` (a key of `UNITS`, or None: another channel), its factor
    to SI, and `problem`: why it cannot be used (no unit, an unknown unit), if so."""

    index: int
    name: str
    quantity: str | None
    factor: float = 1.0
    problem: str | None = None


def _classify(index: int, name: str) -> _Column:
    if name in CSV_COLUMNS:
        field, factor = CSV_COLUMNS[name]
        return _Column(index, name, _QUANTITY[field], factor)
    word, unit = _split_unit(name)
    named = _named_quantity(word)
    if unit is None:
        if named is None:
            return _Column(index, name, None)
        allowed = _UNITS_OF.get(named) or f"{word}_v, {word}_mv"
        example = f"{word} ({_UNIT_LIST[named].split(',')[0]})"
        return _Column(index, name, named, problem=f"column {name!r} has no unit; use one of "
                       f"{allowed} (or the unit after the name: '{example}')")
    by_unit = next((q for q in ("time", "force", "velocity", "volts") if unit in UNITS[q]), None)
    if named is None:
        return _Column(index, name, by_unit, UNITS[by_unit][unit] if by_unit else 1.0)
    if named in ("force", "tangential_force") and by_unit == "volts":
        return _Column(index, name, "volts", UNITS["volts"][unit])
    if unit in UNITS[named]:
        return _Column(index, name, named, UNITS[named][unit])
    return _Column(index, name, named, problem=(
        f"unknown column {name!r}: {unit!r} is not a unit of {named.replace('_', ' ')}; "
        f"allowed {_UNIT_LIST[named]}"))


def _chosen(path: Path, columns: list[_Column], given: Any, quantity: str) -> _Column:
    """The column a --time-column / --force-column flag names: a header name (any case) or a
    0-based position (as --channel counts)."""
    flag = CHOICE_FLAGS[quantity]
    text = str(given).strip()
    if (isinstance(given, (int, np.integer)) and not isinstance(given, bool)) or text.isdigit():
        position = int(text)
        if not 0 <= position < len(columns):
            raise InputError(f"{path}: {flag} {text}: the file has {len(columns)} columns, "
                             f"positions 0..{len(columns) - 1} (0 = the first, {columns[0].name})")
        return columns[position]
    found = [c for c in columns if c.name == text.lower()]
    if not found:
        raise InputError(f"{path}: {flag} {text!r}: no such column; the columns are "
                         f"{', '.join(c.name for c in columns)} (or give a 0-based position)")
    return found[0]


def _column_plan(path: Path, names: list[str], choice: dict[str, Any]) -> dict[str, Any]:
    """Which columns of a record CSV make the record: `fields` {field: (index, factor, column
    name)}, `volts` (the force column is a voltage), the columns `left_out` and `notes` about
    them."""
    if any(is_number(name) for name in names):
        raise InputError(f"{path}: first line is not a header; name the columns with units "
                         f"(e.g. time_s,force_n)")
    if any(name in FE_FORCE_COLUMNS for name in names):
        return _fe_plan(path, names, choice)
    columns = [_classify(k, name) for k, name in enumerate(names)]
    if not any(c.quantity == "time" for c in columns) and (RESULT_TABLE_COLUMNS & set(names)):
        raise InputError(f"{path}: a table of results (as fit --table, identify --table and "
                         "report write), not a test record; give the test's force record "
                         "(a time and a force column)")
    used: dict[str, _Column] = {}
    for quantity in ("time", "force"):  # the columns chosen first, then the others found
        flag, given = CHOICE_FLAGS[quantity], choice.get(quantity)
        if given is not None:
            column = _chosen(path, columns, given, quantity)
            if any(column is other for other in used.values()):
                raise InputError(f"{path}: --time-column and --force-column name the same "
                                 f"column, {column.name!r}")
            if column.problem:
                raise InputError(f"{path}: {flag} {given}: {column.problem}")
            wanted = ("force", "volts", "tangential_force") if quantity == "force" else ("time",)
            if column.quantity not in wanted:
                units = _UNIT_LIST[quantity] + (", or V, mV" if quantity == "force" else "")
                raise InputError(f"{path}: {flag} {given}: column {column.name!r} is not a "
                                 f"{quantity} column; its header must give a unit of "
                                 f"{quantity}: {units}")
            used[quantity] = column
    for quantity in ("time", "force"):
        if quantity in used:
            continue
        flag = CHOICE_FLAGS[quantity]
        found: list[_Column] = []
        for tier in ([("time",)] if quantity == "time" else [("force",), ("volts",)]):
            found = [c for c in columns if c.quantity in tier
                     and not any(c is u for u in used.values())]
            if found:
                break
        if len(found) > 1:
            described = ", ".join(c.name + (" (no unit)" if "no unit" in (c.problem or "")
                                            else "") for c in found)
            raise InputError(f"{path}: header names {quantity} twice ({described}); choose the "
                             f"column to read with {flag} NAME (or its 0-based position)")
        if not found:
            example = "Time (ms)" if quantity == "time" else "Force (kN)"
            raise InputError(f"{path}: no {quantity} column; add one of {_UNITS_OF[quantity]} "
                             f"(or a name with its unit, e.g. '{example}')")
        if found[0].problem:
            raise InputError(f"{path}: {found[0].problem}")
        used[quantity] = found[0]
    notes = []
    for quantity in ("velocity", "tangential_force"):
        found = [c for c in columns if c.quantity == quantity
                 and not any(c is u for u in used.values())]
        if len(found) == 1 and found[0].problem:
            raise InputError(f"{path}: {found[0].problem}")
        if len(found) == 1:
            used[quantity] = found[0]
        elif found:
            notes.append(f"{len(found)} {quantity.replace('_', ' ')} columns "
                         f"({', '.join(c.name for c in found)}) left out: which one is meant is "
                         "not known")
    left = [c.name or f"(unnamed, column {c.index})" for c in columns
            if not any(c is u for u in used.values())]
    return {"fields": {_RECORD_FIELD[q]: (c.index, c.factor, c.name) for q, c in used.items()},
            "volts": used["force"].quantity == "volts", "left_out": left, "notes": notes}


def _fe_plan(path: Path, names: list[str], choice: dict[str, Any]) -> dict[str, Any]:
    """An FE history of `simulate --csv`: its record columns by their exact names; its other
    columns (energies, centre motion) are not part of a record and are left out silently."""
    if any(value is not None for value in choice.values()):
        raise InputError(f"{path}: an FE history of simulate --csv; its columns are fixed: give "
                         "no --time-column or --force-column")
    fields: dict[str, tuple[int, float, str]] = {}
    for col, name in enumerate(names):
        if name in CSV_COLUMNS:
            field, factor = CSV_COLUMNS[name]
            if field in fields:
                raise InputError(f"{path}: header names {_QUANTITY[field]} twice")
            fields[field] = (col, factor, name)
    if "time_s" not in fields:
        raise InputError(f"{path}: no time column; add one of {_UNITS_OF['time']}")
    return {"fields": fields, "volts": False, "left_out": [], "notes": [], "fe": True}


def read_csv(
    path: str | Path,
    *,
    time_column: str | int | None = None,
    force_column: str | int | None = None,
    sensitivity_v_per_n: float | None = None,
    amplifier_gain: float | None = None,
) -> dict[str, Any]:
    """Columns of an impact CSV as SI arrays keyed by record field (an FE history's also holds
    `fe_lead_samples`: how many zero-force samples were put back before first contact).

    Headers name each column with its unit (module notes; docs/features.md, "Lab files").
    `time_column` and `force_column` choose a column by header name or 0-based position where
    several would do; the columns not read are left out with an `InputWarning` naming them (a
    measured record's dict also holds `columns`, the column read for each field, and
    `ignored_columns`). A force column in volts is turned into newtons by `sensitivity_v_per_n`
    (V/N) and `amplifier_gain` (default 1)."""
    path = Path(path)
    choice = {"time": time_column, "force": force_column}
    header: dict[str, Any] = {}

    def plan(names: list[str], _line: int) -> list[int]:
        if len(names) == 1:
            for separator, called in ((";", "semicolons"), ("\t", "tabs")):
                if separator in names[0]:
                    raise InputError(f"{path}: the columns are separated by {called}; separate "
                                     "them with commas (e.g. time_s,force_n)")
        header.update(_column_plan(path, names, choice))
        return [col for col, _, _ in header["fields"].values()]

    _, _, rows, table = read_table(path, "samples", plan)
    if not rows:
        raise InputError(f"{path}: the header has no samples below it")
    fields = header["fields"]
    out: dict[str, Any] = {field: table[:, col] * factor
                           for field, (col, factor, _) in fields.items()}
    if header["volts"]:
        out["force_n"] = out["force_n"] / _volts_per_newton(path, fields["force_n"][2],
                                                            sensitivity_v_per_n, amplifier_gain)
    if header.get("fe"):
        return _with_contact_start(out)
    for note in header["notes"]:
        warnings.warn(f"{path}: {note}", InputWarning, stacklevel=2)
    noted = " ".join(header["notes"])
    left = [name for name in header["left_out"] if name not in noted]
    if left:
        read = ", ".join(f"{name} as {field}" for field, (_, _, name) in fields.items())
        warnings.warn(f"{path}: column(s) {', '.join(left)} left out (read: {read}); choose "
                      "others with --time-column / --force-column", InputWarning, stacklevel=2)
    out["columns"] = {field: name for field, (_, _, name) in fields.items()}
    out["ignored_columns"] = header["left_out"]
    return out


def _volts_per_newton(path: Path, column: str, sensitivity: float | None,
                      gain: float | None) -> float:
    """The volts per newton of a force column in volts: sensitivity times gain (both checked)."""
    if sensitivity is None:
        raise InputError(f"{path}: sensitivity_v_per_n: the force column {column!r} is in volts; "
                         "give the load-cell sensitivity in V/N with --sensitivity-v-per-n "
                         "(e.g. 9.442e-5 for a PCB 223A; and the amplifier's gain with "
                         "--amplifier-gain)")
    try:
        return check_sensitivity(sensitivity) * check_positive(
            "amplifier_gain", 1.0 if gain is None else gain)
    except InputError as error:
        raise InputError(f"{path}: {error}") from None


def _with_contact_start(columns: dict[str, np.ndarray]) -> dict[str, Any]:
    """An FE history starts one step after first contact, in contact: put back the contact
    instant (t = 0, zero force) and zero-force samples before it at the first step's spacing, so
    that the record starts before the impact as a measured one does."""
    time, force = columns["time_s"], columns["force_n"]
    if not (time[0] > 0 and force[0] > 0):
        return {**columns, "fe_lead_samples": 0}
    lead = max(3, int(FE_LEAD_FRACTION * time.size))
    before = np.arange(-lead, 1) * time[0]
    out: dict[str, Any] = {name: np.concatenate([np.zeros(lead + 1), series])
                           for name, series in columns.items()}
    out["time_s"] = np.concatenate([before, time])
    out["fe_lead_samples"] = lead + 1
    return out


def read_wav(
    path: str | Path,
    *,
    sensitivity_v_per_n: float | None,
    amplifier_gain: float = 1.0,
    full_scale_v: float = 1.0,
    channel: int | None = None,
) -> dict[str, np.ndarray]:
    """Force samples of a WAV export as {time_s, force_n}, plus `full_scale_n`: the forces of the
    extreme codes, for the clipping check. A file with several channels needs `channel`
    (0 = first). A negative sensitivity inverts the signal (a load cell or amplifier whose
    output falls in compression)."""
    path = Path(path)
    if sensitivity_v_per_n is None:
        raise InputError(f"{path}: sensitivity_v_per_n: a WAV file needs the load-cell "
                         "sensitivity in V/N (e.g. --sensitivity-v-per-n 9.442e-5 for a PCB 223A)")
    try:
        sensitivity = check_sensitivity(sensitivity_v_per_n)
        gain = check_positive("amplifier_gain", amplifier_gain)
        full_scale = check_positive("full_scale_v", full_scale_v)
    except InputError as error:
        raise InputError(f"{path}: {error}") from None
    from scipy.io import wavfile

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


def check_sensitivity(value: Any) -> float:
    """A load-cell sensitivity (V/N): finite and not zero; negative for an inverted output."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"sensitivity_v_per_n: expected a number, got {value!r}") from None
    if not math.isfinite(number) or number == 0:
        raise InputError(f"sensitivity_v_per_n: must be finite and not 0 (V/N, e.g. 9.442e-5; "
                         f"negative for an inverted load cell), got {number:g}")
    return number


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
    """Scalars from a JSON side file: `SIDE_KEYS`, with the speeds as their normal components
    (see `COMPONENT_KEYS`); or from the JSON that `simulate --json` or `video --json` printed.
    Unknown keys and bad values are errors naming the file and the key. Values must be JSON
    numbers (not strings or booleans)."""
    path = Path(path)
    try:
        content = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise InputError(f"{path}: not a readable JSON file ({error})") from None
    if not isinstance(content, dict):
        raise InputError(f"{path}: expected a JSON object with keys {', '.join(SIDE_KEYS)}")
    try:
        if _written_by_simulate(content):
            return _simulate_scalars(content)
        if _written_by_video(content):
            return _video_scalars(content)
        return _side_scalars(content)
    except InputError as error:
        raise InputError(f"{path}: {error}") from None


def _side_scalars(content: dict[str, Any]) -> dict[str, float]:
    numbers = {}
    for key, value in content.items():
        if key in NOTE_KEYS:
            continue
        if key not in SIDE_KEYS + COMPONENT_KEYS:
            raise InputError(f"unknown key {key!r}; allowed: {', '.join(SIDE_KEYS)}, and the "
                             f"speeds' parts {', '.join(COMPONENT_KEYS)}")
        numbers[key] = _number(key, value)
    scalars = {}
    for key in ("mass_kg", "amplifier_gain", "full_scale_v"):
        if key in numbers:
            scalars[key] = check_positive(key, numbers[key])
    if "sensitivity_v_per_n" in numbers:
        scalars["sensitivity_v_per_n"] = check_sensitivity(numbers["sensitivity_v_per_n"])
    for phase in PHASES:
        speed = _normal_speed(phase, numbers)
        if speed is not None:
            scalars[f"{phase}_speed_m_s"] = speed
    return scalars


def _number(key: str, value: Any) -> float:
    """A side-file value that must be a JSON number (a string or a boolean is a slip)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{key}: expected a JSON number, got {json.dumps(value)} "
                         f"({type(value).__name__})")
    return float(value)


def _normal_speed(phase: str, numbers: dict[str, float]) -> float | None:
    """The speed normal to the surface of `phase` ("impact" or "rebound") from a side file's
    numbers: `{phase}_speed_normal_m_s`; else the total speed times the cosine of the angle (or
    from the total and tangential parts); else `{phase}_speed_m_s`. Parts that disagree are an
    error."""
    plain, normal, tangential, total, angle = (numbers.get(f"{phase}_{part}") for part in (
        "speed_m_s", "speed_normal_m_s", "speed_tangential_m_s", "speed_total_m_s", "angle_deg"))
    allow_zero = phase == "rebound"
    if angle is not None and not abs(angle) < 90:
        raise InputError(f"{phase}_angle_deg: {angle:g} deg; the angle from the surface normal "
                         "must lie between -90 and 90 deg")
    if total is not None:
        total = check_positive(f"{phase}_speed_total_m_s", total, allow_zero=allow_zero)
        if normal is None and angle is not None:
            normal = total * math.cos(math.radians(angle))
        elif normal is None and tangential is not None:
            normal = math.sqrt(max(total**2 - tangential**2, 0.0))
        elif normal is None and plain is None:
            raise InputError(f"{phase}_speed_total_m_s is the total speed; the force record "
                             f"needs its component normal to the surface: add "
                             f"{phase}_speed_normal_m_s (or {phase}_angle_deg, from the normal)")
    if normal is None:
        return None if plain is None else check_positive(f"{phase}_speed_m_s", plain,
                                                         allow_zero=allow_zero)
    if total is not None:
        _check_parts(phase, normal, tangential, total, angle)
    return check_positive(f"{phase}_speed_normal_m_s", normal, allow_zero=allow_zero)


def _check_parts(phase: str, normal: float, tangential: float | None, total: float,
                 angle: float | None) -> None:
    """`InputError` when the parts of a speed do not make its total (within
    `COMPONENT_TOLERANCE`): the normal component above it, or the normal and tangential
    components, or the normal component and the angle, giving another total."""
    totals = {"the normal component is": (normal, "at most")}
    if tangential is not None:
        totals["the normal and tangential components make"] = (math.hypot(normal, tangential),
                                                                "")
    if angle is not None:
        totals["the normal component and the angle make"] = (
            normal / max(math.cos(math.radians(angle)), 1e-12), "")
    for parts, (value, bound) in totals.items():
        above = value > total * (1 + COMPONENT_TOLERANCE)
        below = not bound and value < total * (1 - COMPONENT_TOLERANCE)
        if above or below:
            raise InputError(f"{phase}: {parts} {value:g} m/s, but "
                             f"{phase}_speed_total_m_s is {total:g} m/s: the speed's parts do "
                             "not add up (keys swapped?)")


def _written_by_simulate(content: dict[str, Any]) -> bool:
    """The JSON of `simulate --json`: the ball's name, its COR and its impact speed."""
    return isinstance(content.get("ball"), str) and {"cor", "impact_speed_m_s"} <= set(content)


def _simulate_scalars(content: dict[str, Any]) -> dict[str, float]:
    """Mass and normal speeds from `simulate --json`: an oblique (3d) run's impact speed is the
    total at `angle_deg` from the normal and its `cor` the normal COR."""
    if "mass_kg" not in content:
        raise InputError("the output of simulate has no mass_kg; add \"mass_kg\": the ball's "
                         "mass in kg (or give --mass-kg)")
    speed = check_positive("impact_speed_m_s", _number("impact_speed_m_s",
                                                        content["impact_speed_m_s"]))
    angle = _number("angle_deg", content.get("angle_deg", 0.0))
    cor = _number("cor", content.get("normal_cor", content["cor"]))
    normal = speed * math.cos(math.radians(angle))
    return {"mass_kg": check_positive("mass_kg", _number("mass_kg", content["mass_kg"])),
            "impact_speed_m_s": check_positive("impact_speed_m_s (normal component)", normal),
            "rebound_speed_m_s": max(cor, 0.0) * normal}


def _written_by_video(content: dict[str, Any]) -> bool:
    """The JSON of `video --json`: frame rate, scale and speeds."""
    return {"fps", "scale_m_per_px", "impact_speed_m_s", "rebound_speed_m_s"} <= set(content)


def _video_scalars(content: dict[str, Any]) -> dict[str, float]:
    """Normal speeds from `video --json` (its `*_speed_m_s` are the totals): the explicit
    normal components, or the totals times the cosines of the angles (older output)."""
    scalars = {}
    for phase in PHASES:
        key = f"{phase}_speed_normal_m_s"
        if key in content:
            numbers = {key: _number(key, content[key])}
        else:
            _check_video_keys(content, phase)
            numbers = {f"{phase}_{part}": _number(f"{phase}_{part}", content[f"{phase}_{part}"])
                       for part in ("speed_m_s", "angle_deg")}
            numbers[f"{phase}_speed_total_m_s"] = numbers.pop(f"{phase}_speed_m_s")
        scalars[f"{phase}_speed_m_s"] = _normal_speed(phase, numbers)
    if "mass_kg" in content:
        scalars["mass_kg"] = check_positive("mass_kg", _number("mass_kg", content["mass_kg"]))
    return scalars


def _check_video_keys(content: dict[str, Any], phase: str) -> None:
    """A `video --json` output without the normal speed of `phase` needs its total and angle
    (edited by hand, or cut short): `InputError` naming the missing keys."""
    missing = [f"{phase}_{part}" for part in ("speed_m_s", "angle_deg")
               if f"{phase}_{part}" not in content]
    if missing:
        raise InputError(f"no {phase}_speed_normal_m_s and no {' or '.join(missing)}: the "
                         f"output of `video --json` needs one of the two to give the normal "
                         f"{phase} speed; add {phase}_speed_normal_m_s (m/s)")


def load_record(path: str | Path, **given: Any) -> ImpactRecord:
    """An `ImpactRecord` from a CSV or WAV test file.

    Scalars come from the side file `path.with_suffix('.json')` if it exists, overridden by the
    keyword arguments that are not None: `mass_kg`, `impact_speed_m_s`, `rebound_speed_m_s`, and for
    WAV files `sensitivity_v_per_n`, `amplifier_gain`, `full_scale_v`, `channel`; for CSV files
    `time_column`, `force_column` (a header name or a 0-based position) and, for a force column
    in volts, `sensitivity_v_per_n` and `amplifier_gain`. `path` may name a built-in data set,
    `builtin:sample` (`datasets`). The record's metadata names its `file` (errors and warnings
    about it start with it), a CSV's `columns` read and `ignored_columns`, and marks the
    package's own records `builtin`.
    """
    path = resolve_builtin(path)
    if path.is_dir():
        raise InputError(f"{path}: is a folder; give a test record file (.csv, .txt or .wav)")
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    suffix = path.suffix.lower()
    if suffix == ".json":
        raise InputError(f"{path}: a JSON file is the side file of a record (or a verb's output), "
                         "not a test record; give the record itself (.csv, .txt or .wav) beside "
                         "it")
    if suffix not in (".wav", ".csv", ".txt"):
        raise InputError(f"{path}: unknown file type {suffix!r}; expected .csv or .wav")
    side = path.with_suffix(".json")
    scalars: dict[str, Any] = read_side_file(side) if side.is_file() else {}
    scalars.update({key: value for key, value in given.items() if value is not None})
    unknown = set(scalars) - set(SIDE_KEYS) - {"channel", "time_column", "force_column"}
    if unknown:
        raise TypeError(f"load_record: unexpected arguments {sorted(unknown)}")
    if suffix == ".wav":
        columns = read_wav(
            path,
            sensitivity_v_per_n=scalars.get("sensitivity_v_per_n"),
            amplifier_gain=scalars.get("amplifier_gain", 1.0),
            full_scale_v=scalars.get("full_scale_v", 1.0),
            channel=scalars.get("channel"),
        )
    else:
        columns = read_csv(path, time_column=scalars.get("time_column"),
                           force_column=scalars.get("force_column"),
                           sensitivity_v_per_n=scalars.get("sensitivity_v_per_n"),
                           amplifier_gain=scalars.get("amplifier_gain"))
    metadata: dict[str, Any] = {"source": str(path), "file": str(path)}
    if side.is_file():
        metadata["side_file"] = str(side)
    # the package's own records (the sample, the speed set): see `process(warn_noisy=...)`
    if path.resolve().is_relative_to(DATA):
        metadata["builtin"] = True
    for key in ("full_scale_n", "fe_lead_samples", "columns", "ignored_columns"):
        if key in columns:
            metadata[key] = columns.pop(key)
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
