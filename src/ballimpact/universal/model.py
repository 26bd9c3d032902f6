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
from ..features import FEATURE_NAMES
from . import space
from .networks import Architecture, from_leaves, gaussian_interval_scale, leaves, predict

FORMAT = "ballimpact-universal-model/1"
FEATURES = tuple(FEATURE_NAMES)  # P1..P19
COR_COLUMN = FEATURES.index("P17")
#: what the inverse ensemble predicts: the four parameters and mu0 = 2 (C10 + C01), each in the
#: unit scale of its range (mu0: the range implied by C10's and C01's)
TARGETS = (*space.MATERIAL_PARAMETERS, "mu0_pa")
TARGET_UNITS = {"c10_pa": "Pa", "c01_pa": "Pa", "g1": "1", "tau1_s": "s", "mu0_pa": "Pa"}
BUILTIN = "cricket-universal-model"
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
    (c10_lo, c10_hi), (c01_lo, c01_hi) = ranges["c10_pa"], ranges["c01_pa"]
    return {**ranges, "mu0_pa": (2 * (c10_lo + c01_lo), 2 * (c10_hi + c01_hi))}


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

    def solver_options(self):
        """FE settings of the model's study (its element size): identified balls run as the
        training runs did."""
        from ..fe import SolverOptions

        return SolverOptions(element_size_m=self.metadata["study"]["element_size_m"])

    # -- inverse ---------------------------------------------------------------------------------
    def estimate(self, features: np.ndarray, level: float = INTERVAL_LEVEL) -> dict[str, np.ndarray]:
        """Parameters (SI) and their `level` intervals from feature rows (n, 19) in SI."""
        z = self.feature_scaler.forward(np.atleast_2d(features))
        mean, sigma = (np.asarray(a, np.float64) for a in predict(self.inverse, z.astype(np.float32)))
        half = gaussian_interval_scale(level) * self.interval_scale * sigma
        ranges = target_ranges(self.ranges)
        unit = [np.clip(self.target_scaler.inverse(v), 0.0, 1.0)
                for v in (mean, mean - half, mean + half)]
        values, low, high = (space.from_unit(u, ranges, TARGETS) for u in unit)
        return {"values": values, "low": low, "high": high}

    # -- forward ---------------------------------------------------------------------------------
    def forward_inputs(self, params_si: np.ndarray) -> np.ndarray:
        """Rows (c10_pa, c01_pa, g1, tau1_s, impact_speed_m_s) -> the forward ensemble's inputs."""
        return (space.to_unit(np.atleast_2d(params_si), self.ranges) - 0.5) / np.sqrt(1 / 12)

    def simulate(self, params_si: np.ndarray) -> dict[str, np.ndarray]:
        """Forward surrogate: features (n, 19) in SI, force shape (n, 64) and their sigmas
        (in standardised units)."""
        mean, sigma = (np.asarray(a, np.float64) for a in
                       predict(self.forward, self.forward_inputs(params_si).astype(np.float32)))
        n = len(FEATURES)
        return {"features": self.feature_scaler.inverse(mean[:, :n]),
                "force_shape": self.shape_scaler.inverse(mean[:, n:]),
                "sigma_standardised": sigma}

    # -- files -----------------------------------------------------------------------------------
    def save(self, path: Path) -> tuple[Path, Path]:
        path = Path(path)
        npz, meta = path.with_suffix(".npz"), path.with_suffix(".json")
        arrays = {**self.feature_scaler.arrays("feature"), **self.target_scaler.arrays("target"),
                  **self.shape_scaler.arrays("shape"), "interval_scale": self.interval_scale}
        for name, ensemble in (("inverse", self.inverse), ("forward", self.forward)):
            for i, leaf in enumerate(leaves(ensemble)):
                arrays[f"{name}_{i:03d}"] = leaf.astype(np.float32)
        for key, value in self.held_out.items():
            arrays[f"held_out_{key}"] = value
        np.savez_compressed(npz, **arrays)
        meta.write_text(json.dumps(self.metadata, indent=2))
        return npz, meta


def load_model(name_or_path: str | Path | None = None) -> UniversalModel:
    """The built-in model (None or "cricket-universal-model"), or MODEL(.json|.npz) files."""
    if name_or_path is None or str(name_or_path) == BUILTIN:
        base = resources.files("ballimpact") / "data" / BUILTIN
        npz, meta = Path(str(base) + ".npz"), Path(str(base) + ".json")
    else:
        path = Path(name_or_path)
        npz, meta = path.with_suffix(".npz"), path.with_suffix(".json")
    for p in (npz, meta):
        if not p.is_file():
            raise InputError(f"--model: {p} not found (a model is a .json and a .npz file)")
    try:
        metadata = json.loads(meta.read_text())
    except (OSError, ValueError) as error:
        raise InputError(f"--model: {meta}: not readable JSON ({error})") from None
    if metadata.get("format") != FORMAT:
        raise InputError(f"--model: {meta}: format {metadata.get('format')!r}, expected {FORMAT}")
    try:
        with np.load(npz, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
        ensembles = {}
        for name in ("inverse", "forward"):
            keys = sorted(k for k in arrays if k.startswith(f"{name}_") and k[len(name) + 1:].isdigit())
            arch = Architecture(**metadata["architecture"][name])
            ensembles[name] = from_leaves(arch, [arrays[k] for k in keys])
    except (OSError, ValueError, KeyError) as error:
        raise InputError(f"--model: {npz}: not a universal model's weights ({error})") from None
    held_out = {k[len("held_out_"):]: v for k, v in arrays.items() if k.startswith("held_out_")}
    return UniversalModel(ensembles["inverse"], ensembles["forward"],
                          Scaler.from_arrays(arrays, "feature"), Scaler.from_arrays(arrays, "target"),
                          Scaler.from_arrays(arrays, "shape"), arrays["interval_scale"], metadata,
                          held_out)

