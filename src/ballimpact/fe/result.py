"""What a run of the explicit engine returns, whatever its geometry: `ImpactResult` (or a
`FailedRun` in a batch), and the energy figures every geometry's histories give."""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..records.record import ImpactRecord
from .driver import RunFigures
from .options import ImpactCondition

NAN = float("nan")


@dataclass(frozen=True, eq=False)
class ImpactResult(RunFigures):
    """One simulated impact (SI; `driver.RunFigures` and the below; forces and energies of the
    whole ball).

    `geometry` names the engine's geometry ("axisymmetric" or "3d"). The normal COR `cor` is
    v_z' / (-v_z) of the centre of mass; the tangential figures (`tangential_cor` v_x' / v_x,
    `contact_point_tangential_cor` -(v_x' - w' R) / (v_x - w R), `rebound_angle_deg` from the
    normal, `rebound_spin_rad_s`) are NaN or 0 for the axisymmetric geometry, which runs
    normal impacts. The mesh fields hold the geometry's own mesh (`nodes_m`, the connectivity and
    the displacement at the peak force for the axisymmetric one; `mesh`, `frames` for the
    hexahedral one)."""

    condition: ImpactCondition
    cor: float
    energies_j: dict[str, float]
    wall_time_s: float
    geometry: str = "axisymmetric"
    tangential_cor: float = NAN
    contact_point_tangential_cor: float = NAN
    rebound_angle_deg: float = 0.0
    rebound_spin_rad_s: float = 0.0
    rebound_speed_m_s: float = NAN
    half_model: bool = False
    target: str = "rigid plane"
    moduli: tuple[str, ...] = ()
    integration: str = "reduced"
    precision: str = "float64"
    pole_grading: float = NAN                # 3D: the mesh's (chosen from the contact unless given)
    penalty_scale: float = NAN               # 3D: the contact penalty's (the same)
    pole_spacing_m: float = NAN              # 3D: arc spacing of the elements at the contact pole
    nodes_m: np.ndarray | None = field(default=None, repr=False)
    elements_connectivity: np.ndarray | None = field(default=None, repr=False)
    displacement_at_peak_m: np.ndarray | None = field(default=None, repr=False)
    layer_slices: tuple = ()
    frames: list = field(default_factory=list, repr=False)   # 3D: snapshots (single runs)
    mesh: Any = field(default=None, repr=False)               # 3D: `fe.hex.mesh.HexMesh`
    kernel_geometry: Any = field(default=None, repr=False)    # 3D: the kernel's `HexGeometry`

    @property
    def impact_speed_m_s(self) -> float:
        return self.condition.speed_m_s

    @property
    def normal_cor(self) -> float:
        return self.cor

    @property
    def normal_speed_m_s(self) -> float:
        """The impact's normal speed (m/s)."""
        return self.condition.speed_m_s * math.cos(math.radians(self.condition.angle_deg))

    def history_digest(self) -> str:
        """A fingerprint of the histories (SHA-256 of their names, sorted, and float64 bytes;
        16 hex digits): equal digests, the same bits (benchmarks/bench_fe.py, bench_oblique.py
        print it, so a change that should leave the results alone can be checked)."""
        digest = hashlib.sha256()
        for name in sorted(self.history):
            digest.update(name.encode())
            digest.update(np.ascontiguousarray(self.history[name], np.float64).tobytes())
        return digest.hexdigest()[:16]

    def summary(self) -> dict[str, Any]:
        """The scalar results, JSON-able, with SI unit suffixes."""
        if self.geometry == "axisymmetric":
            return {"ball": self.ball_name, "impact_speed_m_s": self.impact_speed_m_s,
                    "peak_force_n": self.peak_force_n, "time_of_peak_s": self.time_of_peak_s,
                    "contact_time_s": self.contact_time_s, "cor": self.cor,
                    "rebound_speed_m_s": self.rebound_speed_m_s,
                    "energy_balance_error": self.energy_balance_error,
                    "energies_j": dict(self.energies_j), "mass_kg": self.mass_kg,
                    "elements": self.elements, "nodes": self.nodes, "steps": self.steps,
                    "stable_time_increment_s": self.stable_time_increment_s,
                    "final_time_increment_s": self.final_time_increment_s,
                    "principal_stretch_range": list(self.stretch_range),
                    "moduli": self.moduli[0] if len(set(self.moduli)) == 1 else list(self.moduli),
                    "integration": self.integration, "precision": self.precision,
                    "wall_time_s": self.wall_time_s,
                    **({} if self.target == "rigid plane" else {"target": self.target})}
        c, h = self.condition, self.history
        return {"ball": self.ball_name, "solver": "3d", "impact_speed_m_s": c.speed_m_s,
                "angle_deg": c.angle_deg, "spin_rad_s": c.spin_rad_s, "friction": c.friction,
                "target": self.target, "peak_force_n": self.peak_force_n,
                "peak_tangential_force_n": float(np.max(np.abs(h["tangential_force_x_n"]))),
                "time_of_peak_s": self.time_of_peak_s, "contact_time_s": self.contact_time_s,
                "cor": self.cor, "normal_cor": self.cor,
                "tangential_cor": self.tangential_cor,
                "contact_point_tangential_cor": self.contact_point_tangential_cor,
                "rebound_angle_deg": self.rebound_angle_deg,
                "rebound_spin_rad_s": self.rebound_spin_rad_s,
                "rebound_speed_m_s": self.rebound_speed_m_s,
                "rebound_velocity_m_s": [float(h[f"centre_velocity_{a}_m_s"][-1]) for a in "xyz"],
                "rebound_spin_vector_rad_s": [float(h[f"spin_{a}_rad_s"][-1]) for a in "xyz"],
                "spin_x_rad_s": c.spin_x_rad_s, "spin_z_rad_s": c.spin_z_rad_s,
                "energy_balance_error": self.energy_balance_error,
                "energies_j": dict(self.energies_j), "mass_kg": self.mass_kg,
                "elements": self.elements, "nodes": self.nodes, "steps": self.steps,
                "half_model": self.half_model, "pole_grading": self.pole_grading,
                "pole_spacing_m": self.pole_spacing_m, "penalty_scale": self.penalty_scale,
                "stable_time_increment_s": self.stable_time_increment_s,
                "final_time_increment_s": self.final_time_increment_s,
                "principal_stretch_bounds": list(self.stretch_range),  # Gershgorin bounds
                "wall_time_s": self.wall_time_s}

    def record(self) -> ImpactRecord:
        """The (normal) contact-force pulse as an `ImpactRecord` (zero force before contact),
        uniformly sampled at the run's final increment (the increment may shrink during a run;
        linear interpolation between steps); the axisymmetric geometry's with the ball's
        velocity."""
        steps = self.history["time_s"]
        dt = self.final_time_increment_s
        t = np.arange(1, int(np.floor(steps[-1] / dt * (1 + 1e-9))) + 1) * dt
        f = np.interp(t, steps, self.history["contact_force_n"])
        lead = np.arange(-max(3, int(0.05 * len(t))), 0) * dt
        time = np.concatenate([lead, [0.0], t])
        force = np.concatenate([np.zeros(len(lead) + 1), f])
        speed = self.normal_speed_m_s
        rebound = max(self.cor * speed, 0.0)
        if self.geometry != "axisymmetric":
            return ImpactRecord(time, force, mass_kg=self.mass_kg, impact_speed_m_s=speed,
                                rebound_speed_m_s=rebound,
                                metadata={"source": "fe-3d", "ball": self.ball_name})
        velocity = np.concatenate([np.full(len(lead) + 1, speed),
                                   -np.interp(t, steps, self.history["centre_velocity_z_m_s"])])
        return ImpactRecord(time, force, velocity_m_s=velocity, mass_kg=self.mass_kg,
                            impact_speed_m_s=speed, rebound_speed_m_s=rebound,
                            metadata={"source": "fe", "ball": self.ball_name,
                                      "contact_time_s": self.contact_time_s})


@dataclass(frozen=True)
class FailedRun:
    """A run of a batch that failed (`simulate_batch(..., on_failure="return")`): why, in words."""

    ball_name: str
    impact_speed_m_s: float
    reason: str


def contact_end_time(time: np.ndarray, force: np.ndarray) -> float:
    """Time at which the force returns to zero, extrapolated from the last two positive samples."""
    positive = np.flatnonzero(force > 0)
    k = positive[-1]
    if k == 0 or k + 1 >= len(time) or force[k - 1] <= force[k]:
        return float(time[min(k + 1, len(time) - 1)])
    slope = (force[k - 1] - force[k]) / (time[k] - time[k - 1])
    return float(min(time[k] + force[k] / slope, time[k + 1]))


def energy_histories(h: dict[str, np.ndarray], ke0: float) -> float:
    """Adds to the histories `h` the energy balance error (KE + internal work - contact work -
    KE0, over KE0) and the viscous dissipation (internal work - strain energy - bulk-viscous
    dissipation - hourglass energy, J); returns the largest |balance| (J)."""
    balance = h["kinetic_energy_j"] + h["internal_work_j"] - h["contact_work_j"] - ke0
    h["energy_balance_error"] = balance / ke0
    h["viscous_dissipation_j"] = (h["internal_work_j"] - h["strain_energy_j"]
                                  - h["bulk_viscous_dissipation_j"] - h["hourglass_energy_j"])
    return float(np.max(np.abs(balance)))


def target_energies(history: dict[str, np.ndarray], target) -> dict[str, float]:
    """A layered target's figures at the end of a run, either geometry: each layer's internal
    work (J: what it holds and has dissipated) and largest compression on the axis under the
    first touch (thickness lost over thickness), and the largest force on its base (N; where
    the history has it: a backed base, or any base in the axisymmetric geometry)."""
    out = {}
    for k, layer in enumerate(target.layers):
        out[f"target_{layer.name}_work_j"] = float(history[f"target_layer_{k}_work_j"][-1])
        out[f"target_{layer.name}_max_compression"] = float(
            np.max(history[f"target_layer_{k}_compression"]))
    if "transmitted_force_n" in history:
        out["target_max_transmitted_force_n"] = float(np.max(history["transmitted_force_n"]))
    return out
