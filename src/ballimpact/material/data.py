"""Material test data: CSV files of one test each, read into SI arrays and checked.

The format is that of the impact records (`loaders.read_csv`): lines starting with `#` are
comments, the first other line is a header naming each column with its unit, values are
converted to SI. A test file holds one mode (docs: "Material tests"):

| mode | columns |
|---|---|
| `uniaxial` | `stretch`, `nominal_stress_pa` (tension and compression) |
| `biaxial` | `stretch_1`, `stretch_2`, `nominal_stress_1_pa`, `nominal_stress_2_pa`; equibiaxial: `stretch`, `nominal_stress_pa` |
| `planar` | `stretch`, `nominal_stress_pa` (pure shear) |
| `volumetric` | `volume_ratio`, `pressure_pa` |
| `relaxation` | `time_s`, `relaxation_modulus_ratio` or `relaxation_modulus_pa` |
| `creep` | `time_s`, `creep_compliance_ratio` or `creep_compliance_per_pa` |
| `dma` | `frequency_hz`, `storage_modulus_pa`, `loss_modulus_pa`, optional `temperature_c` |

Unit variants: stresses, pressures and moduli in `_pa`, `_kpa` or `_mpa`; a stretch may be given
as engineering `strain` (a fraction) or `strain_pct` (%), stretch = 1 + strain; `time_ms`. A
modulus (compliance) column is normalised by its first value, the instantaneous one.
Every error names the file and, for a value, its 1-based line and its column.

Signs: tension positive (a compressive strain and a compressive nominal stress are negative).
Data written compression-positive (the common lab sign: strain > 0 and stress > 0 in
compression) are read with `compression_positive=True` (`material fit --compression-positive`),
which negates the strain and stress columns of uniaxial, biaxial and planar tests (a `stretch`
column is a ratio with no sign convention and is kept). `compression` and `tension` are
uniaxial tests declared as such (`FILE:compression`): their stretches must stay on that side of
1, and a file that reads the other way round is refused with the flag as the hint.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..checks import range_text
from ..errors import InputError, InputWarning
from ..fileio import is_number, read_table

#: test modes and the file's quantities (SI names); alternatives separated by '|'
MODES = ("uniaxial", "biaxial", "planar", "volumetric", "relaxation", "creep", "dma")
STRESS_MODES = ("uniaxial", "biaxial", "planar", "volumetric")
VISCOELASTIC_MODES = ("relaxation", "creep", "dma")
#: uniaxial tests declared as one branch (`FILE:compression`): the name -> the side of stretch 1
DECLARED_MODES = {"compression": "uniaxial", "tension": "uniaxial"}
#: modes whose strain and stress columns `compression_positive` negates
SIGNED_MODES = ("uniaxial", "biaxial", "planar")
#: the command line's name of `compression_positive` (named in the messages)
COMPRESSION_POSITIVE_FLAG = "--compression-positive"
#: measured ratios are normalised by a measured instantaneous value, so noise can put early points
#: a little past 1: accepted up to this slack (beyond it the data are not normalised)
RATIO_SLACK = 0.05

_PRESSURE_UNITS = {"pa": 1.0, "kpa": 1e3, "mpa": 1e6}
_COMPLIANCE_UNITS = {"per_pa": 1.0, "per_kpa": 1e-3, "per_mpa": 1e-6}


def _stretch_names(suffix: str = "") -> dict[str, tuple[str, float, float]]:
    """name -> (SI quantity, factor, offset): stretch = offset + factor * value."""
    q = f"stretch{suffix}"
    return {f"stretch{suffix}": (q, 1.0, 0.0), f"strain{suffix}": (q, 1.0, 1.0),
            f"strain{suffix}_pct": (q, 0.01, 1.0)}


def _with_units(stem: str, quantity: str, units: dict[str, float]) -> dict[str, tuple]:
    return {f"{stem}_{unit}": (quantity, factor, 0.0) for unit, factor in units.items()}


_STRESS = _with_units("nominal_stress", "nominal_stress_pa", _PRESSURE_UNITS)
_TIME = {"time_s": ("time_s", 1.0, 0.0), "time_ms": ("time_s", 1e-3, 0.0)}

#: mode -> column name -> (SI quantity, factor, offset)
COLUMNS: dict[str, dict[str, tuple[str, float, float]]] = {
    "uniaxial": {**_stretch_names(), **_STRESS},
    "planar": {**_stretch_names(), **_STRESS},
    "biaxial": {**_stretch_names(), **_STRESS, **_stretch_names("_1"), **_stretch_names("_2"),
                **_with_units("nominal_stress_1", "nominal_stress_1_pa", _PRESSURE_UNITS),
                **_with_units("nominal_stress_2", "nominal_stress_2_pa", _PRESSURE_UNITS)},
    "volumetric": {"volume_ratio": ("volume_ratio", 1.0, 0.0),
                   **_with_units("pressure", "pressure_pa", _PRESSURE_UNITS)},
    "relaxation": {**_TIME, "relaxation_modulus_ratio": ("relaxation_modulus_ratio", 1.0, 0.0),
                   **_with_units("relaxation_modulus", "relaxation_modulus_pa", _PRESSURE_UNITS)},
    "creep": {**_TIME, "creep_compliance_ratio": ("creep_compliance_ratio", 1.0, 0.0),
              **_with_units("creep_compliance", "creep_compliance_per_pa", _COMPLIANCE_UNITS)},
    "dma": {"frequency_hz": ("frequency_hz", 1.0, 0.0),
            **_with_units("storage_modulus", "storage_modulus_pa", _PRESSURE_UNITS),
            **_with_units("loss_modulus", "loss_modulus_pa", _PRESSURE_UNITS),
            "temperature_c": ("temperature_c", 1.0, 0.0)},
}

#: mode -> the sets of quantities a file may hold (the first that is complete is used)
REQUIRED: dict[str, tuple[tuple[str, ...], ...]] = {
    "uniaxial": (("stretch", "nominal_stress_pa"),),
    "planar": (("stretch", "nominal_stress_pa"),),
    "biaxial": (("stretch_1", "stretch_2", "nominal_stress_1_pa", "nominal_stress_2_pa"),
                ("stretch", "nominal_stress_pa")),
    "volumetric": (("volume_ratio", "pressure_pa"),),
    "relaxation": (("time_s", "relaxation_modulus_ratio"), ("time_s", "relaxation_modulus_pa")),
    "creep": (("time_s", "creep_compliance_ratio"), ("time_s", "creep_compliance_per_pa")),
    "dma": (("frequency_hz", "storage_modulus_pa", "loss_modulus_pa"),),
}
_OPTIONAL = {"dma": ("temperature_c",)}


@dataclass(frozen=True)
class MaterialTest:
    """One material test in SI: `columns` maps quantity names (`stretch`, `nominal_stress_pa`,
    `volume_ratio`, `pressure_pa`, `time_s`, `relaxation_modulus_ratio`, ...) to arrays.
    `lines` holds the file's 1-based line number of each row."""

    path: Path
    mode: str
    columns: dict[str, np.ndarray]
    lines: tuple[int, ...] = ()

    @property
    def deformation(self) -> str:
        """The deformation a stress test imposes: uniaxial, equibiaxial, biaxial (general),
        planar or volumetric; the mode itself for the viscoelastic tests."""
        if self.mode == "biaxial" and "stretch_1" not in self.columns:
            return "equibiaxial"
        return self.mode

    @property
    def size(self) -> int:
        return int(next(iter(self.columns.values())).size)

    @property
    def name(self) -> str:
        return self.path.name

    def stretch_range(self) -> tuple[float, float]:
        """(smallest, largest) principal stretch the test imposes along its loaded axes."""
        keys = [k for k in ("stretch", "stretch_1", "stretch_2") if k in self.columns]
        values = np.concatenate([self.columns[k] for k in keys])
        return float(values.min()), float(values.max())


def parse_spec(text: str) -> tuple[Path, str]:
    """`FILE:MODE` (the command line's test argument) -> (path, mode); MODE one of `MODES` or
    `DECLARED_MODES` (`compression`, `tension`: a uniaxial test of that branch)."""
    path, sep, mode = str(text).rpartition(":")
    allowed = (*MODES, *DECLARED_MODES)
    if not sep or mode.strip().lower() not in allowed:
        raise InputError(f"{text}: give the test as FILE:MODE with MODE one of "
                         f"{', '.join(allowed)}")
    return Path(path), mode.strip().lower()


def base_mode(mode: str) -> str:
    """The mode a test is read as: `compression` and `tension` are uniaxial tests."""
    return DECLARED_MODES.get(mode, mode)


def read_test(path: str | Path, mode: str, *, compression_positive: bool = False) -> MaterialTest:
    """Read and check one test file of `mode` (see the module docstring). `mode` may be
    `compression` or `tension` (a uniaxial test of that branch, checked to be one; the test's
    `mode` is then `uniaxial`). `compression_positive`: the file's strains and stresses are
    positive in compression (uniaxial, biaxial, planar tests); they are negated on reading."""
    path = Path(path)
    declared = mode if mode in DECLARED_MODES else None
    mode = base_mode(mode)
    if mode not in MODES:
        raise InputError(f"{path}: mode {mode!r}; allowed {', '.join((*MODES, *DECLARED_MODES))}")
    # the header is checked before any value is read
    _, names, lines, values = read_table(path, "values",
                                         lambda names, _: _header(path, mode, names) and None)
    quantities = _header(path, mode, names)
    if len(lines) < 2:
        raise InputError(f"{path}: {len(lines)} row(s) of values; a test needs at least 2")
    columns, column_of = {}, {}
    flip = compression_positive and mode in SIGNED_MODES
    for col, name in enumerate(names):
        quantity, factor, offset = COLUMNS[mode][name]
        if quantity in quantities:
            # compression-positive: strain and nominal stress negated (a stretch is kept)
            sign = -1.0 if flip and name.startswith(("strain", "nominal_stress")) else 1.0
            columns[quantity] = offset + factor * (sign * values[:, col])
            column_of[quantity] = name
    test = MaterialTest(path=path, mode=mode, columns=columns, lines=tuple(lines))
    if mode in SIGNED_MODES:
        _check_sign_convention(test, column_of, declared, compression_positive)
    _CHECKS[mode](test, column_of)
    _warn_unit_slips(test, column_of)
    return test


#: below this largest stress or modulus (Pa) no rubber or foam test reads: MPa given as Pa
SMALLEST_PLAUSIBLE_PA = 1e3
#: above this stretch from an engineering-strain column, percent was given as a fraction
LARGEST_PLAUSIBLE_STRETCH = 10.0


def _warn_unit_slips(test: MaterialTest, column_of: dict[str, str]) -> None:
    """Warnings (the data may be right) for the two slips that fit silently: stresses in MPa
    under a `_pa` header, and percent under a `strain` header."""
    for quantity in ("nominal_stress_pa", "nominal_stress_1_pa", "nominal_stress_2_pa",
                     "pressure_pa", "storage_modulus_pa"):
        name = column_of.get(quantity, "")
        if not name.endswith("_pa") or quantity not in test.columns:
            continue
        largest = float(np.max(np.abs(test.columns[quantity])))
        if 0.0 < largest < SMALLEST_PLAUSIBLE_PA:
            warnings.warn(f"{test.path}: column {name}: the largest value is {largest:g} Pa, "
                          f"below {SMALLEST_PLAUSIBLE_PA:g} Pa, less than any rubber or foam test "
                          f"reads: MPa given as Pa? (then name it {name[:-3]}_mpa)",
                          InputWarning, stacklevel=3)
    for quantity in ("stretch", "stretch_1", "stretch_2"):
        name = column_of.get(quantity, "")
        if name.startswith("strain") and not name.endswith("_pct"):
            largest = float(np.max(test.columns[quantity]))
            if largest > LARGEST_PLAUSIBLE_STRETCH:
                warnings.warn(f"{test.path}: column {name}: stretches up to {largest:g} (strain "
                              f"{largest - 1.0:g}): percent given as a fraction? (then name the "
                              f"column {name}_pct)", InputWarning, stacklevel=3)


def _header(path: Path, mode: str, names: list[str]) -> tuple[str, ...]:
    """The quantities the file's columns give (one of REQUIRED[mode], plus optional ones)."""
    allowed = COLUMNS[mode]
    seen: dict[str, str] = {}
    for name in names:
        if name not in allowed:
            if is_number(name):
                raise InputError(f"{path}: the first line is not a header; name the columns "
                                 f"with units (e.g. {','.join(REQUIRED[mode][0])})")
            raise InputError(f"{path}: unknown column {name!r} for a {mode} test; allowed: "
                             f"{', '.join(allowed)}")
        quantity = allowed[name][0]
        if quantity in seen:
            raise InputError(f"{path}: columns {seen[quantity]!r} and {name!r} both give "
                             f"{quantity}; keep one")
        seen[quantity] = name
    for required in REQUIRED[mode]:
        if all(q in seen for q in required):
            extra = [q for q in seen if q not in required and q not in _OPTIONAL.get(mode, ())]
            if extra:
                raise InputError(f"{path}: column {seen[extra[0]]!r} does not belong with "
                                 f"{', '.join(seen[q] for q in required)} in a {mode} test")
            return required + tuple(q for q in _OPTIONAL.get(mode, ()) if q in seen)
    wanted = " or ".join(", ".join(r) for r in REQUIRED[mode])
    missing = next(q for q in REQUIRED[mode][0] if q not in seen)
    accepted = ", ".join(n for n, spec in allowed.items() if spec[0] == missing)
    raise InputError(f"{path}: no {missing} column (accepted: {accepted}); a {mode} test needs "
                     f"{wanted}")


# ---- checks per mode ----------------------------------------------------------------------------
def _fail(test: MaterialTest, row: int, column: str, what: str) -> None:
    raise InputError(f"{test.path}: line {test.lines[row]}, column {column}: {what}")


def _positive(test: MaterialTest, quantity: str, column: str, note: str = "") -> None:
    """Every value of `quantity` > 0, else `_fail` at the first row that is not: the file, line
    and column, then the one message shape of `checks.range_text`."""
    values = test.columns[quantity]
    bad = np.flatnonzero(~(values > 0))
    if bad.size:
        _fail(test, bad[0], column, range_text(quantity, values[bad[0]], "allowed range", 0.0,
                                               math.inf, low_open=True, note=note))


def _monotone(test: MaterialTest, quantity: str, column: str) -> None:
    """Strictly increasing or strictly decreasing (a loading curve)."""
    step = np.diff(test.columns[quantity])
    direction = np.sign(step[0]) if step[0] != 0 else 1.0
    bad = np.flatnonzero(~(step * direction > 0))
    if bad.size:
        _fail(test, bad[0] + 1, column, f"{quantity} {test.columns[quantity][bad[0] + 1]:g} after "
              f"{test.columns[quantity][bad[0]]:g}: the curve must be strictly monotone in "
              f"{quantity} (one loading branch per file)")


def _stress_sign(test: MaterialTest, stretch: str, stress: str, column: str) -> None:
    """Tension (stretch > 1) needs stress > 0, compression (< 1) needs stress < 0."""
    lam, p = test.columns[stretch], test.columns[stress]
    bad = np.flatnonzero(((lam > 1.0) & ~(p > 0.0)) | ((lam < 1.0) & ~(p < 0.0)))
    if bad.size:
        i = bad[0]
        need = "> 0 (tension)" if lam[i] > 1.0 else "< 0 (compression)"
        # every compressive point with a positive stress: the stresses are compression-positive
        compressive = lam < 1.0
        hint = (f" (stresses positive in compression: give {COMPRESSION_POSITIVE_FLAG})"
                if lam[i] < 1.0 and np.all(p[compressive] > 0.0) else "")
        _fail(test, i, column, f"stress {p[i]:g} at {stretch} {lam[i]:g}: must be {need}; "
              f"compressive stresses are negative{hint}")


def _check_sign_convention(test: MaterialTest, cols: dict[str, str], declared: str | None,
                           compression_positive: bool) -> None:
    """A uniaxial test declared (`FILE:compression`, `FILE:tension`) or named ("compress" in
    the file name) as one branch must read as that branch once signed; one that reads as the
    other branch has its signs the other way round: `InputError` with the flag as the hint."""
    if "stretch" not in test.columns or test.mode != "uniaxial":
        return
    named = "compress" in test.path.name.lower()
    branch = declared or ("compression" if named else None)
    if branch is None:
        return
    lam, p = test.columns["stretch"], test.columns["nominal_stress_pa"]
    low, high = float(lam.min()), float(lam.max())
    wrong = high > 1.0 if branch == "compression" else low < 1.0
    if not wrong:
        return
    # the whole file on the other side, the stresses with it: the signs are the other way round
    mirrored = (low >= 1.0 and bool(np.all(p >= 0.0))) if branch == "compression" else (
        high <= 1.0 and bool(np.all(p <= 0.0)))
    how = (f"declared {branch} ({test.path.name}:{branch})" if declared
           else "named as a compression test")
    column = f"{cols['stretch']}, {cols['nominal_stress_pa']}"
    if not mirrored:
        side = "above" if branch == "compression" else "below"
        raise InputError(f"{test.path}: columns {column}: {how}, but stretches reach "
                         f"{high if branch == 'compression' else low:g}, {side} 1: one branch "
                         f"per file (give {test.path.name}:uniaxial for a test through both)")
    if compression_positive:
        hint = (f"the file is already signed (compression negative): drop "
                f"{COMPRESSION_POSITIVE_FLAG}")
    elif branch == "compression":
        hint = (f"strain and stress positive in compression? give {COMPRESSION_POSITIVE_FLAG}"
                + ("" if declared else f" (a tension test: {test.path.name}:tension)"))
    else:
        hint = f"strain and stress positive in compression? give {COMPRESSION_POSITIVE_FLAG}"
    raise InputError(f"{test.path}: columns {column}: {how}, but it reads as "
                     f"{'tension' if branch == 'compression' else 'compression'} (stretch "
                     f"{low:g} to {high:g}, stress {float(p.min()):g} to {float(p.max()):g} Pa): "
                     f"{hint}")


def _check_curve(test: MaterialTest, cols: dict[str, str]) -> None:
    stretch_keys = [k for k in ("stretch", "stretch_1", "stretch_2") if k in test.columns]
    for key in stretch_keys:
        _positive(test, key, cols[key], "a stretch; a strain must be above -1")
    if "stretch" in test.columns:
        _monotone(test, "stretch", cols["stretch"])
        _stress_sign(test, "stretch", "nominal_stress_pa", cols["nominal_stress_pa"])
        return
    # general biaxial: one of the two stretches drives the test (the other may be held)
    l1, l2 = test.columns["stretch_1"], test.columns["stretch_2"]
    key = "stretch_1" if np.ptp(l1) >= np.ptp(l2) else "stretch_2"
    _monotone(test, key, cols[key])


def _check_volumetric(test: MaterialTest, cols: dict[str, str]) -> None:
    _positive(test, "volume_ratio", cols["volume_ratio"])
    j, p = test.columns["volume_ratio"], test.columns["pressure_pa"]
    bad = np.flatnonzero(((j < 1.0) & ~(p > 0.0)) | ((j > 1.0) & ~(p < 0.0)))
    if bad.size:
        i = bad[0]
        _fail(test, i, cols["pressure_pa"], f"pressure {p[i]:g} at volume ratio {j[i]:g}: must "
              f"be {'> 0 (compressed)' if j[i] < 1 else '< 0 (expanded)'}; pressure is positive "
              "in compression")


def _check_time(test: MaterialTest, cols: dict[str, str]) -> None:
    t = test.columns["time_s"]
    if t[0] < 0:
        _fail(test, 0, cols["time_s"], range_text("time_s", t[0], "allowed range", 0.0, math.inf,
                                                  unit="s"))
    bad = np.flatnonzero(~(np.diff(t) > 0))
    if bad.size:
        _fail(test, bad[0] + 1, cols["time_s"], f"time {t[bad[0] + 1]:g} s after {t[bad[0]]:g} s:"
              " times must increase")


def _normalised(test: MaterialTest, cols: dict[str, str], raw: str, ratio: str) -> None:
    """A modulus (compliance) column -> its ratio to the first (instantaneous) value."""
    if raw in test.columns:
        _positive(test, raw, cols[raw], "moduli and compliances are positive")
        test.columns[ratio] = test.columns[raw] / test.columns[raw][0]
        cols[ratio] = cols[raw]


def _check_relaxation(test: MaterialTest, cols: dict[str, str]) -> None:
    _check_time(test, cols)
    _normalised(test, cols, "relaxation_modulus_pa", "relaxation_modulus_ratio")
    g = test.columns["relaxation_modulus_ratio"]
    bad = np.flatnonzero(~((g > 0.0) & (g <= 1.0 + RATIO_SLACK)))
    if bad.size:
        _fail(test, bad[0], cols["relaxation_modulus_ratio"], f"ratio {g[bad[0]]:.6g} outside "
              f"(0, {1.0 + RATIO_SLACK:g}]: a relaxation modulus lies between 0 and its "
              "instantaneous (first) value (up to 5% above it as noise)")


def _check_creep(test: MaterialTest, cols: dict[str, str]) -> None:
    _check_time(test, cols)
    _normalised(test, cols, "creep_compliance_per_pa", "creep_compliance_ratio")
    r = test.columns["creep_compliance_ratio"]
    bad = np.flatnonzero(~(r >= 1.0 - RATIO_SLACK))
    if bad.size:
        _fail(test, bad[0], cols["creep_compliance_ratio"], f"ratio {r[bad[0]]:.6g} below "
              f"{1.0 - RATIO_SLACK:g}: a creep compliance is at least its instantaneous (first) "
              "value (up to 5% below it as noise)")


def _check_dma(test: MaterialTest, cols: dict[str, str]) -> None:
    _positive(test, "frequency_hz", cols["frequency_hz"])
    _positive(test, "storage_modulus_pa", cols["storage_modulus_pa"],
              "is negative or zero (a storage modulus is > 0)")
    loss = test.columns["loss_modulus_pa"]
    bad = np.flatnonzero(loss < 0)
    if bad.size:
        _fail(test, bad[0], cols["loss_modulus_pa"], f"{loss[bad[0]]:g} is negative (a loss "
              "modulus is >= 0)")


_CHECKS = {"uniaxial": _check_curve, "planar": _check_curve, "biaxial": _check_curve,
           "volumetric": _check_volumetric, "relaxation": _check_relaxation,
           "creep": _check_creep, "dma": _check_dma}

__all__ = ["COLUMNS", "COMPRESSION_POSITIVE_FLAG", "DECLARED_MODES", "MODES", "REQUIRED",
           "SIGNED_MODES", "STRESS_MODES", "VISCOELASTIC_MODES", "MaterialTest", "base_mode",
           "parse_spec", "read_test"]
