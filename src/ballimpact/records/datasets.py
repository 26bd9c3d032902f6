"""The package's own data by name: the sample test, the speed set, Treloar's rubber tests and the
oblique-rebound measurements, each with what it is, its source and its files.

A file argument of any verb may name a data set as `builtin:NAME` (or `builtin:NAME/FILE`, one
file of a folder set) instead of a path: `resolve` turns it into the installed path, in the few
places where file arguments are read (`loaders.load_record`, `repeats.expand_records`,
`fileio.read_table`). `ballimpact data list` shows the sets and `ballimpact data copy NAME DEST`
copies their files out (docs/features.md, "Built-in data by name").
"""

from __future__ import annotations

import difflib
import shutil
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError

#: The prefix that marks a built-in data set in a file argument.
PREFIX = "builtin:"
#: The installed data folder.
DATA = Path(__file__).resolve().parents[1] / "data"

_TRELOAR = ("Treloar, L.R.G. (1944) Trans. Faraday Soc. 40:59-70: vulcanised natural rubber; "
            "numbers as tabulated in the file's comment lines")
_KHARAZ = ("Kharaz, Gorham & Salman (2001) Powder Technology 120:281-291, digitised (see the "
           "file's comment lines)")


@dataclass(frozen=True)
class DataSet:
    """One built-in data set. `path` is its file or folder inside the data folder; `files` the
    files it is made of (a record's side file included); `kind` what it is ("record", "records",
    "material test", "table"); `usage` an example of its use."""

    name: str
    kind: str
    description: str
    source: str
    path: str
    files: tuple[str, ...]
    usage: str

    @property
    def location(self) -> Path:
        return DATA / self.path

    def to_dict(self) -> dict:
        return {"name": self.name, "argument": PREFIX + self.name, "kind": self.kind,
                "description": self.description, "source": self.source,
                "files": list(self.files), "path": str(self.location), "usage": self.usage}


_SPEED_FILES = tuple(f"speed_set/synthetic_{v}_m_s.{ext}" for v in ("05.5", "10.0", "20.8", "25.0")
                     for ext in ("csv", "json")) + ("speed_set/synthetic-3layer.json",)

#: name -> data set
DATASETS: dict[str, DataSet] = {d.name: d for d in (
    DataSet("sample", "record",
            "SYNTHETIC impact test: a Hunt-Crossley ball (0.16 kg) at 20.8 m/s dressed as a "
            "load-cell record (offset, 14 kHz ringing, 1% noise, 200 kHz); side file with the "
            "mass and speeds",
            "examples/make_sample_record.py (not a measurement)",
            "sample_impact.csv", ("sample_impact.csv", "sample_impact.json"),
            "ballimpact features builtin:sample"),
    DataSet("speed-set", "records",
            "SYNTHETIC tests of a three-layer FE ball (0.16 kg) at 5.5, 10, 20.8 and 25 m/s, "
            "100 kHz with 1% noise, side files with the speeds; the generating ball "
            "synthetic-3layer.json",
            "examples/make_speed_set.py (not a measurement)",
            "speed_set", _SPEED_FILES,
            "ballimpact fit builtin:speed-set --model single_element"),
    DataSet("treloar-uniaxial", "material test",
            "Treloar's uniaxial tension of vulcanised rubber: stretch, nominal stress (MPa)",
            _TRELOAR, "treloar1944_uniaxial.csv", ("treloar1944_uniaxial.csv",),
            "ballimpact material fit builtin:treloar-uniaxial:uniaxial --model ogden"),
    DataSet("treloar-biaxial", "material test",
            "Treloar's equibiaxial tension of vulcanised rubber: stretch, nominal stress (MPa)",
            _TRELOAR, "treloar1944_biaxial.csv", ("treloar1944_biaxial.csv",),
            "ballimpact material fit builtin:treloar-biaxial:biaxial --model ogden"),
    DataSet("treloar-planar", "material test",
            "Treloar's pure shear (planar tension) of vulcanised rubber: stretch, nominal stress "
            "(MPa)",
            _TRELOAR, "treloar1944_planar.csv", ("treloar1944_planar.csv",),
            "ballimpact material fit builtin:treloar-planar:planar --model ogden"),
    DataSet("kharaz-tangential-cor", "table",
            "Alumina spheres on glass at 3.9 m/s: tangential COR against the angle from the "
            "normal (deg)",
            _KHARAZ, "kharaz2001_tangential_cor.csv", ("kharaz2001_tangential_cor.csv",),
            "ballimpact data copy kharaz-tangential-cor ."),
    DataSet("kharaz-rebound-spin", "table",
            "Alumina spheres on glass at 3.9 m/s: rebound spin (rad/s) against the angle from "
            "the normal (deg)",
            _KHARAZ, "kharaz2001_rebound_spin.csv", ("kharaz2001_rebound_spin.csv",),
            "ballimpact data copy kharaz-rebound-spin ."),
)}


def is_builtin(path: str | Path) -> bool:
    """Whether a file argument names a built-in data set (`builtin:NAME`)."""
    return str(path).lower().startswith(PREFIX)


def get(name: str) -> DataSet:
    """The data set `name`; `InputError` naming the allowed names (and the nearest) otherwise."""
    key = name.strip().lower()
    if key in DATASETS:
        return DATASETS[key]
    nearest = difflib.get_close_matches(key, list(DATASETS), n=1, cutoff=0.5)
    hint = f" (did you mean {PREFIX}{nearest[0]}?)" if nearest else ""
    raise InputError(f"{PREFIX}{name}: not a built-in data set{hint}; allowed: "
                     f"{', '.join(DATASETS)} (ballimpact data list)")


def resolve(path: str | Path) -> Path:
    """`path` itself, or for `builtin:NAME` the installed file or folder of the data set, and for
    `builtin:NAME/FILE` that file of a folder set (an `InputError` names a missing one)."""
    if not is_builtin(path):
        return Path(path)
    text = str(path)[len(PREFIX):]
    name, _, rest = text.partition("/")
    found = get(name).location
    if rest:
        inside = [f.split("/", 1)[1] for f in get(name).files if "/" in f]
        if not found.is_dir() or rest not in inside:
            allowed = ", ".join(f for f in inside if not f.endswith(".json")) or "none"
            raise InputError(f"{path}: no such file in {PREFIX}{name}; its records: {allowed}")
        found = found / rest
    return found


def copy(name: str, dest: str | Path, *, overwrite: bool = False) -> list[Path]:
    """Copy the files of data set `name` into the folder `dest` (made if its parent exists): a
    folder set as a folder of its own (`dest/speed_set/`), the others file by file. Files that
    exist are an `InputError` unless `overwrite`. Returns the paths written."""
    data = get(name)
    dest = Path(dest)
    if dest.exists() and not dest.is_dir():
        raise InputError(f"DEST {dest}: is a file; give a folder to copy {PREFIX}{data.name} "
                         "into")
    if not dest.exists() and not dest.parent.is_dir():
        raise InputError(f"DEST {dest}: folder {dest.parent} does not exist")
    targets = [(DATA / f, dest / f) for f in data.files]
    existing = [str(t) for _, t in targets if t.exists()]
    if existing and not overwrite:
        raise InputError(f"DEST {dest}: {', '.join(existing)} exist(s); give another folder or "
                         "--force to overwrite")
    for source, target in targets:
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, target)
    return [t for _, t in targets]
