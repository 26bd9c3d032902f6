"""The universal model: an inverse ensemble (features -> parameters with intervals) and a forward
ensemble (parameters, speed -> features and force shape), with their scalers and metadata.

Files are safe to load from a stranger: `MODEL.npz` holds only arrays (weights, scalers, the
held-out predictions; read with `allow_pickle=False`), `MODEL.json` the metadata (ranges, template,
feature list, architecture, versions, training and held-out figures). No pickle anywhere.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..records.features import FEATURE_NAMES
from ..fileio import read_arrays, replacing, write_atomic
from . import space
from .dataset import SHAPE_POINTS
from .networks import (
    Architecture,
    from_leaves,
    gaussian_interval_scale,
    leaf_shapes,
    leaves,
    predict,
)
from .design import DESIGNS, MATERIAL, Design
from .study import CONFIG_SCHEMA, GROUP_RANGES_SCHEMA

FORMAT = "ballimpact-universal-model/1"
FEATURES = tuple(FEATURE_NAMES)  # P1..P19
COR_COLUMN = FEATURES.index("P17")
#: what the inverse ensemble predicts: the four parameters and mu0 = 2 (C10 + C01), each in the
#: unit scale of its range (mu0: the range implied by C10's and C01's)
TARGETS = (*space.MATERIAL_PARAMETERS, "mu0_pa")
TARGET_UNITS = {"c10_pa": "Pa", "c01_pa": "Pa", "g1": "1", "tau1_s": "s", "mu0_pa": "Pa",
                "rho_v2_over_mu0": "1", "c01_over_c10": "1", "tau1_v_over_r": "1"}
BUILTIN = "cricket-universal-model"
#: the built-in models: the cricket ball's (thesis chapter 6, the default) and the one of every
#: solid sports ball (a study of the groups, issue 42; docs/universal.md, "A study in the groups")
SPORTS_BALLS = "sports-ball-universal-model"
BUILTINS = (BUILTIN, SPORTS_BALLS)
INTERVAL_LEVEL = 0.9


@dataclass(frozen=True)
class Scaler:
    """Columns: log where `log` (positive quantities spanning decades), then standardised."""

    log: np.ndarray
    mean: np.ndarray
    std: np.ndarray

    @classmethod
    def fit(cls, values: np.ndarray, log_candidates: np.ndarray | None = None) -> "Scaler":
        log = np.zeros(values.shape[1], bool) if log_candidates is None else \
            log_candidates & np.all(values > 0, axis=0)
        v = np.where(log, np.log(np.where(log, values, 1.0)), values)
        std = v.std(axis=0)
        return cls(log, v.mean(axis=0), np.where(std > 0, std, 1.0))

    def forward(self, values: np.ndarray) -> np.ndarray:
        values = np.asarray(values, np.float64)
        v = np.where(self.log, np.log(np.where(self.log, np.maximum(values, 1e-300), 1.0)), values)
        return (v - self.mean) / self.std

    def inverse(self, z: np.ndarray) -> np.ndarray:
        v = np.asarray(z, np.float64) * self.std + self.mean
        return np.where(self.log, np.exp(np.where(self.log, v, 0.0)), v)

    def arrays(self, prefix: str) -> dict[str, np.ndarray]:
        return {f"{prefix}_log": self.log, f"{prefix}_mean": self.mean, f"{prefix}_std": self.std}

    @classmethod
    def from_arrays(cls, arrays, prefix: str) -> "Scaler":
        return cls(arrays[f"{prefix}_log"].astype(bool), arrays[f"{prefix}_mean"],
                   arrays[f"{prefix}_std"])


def target_ranges(ranges: dict[str, tuple[float, float]]) -> dict[str, tuple[float, float]]:
    """The material design's target ranges (`Design.target_ranges`)."""
    return MATERIAL.target_ranges(ranges)


@dataclass
class UniversalModel:
    inverse: Any                  # ensemble: standardised features -> standardised unit targets
    forward: Any                  # ensemble: unit parameters + unit speed -> standardised outputs
    feature_scaler: Scaler        # of P1..P19 (inverse inputs, forward outputs' first 19)
    target_scaler: Scaler         # of the inverse's unit targets
    shape_scaler: Scaler          # of the force shape on the normalised grid
    interval_scale: np.ndarray    # per target: conformal factor on the ensemble's sigma
    metadata: dict[str, Any]
    held_out: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def ranges(self) -> dict[str, tuple[float, float]]:
        return {k: tuple(v) for k, v in self.metadata["ranges"].items()}

    @property
    def design(self) -> Design:
        """What the model learns from and predicts (`design.Design`): its study's design space
        ("material" for models trained before the groups' design)."""
        return DESIGNS[self.metadata.get("design_space", "material")]

    @property
    def feature_method(self) -> str:
        """How the model's noisy training copies were described (`extract_features(method=)`):
        its inputs from a measured test are described the same way (`identify`). Models
        trained before issue 39 (the built-in one) used the samples."""
        return self.metadata.get("feature_method", "samples")

    def solver_options(self):
        """FE settings of the model's study (its element size): identified balls run as the
        training runs did."""
        from ..fe import SolverOptions

        return SolverOptions(element_size_m=self.metadata["study"]["element_size_m"])

    # -- inverse ---------------------------------------------------------------------------------
    def estimate(self, features: np.ndarray, level: float = INTERVAL_LEVEL) -> dict[str, np.ndarray]:
        """Targets (`design.targets`, SI) and their `level` intervals from rows of the inverse's
        inputs (`design.inputs`: the 19 features in SI for a material design)."""
        z = self.feature_scaler.forward(np.atleast_2d(features))
        mean, sigma = (np.asarray(a, np.float64) for a in predict(self.inverse, z.astype(np.float32)))
        half = gaussian_interval_scale(level) * self.interval_scale * sigma
        targets = self.design.targets
        ranges = self.design.target_ranges(self.ranges)
        unit = [np.clip(self.target_scaler.inverse(v), 0.0, 1.0)
                for v in (mean, mean - half, mean + half)]
        values, low, high = (space.from_unit(u, ranges, targets) for u in unit)
        return {"values": values, "low": low, "high": high}

    # -- forward ---------------------------------------------------------------------------------
    def forward_inputs(self, params_si: np.ndarray) -> np.ndarray:
        """Rows of `design.forward_inputs` (material: c10_pa, c01_pa, g1, tau1_s,
        impact_speed_m_s; groups: the four groups) -> the forward ensemble's inputs."""
        names = self.design.forward_inputs
        return (space.to_unit(np.atleast_2d(params_si), self.ranges, names) - 0.5) \
            / np.sqrt(1 / 12)

    def simulate(self, params_si: np.ndarray) -> dict[str, np.ndarray]:
        """Forward surrogate: the design's features (material: P1..P19 in SI; groups: the 18
        dimensionless ones), force shape (n, 64) and their sigmas (in standardised units)."""
        mean, sigma = (np.asarray(a, np.float64) for a in
                       predict(self.forward, self.forward_inputs(params_si).astype(np.float32)))
        n = len(self.design.features)
        return {"features": self.feature_scaler.inverse(mean[:, :n]),
                "force_shape": self.shape_scaler.inverse(mean[:, n:]),
                "sigma_standardised": sigma}

    # -- files -----------------------------------------------------------------------------------
    def save(self, path: Path) -> tuple[Path, Path]:
        """MODEL.npz and MODEL.json, each written under a temporary name and renamed (an
        interrupted save leaves the previous files or none, never half a file)."""
        npz, meta = file_pair(path)
        arrays = {**self.feature_scaler.arrays("feature"), **self.target_scaler.arrays("target"),
                  **self.shape_scaler.arrays("shape"), "interval_scale": self.interval_scale}
        for name, ensemble in (("inverse", self.inverse), ("forward", self.forward)):
            for i, leaf in enumerate(leaves(ensemble)):
                arrays[f"{name}_{i:03d}"] = leaf.astype(np.float32)
        for key, value in self.held_out.items():
            arrays[f"held_out_{key}"] = value
        with replacing(npz) as tmp:
            np.savez_compressed(tmp, **arrays)
        write_atomic(meta, json.dumps(self.metadata, indent=2))
        return npz, meta


# -- validation of model files: everything is checked before anything is built from it ----------

def _equal(expected):
    return (lambda v: v == expected, json.dumps(expected) if not isinstance(expected, list)
            else f"{expected[0]}..{expected[-1]} in order")


_NUMBER = (lambda v: space.is_number(v, finite=False), "a number")
_FIGURES = {"median": _NUMBER, "p90": _NUMBER, "r2": _NUMBER}


def _architecture(n_in: int, n_out: int) -> dict[str, Any]:
    return {"n_in": _equal(n_in), "n_out": _equal(n_out), "width": space.count(1, 4096),
            "depth": space.count(1, 16), "members": space.count(1, 64)}


def metadata_schema(design: Design) -> dict[str, Any]:
    """What MODEL.json must hold for a model of `design` (keys outside it are free: versions,
    training figures, ...)."""
    features, targets = design.features, design.targets
    return {
        "ranges": GROUP_RANGES_SCHEMA if design.name == "groups" else CONFIG_SCHEMA["ranges"],
        "template": CONFIG_SCHEMA["template"],
        "study": {k: CONFIG_SCHEMA[k] for k in ("runs", "seed", "method", "element_size_m",
                                                "precision", "integration")},
        "features": _equal(list(features)), "targets": _equal(list(targets)),
        "shape_grid_points": _equal(SHAPE_POINTS),
        "feature_range": {k: (space.is_pair, "[low, high] with low <= high") for k in features},
        "architecture": {"inverse": _architecture(len(features), len(targets)),
                         "forward": _architecture(len(design.forward_inputs),
                                                  len(features) + SHAPE_POINTS)},
        "runs": (lambda v: isinstance(v, dict), "an object of run counts"),
        "held_out": {
            "runs": space.count(1, 10**9),
            "inverse": {t: {"range_relative_error": _FIGURES, "interval_90_coverage": _NUMBER,
                            "interval_90_mean_width_of_range": _NUMBER,
                            "relative_error": (lambda v: v is None or (
                                isinstance(v, dict) and all(space.is_number(v.get(k), False)
                                                            for k in _FIGURES)),
                                "null or {median, p90, r2}")} for t in targets},
            "forward": {k: {"median": _NUMBER} for k in ("force_shape_rms_of_peak",
                                                         "cor_absolute_error", "P1", "P6")},
            "identifiability": {"median_rms_change_standardised": (
                lambda v: isinstance(v, dict)
                and all(space.is_number(x, False) for x in v.values()),
                "an object of numbers")}},
    }


#: the material design's schema (models trained before the groups' design)
METADATA_SCHEMA = metadata_schema(MATERIAL)


def check_metadata(metadata: Any, where: str) -> dict[str, Any]:
    """MODEL.json's content checked against `FORMAT` and `METADATA_SCHEMA`."""
    if not isinstance(metadata, dict):
        raise InputError(f"{where}: not a universal model's metadata (a JSON "
                         f"{type(metadata).__name__}, expected an object)")
    if metadata.get("format") != FORMAT:
        raise InputError(f"{where}: format {metadata.get('format')!r}, expected {FORMAT}")
    name = metadata.get("design_space", "material")
    if name not in DESIGNS:
        raise InputError(f"{where}: 'design_space' = {json.dumps(name)[:40]}: expected "
                         f"{' or '.join(DESIGNS)}")
    space.check_fields(metadata, metadata_schema(DESIGNS[name]), where)
    check = metadata.get("held_out_check")
    if check is not None and not (isinstance(check, dict)
                                  and isinstance(check.get("passed"), bool)):
        raise InputError(f"{where}: 'held_out_check' = {json.dumps(check)[:40]}: expected an "
                         "object with passed: true or false")
    return metadata


def expected_arrays(metadata: dict[str, Any]) -> dict[str, tuple[tuple[int, ...], str]]:
    """Every array of MODEL.npz: name -> (shape, dtype kinds), from the checked metadata."""
    design = DESIGNS[metadata.get("design_space", "material")]
    n_t, n_held = len(design.targets), metadata["held_out"]["runs"]
    out: dict[str, tuple[tuple[int, ...], str]] = {}
    for prefix, n in (("feature", len(design.features)), ("target", n_t),
                      ("shape", SHAPE_POINTS)):
        out.update({f"{prefix}_log": ((n,), "b"), f"{prefix}_mean": ((n,), "f"),
                    f"{prefix}_std": ((n,), "f")})
    out["interval_scale"] = ((n_t,), "f")
    for name in ("inverse", "forward"):
        for i, shape in enumerate(leaf_shapes(Architecture(**metadata["architecture"][name]))):
            out[f"{name}_{i:03d}"] = (shape, "f")
    out["held_out_run_id"] = ((n_held,), "iu")
    out.update({f"held_out_{k}": ((n_held, n_t), "f")
                for k in ("truth", "estimate", "low", "high")})
    return out


def check_arrays(arrays: dict[str, np.ndarray], expected: dict, where: str) -> None:
    """Keys, shapes, dtypes and finite values of MODEL.npz's arrays (`expected_arrays`)."""
    missing = [k for k in expected if k not in arrays]
    if missing:
        raise InputError(f"{where}: not a universal model's weights: array {missing[0]} missing"
                         f" ({len(missing)} missing in all)")
    extra = sorted(set(arrays) - set(expected))
    if extra:
        raise InputError(f"{where}: not a universal model's weights: unexpected array {extra[0]}")
    for key, (shape, kinds) in expected.items():
        a = arrays[key]
        if a.shape != shape or a.dtype.kind not in kinds:
            kind = {"b": "booleans", "f": "floats", "iu": "integers"}[kinds]
            raise InputError(f"{where}: array {key} is {a.dtype} {a.shape}, expected {kind} "
                             f"{shape} (as the metadata's architecture and held-out runs give)")
        if kinds == "f" and not np.all(np.isfinite(a)):
            raise InputError(f"{where}: array {key} holds {int(np.sum(~np.isfinite(a)))} "
                             "non-finite values (NaN or inf): damaged weights")
    for key in ("feature_std", "target_std", "shape_std"):
        if np.any(arrays[key] <= 0):
            raise InputError(f"{where}: array {key} holds values <= 0 (a scaler divides by it)")
    if np.any(arrays["interval_scale"] < 0):
        raise InputError(f"{where}: array interval_scale holds negative values")


def file_pair(path: str | Path) -> tuple[Path, Path]:
    """(MODEL.npz, MODEL.json) of a model path given with either suffix or none ("my.model"
    names my.model.json, not my.json)."""
    path = Path(path)
    if path.suffix not in (".json", ".npz"):
        path = path.with_name(path.name + ".json")
    return path.with_suffix(".npz"), path.with_suffix(".json")


def model_paths(name_or_path: str | Path | None) -> tuple[Path, Path]:
    """(MODEL.npz, MODEL.json) of a built-in model (`BUILTINS`; None: the cricket ball's) or of
    a path (`file_pair`)."""
    name = BUILTIN if name_or_path is None else str(name_or_path)
    if name in BUILTINS:
        base = resources.files("ballimpact") / "data" / name
        return Path(str(base) + ".npz"), Path(str(base) + ".json")
    return file_pair(name_or_path)


def load_model(name_or_path: str | Path | None = None) -> UniversalModel:
    """A built-in model (None or "cricket-universal-model"; "sports-ball-universal-model"), or
    MODEL(.json|.npz) files.

    Both files are validated before use (`check_metadata`, `read_arrays`, `check_arrays`): a
    damaged, truncated or tampered file gives `InputError` naming the file and what is wrong.
    Nothing is unpickled."""
    npz, meta = model_paths(name_or_path)
    for p in (meta, npz):
        if p.is_dir():
            raise InputError(f"model {p} is a folder (a model is MODEL.json and MODEL.npz)")
        if not p.is_file():
            raise InputError(f"model {p} not found (a model is MODEL.json and MODEL.npz, "
                             "written by `ballimpact universal train --out MODEL`)")
    try:
        metadata = json.loads(meta.read_text())
    except (OSError, ValueError) as error:
        raise InputError(f"model file {meta}: not readable JSON ({error})") from None
    check_metadata(metadata, f"model file {meta}")
    arrays = read_arrays(npz, f"model file {npz}", "a universal model's weights")
    check_arrays(arrays, expected_arrays(metadata), f"model file {npz}")
    ensembles = {}
    for name in ("inverse", "forward"):
        keys = sorted(k for k in arrays if k.startswith(f"{name}_"))
        ensembles[name] = from_leaves(Architecture(**metadata["architecture"][name]),
                                      [arrays[k].astype(np.float32) for k in keys])
    held_out = {k[len("held_out_"):]: v for k, v in arrays.items() if k.startswith("held_out_")}
    return UniversalModel(ensembles["inverse"], ensembles["forward"],
                          Scaler.from_arrays(arrays, "feature"), Scaler.from_arrays(arrays, "target"),
                          Scaler.from_arrays(arrays, "shape"), arrays["interval_scale"], metadata,
                          held_out)
