"""A rigid plane that moves: carried by a backing of masses, springs and dashpots (SI).

The axisymmetric ball hits the plane z = 0 at t = 0; with a `PlaneBacking` the plane moves
along z. Its displacement is the sum of the coordinates of independent oscillators, each driven
by the same force, the contact force F(t) >= 0 pushing the plane down (-z):

    m_k y_k'' + c_k y_k' + k_k y_k = -F(t),        z_plane = sum_k y_k

This is the response of a linear structure at the impact point written modally:

- a free rigid body of mass M (a headform, a hand, a plate): one oscillator (M, 0, 0);
- the same on a neck or an arm: (M, k, c);
- a flexible bat at the impact point: its modes, mode n with the mass-normalised shape phi_n
  (1/sqrt(kg)) at the point, frequency omega_n and damping ratio zeta_n being the oscillator
  (1 / phi_n^2, omega_n^2 / phi_n^2, 2 zeta_n omega_n / phi_n^2) (the free bat's rigid
  modes have omega = 0: translation, 1/phi^2 = M, and rotation about the centre of mass,
  1/phi^2 = I_cm / b^2).

The oscillators are stepped with the ball's nodes by the same central difference; a mode of
frequency f needs 2 pi f dt well below 2: `MAX_FREQUENCY_HZ` keeps it below 0.3 at the
increments of the default meshes (0.1-0.5 us). The plane's mass at high frequency,
1 / sum(1/m_k), must be much heavier than the ball's contact nodes, which the increment
estimate assumes held by a fixed plane (`check_against`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..checks import check_range
from ..errors import InputError

#: highest oscillator frequency (Hz): a contact of a millisecond or more does not excite it, and
#: 2 pi f dt stays below 0.3 at increments up to 0.5 us
MAX_FREQUENCY_HZ = 100e3
#: the plane's mass at high frequency over the ball's heaviest contact node, at least
MIN_MASS_RATIO = 20.0


@dataclass(frozen=True)
class PlaneBacking:
    """The structure carrying the rigid plane, in modal form at the impact point: each mode's
    mass-normalised shape there (`shapes_1_sqrt_kg`, 1/sqrt(kg)), undamped frequency
    (`frequencies_hz`, Hz, 0 for a rigid-body mode), the modal damping matrix (`damping_1_s`,
    1/s, n x n: diagonal 2 zeta omega, or coupled by a grip's dashpots) and the modal
    velocities at t = 0 (`initial_velocities`, sqrt(kg) m/s; a swung bat). The plane's
    displacement is z = sum phi_k q_k and q'' + C q' + Omega^2 q = -phi F (F >= 0 the contact
    force, pushing the plane down)."""

    shapes_1_sqrt_kg: tuple[float, ...]
    frequencies_hz: tuple[float, ...]
    damping_1_s: tuple[tuple[float, ...], ...]
    initial_velocities: tuple[float, ...] = ()
    labels: tuple[str, ...] = ()
    name: str = "backing"

    def __post_init__(self) -> None:
        n = len(self.shapes_1_sqrt_kg)
        if n == 0:
            raise InputError(f"{self.name}: a backing needs at least one mode")
        if not self.initial_velocities:
            object.__setattr__(self, "initial_velocities", (0.0,) * n)
        if not self.labels:
            object.__setattr__(self, "labels", tuple(f"mode {i + 1}" for i in range(n)))
        for key in ("frequencies_hz", "initial_velocities", "labels"):
            if len(getattr(self, key)) != n:
                raise InputError(f"{self.name}.{key}: expected {n} values (one per mode), got "
                                 f"{len(getattr(self, key))}")
        if np.shape(self.damping_1_s) != (n, n):
            raise InputError(f"{self.name}.damping_1_s: expected a {n} x {n} matrix, got shape "
                             f"{np.shape(self.damping_1_s)}")
        for key in ("shapes_1_sqrt_kg", "frequencies_hz", "initial_velocities", "damping_1_s"):
            values = np.asarray(getattr(self, key), float)
            if not np.all(np.isfinite(values)):
                raise InputError(f"{self.name}.{key}: every value must be finite")
        if np.any(np.asarray(self.shapes_1_sqrt_kg) == 0.0):
            raise InputError(f"{self.name}.shapes_1_sqrt_kg: a mode with no motion at the "
                             "impact point cannot be driven by the contact: leave it out")
        f = np.asarray(self.frequencies_hz)
        if np.any(f < 0) or f.max() > MAX_FREQUENCY_HZ:
            raise InputError(f"{self.name}.frequencies_hz: allowed range [0, "
                             f"{MAX_FREQUENCY_HZ:g}] Hz (got up to {f.max():.4g}); leave out "
                             "modes a contact of a millisecond does not excite")
        c = np.asarray(self.damping_1_s)
        if np.any(np.linalg.eigvalsh(0.5 * (c + c.T)) < -1e-9 * max(1.0, np.abs(c).max())):
            raise InputError(f"{self.name}.damping_1_s: must be positive semi-definite (a "
                             "dashpot dissipates)")

    @classmethod
    def free_mass(cls, mass_kg: float, spring_n_m: float = 0.0, damper_n_s_m: float = 0.0,
                  name: str = "backing") -> PlaneBacking:
        """A rigid mass (kg) behind the plane, free or on a spring (N/m) and dashpot (N s/m) to
        the ground (a neck, an arm)."""
        return cls.rigid_mass(
            check_range(f"{name}.mass_kg", mass_kg, 0.0, 1e3, low_open=True, unit="kg",
                        note="above 1000 it looks like grams"),
            check_range(f"{name}.spring_n_m", spring_n_m, 0.0, unit="N/m"),
            check_range(f"{name}.damper_n_s_m", damper_n_s_m, 0.0, unit="N s/m"), name)

    @classmethod
    def rigid_mass(cls, mass_kg: float, spring_n_m: float, damper_n_s_m: float,
                   name: str) -> PlaneBacking:
        """`free_mass` without its range checks (a target's backing, checked where it was
        read; a test's 1e6 kg standing for a fixed base): one mode, phi = 1/sqrt(M),
        Omega^2 = k/M, C = c/M."""
        m = float(mass_kg)
        return cls((1.0 / math.sqrt(m),), (math.sqrt(spring_n_m / m) / (2.0 * math.pi),),
                   ((damper_n_s_m / m,),), labels=(name,), name=name)

    @property
    def count(self) -> int:
        return len(self.shapes_1_sqrt_kg)

    @property
    def high_frequency_mass_kg(self) -> float:
        """The plane's apparent mass to a sudden force: 1 / sum(phi_k^2) (kg)."""
        return 1.0 / float(np.sum(np.square(self.shapes_1_sqrt_kg)))

    def check_against(self, node_mass_kg: float, ball_name: str) -> None:
        """`InputError` when the plane is not much heavier than the ball's heaviest contact
        node (`node_mass_kg`, kg): the stable increment assumes a plane that nodes cannot
        move."""
        if self.high_frequency_mass_kg < MIN_MASS_RATIO * node_mass_kg:
            raise InputError(
                f"{self.name}: the plane's mass at high frequency, "
                f"{self.high_frequency_mass_kg:.3g} kg, is less than {MIN_MASS_RATIO:g} times "
                f"the heaviest contact node of ball {ball_name} ({node_mass_kg:.3g} kg): the "
                "explicit increment would not be stable; a backing this light needs the target "
                "meshed (3D target slab)")

    def arrays(self) -> dict[str, np.ndarray]:
        """The kernel's parameters (float64 arrays)."""
        omega = 2.0 * math.pi * np.asarray(self.frequencies_hz, float)
        return {"backing_shape_1_sqrt_kg": np.asarray(self.shapes_1_sqrt_kg, float),
                "backing_omega2_1_s2": omega ** 2,
                "backing_damping_1_s": np.asarray(self.damping_1_s, float),
                "backing_velocity0": np.asarray(self.initial_velocities, float)}

    @property
    def initial_energy_j(self) -> float:
        """The modes' kinetic energy at t = 0 (J)."""
        return 0.5 * float(np.sum(np.square(self.initial_velocities)))

    @property
    def initial_plane_velocity_m_s(self) -> float:
        """The plane's velocity along z at t = 0 (m/s)."""
        return float(np.dot(self.shapes_1_sqrt_kg, self.initial_velocities))


def no_backing_arrays() -> dict[str, np.ndarray]:
    """The kernel's backing parameters of a fixed plane: no modes."""
    return {"backing_shape_1_sqrt_kg": np.zeros(0), "backing_omega2_1_s2": np.zeros(0),
            "backing_damping_1_s": np.zeros((0, 0)), "backing_velocity0": np.zeros(0)}


def backing_energies(history: dict[str, np.ndarray], energies: dict[str, float],
                     backing: PlaneBacking) -> dict:
    """The backing's energy figures at the end of a run (J) from its histories and the ball's
    `energies` (`contact_work_j`, `initial_kinetic_energy_j`): the modes' kinetic plus strain
    energy (at the start and the end), the work the contact force did on the plane, the dashpots' dissipation, the
    contact's own dissipation (its dashpots; the penalty springs hold nothing once apart) and
    the backing's balance error (energy + dissipation - work, over the impact energy: the
    modes' state against the work of the force that drove them)."""
    last = {k: float(history[k][-1]) for k in ("backing_energy_j", "backing_work_j",
                                               "backing_damping_j")}
    start = backing.initial_energy_j
    balance = (last["backing_energy_j"] + last["backing_damping_j"] - last["backing_work_j"]
               - start)
    return {**last, "backing_initial_energy_j": start, "contact_dissipation_j": -(energies["contact_work_j"]
                                               + last["backing_work_j"]),
            "backing_balance_error": balance / energies["initial_kinetic_energy_j"]}
