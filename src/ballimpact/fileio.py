"""Files written so that an interrupt never leaves half of one, NPZ files read without
unpickling anything, and the CSV tables with a unit header: every table the package writes goes
through `table_text` / `write_table`, and the test readers share `read_table`.

`replacing(path)` yields a temporary path beside `path` (`STEM.tmp.SUFFIX`: the same folder, so
the rename is atomic on POSIX, and the same suffix, which some writers need: `np.savez` appends
`.npz` to a name without it). The caller writes it; on success it is renamed over `path`, on an
exception it is deleted. A killed process (no exception) leaves only the temporary file, which
the next write replaces; the old `path`, or none, stays whole.
"""

from __future__ import annotations

import math
import numbers
import os
import zipfile
import zlib
from collections.abc import Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputError


def temporary_path(path: Path) -> Path:
    """Where `replacing` writes `path` first: STEM.tmp.SUFFIX beside it."""
    path = Path(path)
    return path.with_name(f"{path.stem}.tmp{path.suffix}")


@contextmanager
def replacing(path: Path) -> Iterator[Path]:
    """A temporary path to write; renamed over `path` when the block ends without an exception,
    deleted when it raises (Ctrl-C included)."""
    tmp = temporary_path(path)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_atomic(path: Path, text: str) -> None:
    """Write `text` to `path` through `replacing`: the old file or the new one, never a part."""
    with replacing(path) as tmp:
        tmp.write_text(text)


#: the number format of a table when its writer names none: 10 significant digits
TABLE_NUMBER_FORMAT = ".10g"


def table_cell(value: Any, number_format: str = TABLE_NUMBER_FORMAT) -> str:
    """One CSV cell: a real number in `number_format` (a format spec: ".10g"; "" for the shortest
    text that reads back to the same float), an integer in full, a non-finite number or None
    empty, a bool or text as written, quoted (RFC 4180) where it holds a comma, a quote or a line
    break."""
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        return format(float(value), number_format) if math.isfinite(value) else ""
    text = str(value)
    if any(c in text for c in ',"\r\n'):
        return '"' + text.replace('"', '""') + '"'
    return text


def table_text(columns: Sequence[str], rows: Iterable[Sequence[Any]],
               number_format: str = TABLE_NUMBER_FORMAT) -> str:
    """A CSV table: the header `columns` (each name ending in its SI unit: `time_s`, `force_n`;
    none for a ratio), then a line per row of `rows` (a sequence in the columns' order, or a
    mapping from column name to value), cells by `table_cell` with `number_format`, each line
    ending in a line feed. Raises ValueError for a row with another number of cells."""
    columns = list(columns)
    lines = [",".join(table_cell(name) for name in columns)]
    for row in rows:
        row = [row[name] for name in columns] if isinstance(row, Mapping) else list(row)
        if len(row) != len(columns):
            raise ValueError(f"table row {len(lines)}: {len(row)} cells for {len(columns)} "
                             "columns")
        lines.append(",".join(table_cell(value, number_format) for value in row))
    return "\n".join(lines) + "\n"


def column_rows(*arrays) -> list[list[float]]:
    """The rows of equal-length column arrays (a history: one array per column), for
    `table_text` / `write_table`."""
    return np.column_stack([np.asarray(a, dtype=float) for a in arrays]).tolist()


def write_table(path: Path, columns: Sequence[str], rows: Iterable[Sequence[Any]],
                number_format: str = TABLE_NUMBER_FORMAT) -> str:
    """`table_text` written to `path` through `replacing` (never half a table). Returns the path
    as text (for a command's JSON)."""
    write_atomic(Path(path), table_text(columns, rows, number_format))
    return str(path)


def check_plot_path(path: Path | None, flag: str = "--plot") -> None:
    """Refuse, before a run, a plot path that is not a .png file in an existing folder."""
    check_output_file(path, flag, ".png")


def check_output_file(path: Path | None, flag: str, suffix: str) -> None:
    """Refuse, before a run, an output file that does not end in `suffix` (".csv") or whose
    folder does not exist."""
    if path is not None and Path(path).suffix.lower() != suffix:
        raise InputError(f"{flag}: {path} must be a {suffix} file")
    check_output_folder(path, flag)


def check_output_folder(path: Path | None, flag: str) -> None:
    """Refuse, before a run, an output file whose folder does not exist."""
    if path is not None and not Path(path).parent.is_dir():
        raise InputError(f"{flag}: folder {Path(path).parent} does not exist")


def first_line(error: BaseException) -> str:
    """The first line of an error's message (its type's name if it has none), for one-line
    `InputError`s about a damaged file."""
    return (str(error).strip().splitlines() or [type(error).__name__])[0]


def check_distinct_files(paths: list[Path], label: str) -> list[Path]:
    """Each file of `paths` (the positional argument `label`, e.g. TEST) given once: the same
    file under two spellings (a.csv and ./a.csv) counts as twice, so paths are compared
    resolved. Returns the resolved paths."""
    seen: dict[Path, Path] = {}
    for path in paths:
        key = path.resolve()
        if key in seen:
            spelling = f" (as {seen[key]})" if str(seen[key]) != str(path) else ""
            raise InputError(f"{label}: {path} is given twice{spelling}; give each file once")
        seen[key] = path
    return list(seen)


def read_arrays(npz: Path, where: str, what: str) -> dict[str, np.ndarray]:
    """The arrays of an NPZ file without unpickling anything (`allow_pickle=False`). A damaged,
    truncated or foreign file gives `InputError` naming it (`where`) and saying it is not `what`
    ("a universal model's weights")."""
    try:
        data = np.load(npz, allow_pickle=False)
        if not isinstance(data, np.lib.npyio.NpzFile):
            raise InputError(f"{where}: a single array (.npy), not an NPZ archive of {what}")
        with data:
            return {key: _array(data, key, where, what) for key in data.files}
    except InputError:
        raise
    except ValueError as error:
        if "pickle" in str(error):  # what np.load cannot read as arrays it would unpickle
            raise InputError(f"{where}: not an NPZ archive (reading it would mean unpickling "
                             "it; refused unread)") from None
        raise InputError(f"{where}: not {what} ({first_line(error)})") from None
    except (OSError, EOFError, zipfile.BadZipFile, zlib.error) as error:
        # a truncated archive: BadZipFile (no central directory) or zlib/EOF errors inside
        raise InputError(f"{where}: not a readable NPZ archive (damaged or truncated: "
                         f"{type(error).__name__}: {first_line(error)})") from None


def _array(data, key: str, where: str, what: str) -> np.ndarray:
    try:
        return data[key]
    except ValueError as error:
        if "allow_pickle" not in str(error):
            raise
        raise InputError(f"{where}: not {what}: array {key} holds Python objects (a pickle), "
                         "refused unread") from None


def read_table(path: Path, what: str = "rows", header=None) -> tuple[int, list[str], list[int],
                                                                    np.ndarray]:
    """A CSV test file as (header line number, column names lower-cased, the line number of each
    row, the values (rows, columns)): lines starting with `#` and blank lines are skipped, the
    first other line is the header. `header(names, line)`, when given, checks the names (on
    line number `line`) before any
    value is read and returns the indices of the columns to read (None: all); the others are
    left NaN. `InputError` naming the file, and the line and column of a value: a file that
    cannot be read or holds no header (`what` names its rows in that message), a row with
    another number of values than the header, a value that is not a finite number. The callers
    check the number of rows and the values' ranges. `path` may name a built-in data set
    (`builtin:treloar-uniaxial`, `datasets.resolve`)."""
    from .records.datasets import resolve  # `builtin:NAME`: the package's own data sets

    path = resolve(path)
    if path.is_dir():
        raise InputError(f"{path}: is a folder; give a CSV file")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(f"{path}: cannot read ({error})") from None
    lines = [(number, line.strip()) for number, line in enumerate(text.splitlines(), start=1)]
    lines = [(number, line) for number, line in lines if line and not line.startswith("#")]
    if not lines:
        raise InputError(f"{path}: the file is empty (no header, no {what})")
    header_line, text_header = lines[0]
    names = [name.strip().lower() for name in text_header.split(",")]
    read = header(names, header_line) if header is not None else None
    read = range(len(names)) if read is None else read
    values = np.full((len(lines) - 1, len(names)), np.nan)
    for row, (number, line) in enumerate(lines[1:]):
        cells = line.split(",")
        if len(cells) != len(names):
            raise InputError(f"{path}: line {number} has {len(cells)} values, the header "
                             f"{len(names)}")
        for col in read:
            try:
                value = float(cells[col])
            except ValueError:
                raise InputError(f"{path}: line {number}, column {names[col]}: "
                                 f"{cells[col].strip()!r} is not a number") from None
            if not math.isfinite(value):
                raise InputError(f"{path}: line {number}, column {names[col]}: "
                                 f"{cells[col].strip()!r} is not a finite number")
            values[row, col] = value
    return header_line, names, [number for number, _ in lines[1:]], values


def is_number(text: str) -> bool:
    """Whether `text` reads as a float (a header cell that is a number: the header is missing)."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def json_safe(value):
    """`value` with its non-finite floats (invalid in JSON) replaced by None, through dicts,
    lists and tuples."""
    if isinstance(value, dict):
        return {key: json_safe(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(item) for item in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def packaged_json_files(folder: str) -> dict[str, Any]:
    """The JSON files shipped in the package's `folder` (e.g. "data/bats"), by name without
    ".json", sorted (resources; an empty dict where the folder is missing)."""
    from importlib import resources

    where = resources.files("ballimpact").joinpath(folder)
    if not where.is_dir():
        return {}
    files = [f for f in where.iterdir() if f.name.endswith(".json")]
    return {f.name[:-len(".json")]: f for f in sorted(files, key=lambda f: f.name)}


def read_spec_file(path: Path, what: str) -> Any:
    """A specification file (`what`: "ball", "bat", ...) as parsed JSON, or TOML for a `.toml`
    suffix; `InputError` naming the file for one that cannot be read or parsed."""
    import json

    path = Path(path)
    suffix = path.suffix.lower()
    try:
        if suffix == ".toml":
            try:
                import tomllib
            except ModuleNotFoundError:  # Python 3.10
                try:
                    import tomli as tomllib  # type: ignore[no-redef]
                except ModuleNotFoundError:
                    raise InputError(f"{path}: reading TOML needs Python 3.11 or the 'tomli' "
                                     f"package; use JSON") from None
            with open(path, "rb") as f:
                return tomllib.load(f)
        return json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError(f"{path}: cannot read the {what} file ({exc.strerror or exc})") from None
    except (ValueError, UnicodeDecodeError) as exc:  # JSONDecodeError, TOMLDecodeError
        kind = "TOML" if suffix == ".toml" else "JSON"
        raise InputError(f"{path}: not valid {kind} ({exc})".replace("\n", " ")) from None
