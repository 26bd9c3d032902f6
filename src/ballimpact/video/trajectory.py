"""Impact and rebound speeds from the tracked ball: the free-flight frames before and after
contact, a straight line (columns) and a parabola under known gravity (rows) fitted to each,
and the velocities where each trajectory meets the surface, with standard errors.

Frames are left out when the ball is not found, touches the image border, fits a circle
badly (deformed or merged with something), or reaches to within `CONTACT_MARGIN_PX` of the
surface row (contact; motion blur stretches the blob toward the surface, so this leaves out
the frames just before contact too). The surface row is given, or the lowest row the blob
reaches (where the ball is flattened against it).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..checks import check_range
from ..errors import InputError
from .track import PROFILE_ANGLES, Detection

#: least free-flight frames on each side of the contact
MIN_FLIGHT_FRAMES = 5
#: a frame whose blob reaches this close to the surface row (px) counts as in contact
CONTACT_MARGIN_PX = 1.5
#: a circle fit worse than this multiple of the median rms residual is left out
RESIDUAL_FACTOR = 3.0
#: fastest ball speed (m/s) a measurement may report: the fastest ball sports (golf drives,
#: jai alai) reach about 90 m/s; faster means a wrong scale or frame rate
MAX_BALL_SPEED_M_S = 100.0
#: ball diameters (m) a scale may give or imply: a marble-sized ball to a large exercise ball
BALL_DIAMETER_RANGE_M = (0.005, 1.0)
#: largest gravity (m/s^2) along the image rows: 9.81 on Earth, tilted cameras less
MAX_GRAVITY_M_S2 = 20.0


@dataclass(frozen=True)
class Measurement:
    """The figures (`summary`, JSON-able, SI) and the fits behind them, for plots."""

    summary: dict
    phases: tuple          # (incoming, outgoing) `Phase`
    contact_frames: tuple  # first and last frame in contact
    gravity_px_s2: float


@dataclass(frozen=True)
class Phase:
    """A fitted free-flight phase: x = a + b t, y = c + d t + g t^2 / 2 (px, s)."""

    frames: np.ndarray
    coefficients: np.ndarray   # a, b, c, d
    covariance: np.ndarray     # 4 x 4
    residual_px: float         # rms of both coordinates

    def position(self, t):
        a, b, c, d = self.coefficients
        return a + b * t, c + d * t

    def velocity(self, t: float, g: float) -> np.ndarray:
        return np.array([self.coefficients[1], self.coefficients[3] + g * t])


def _fit_phase(frames, t, x, y, g) -> Phase:
    basis = np.column_stack([np.ones_like(t), t])
    cx = np.linalg.lstsq(basis, x, rcond=None)[0]
    cy = np.linalg.lstsq(basis, y - 0.5 * g * t ** 2, rcond=None)[0]
    dof = max(1, len(t) - 2)
    rx = x - basis @ cx
    ry = y - 0.5 * g * t ** 2 - basis @ cy
    inv = np.linalg.inv(basis.T @ basis)
    cov = np.zeros((4, 4))
    cov[:2, :2] = inv * (rx @ rx) / dof
    cov[2:, 2:] = inv * (ry @ ry) / dof
    rms = float(np.sqrt((rx @ rx + ry @ ry) / (2 * len(t))))
    return Phase(frames, np.concatenate([cx, cy]), cov, rms)


def _meeting_time(phase: Phase, g: float, bottom_offset: float, surface: float,
                  guess: float) -> float:
    """When the trajectory's lowest point (centre row + radius) reaches the surface row."""
    a, b, c, d = phase.coefficients
    # 0.5 g t^2 + d t + (c + r - s) = 0, the root nearest the guess
    k = c + bottom_offset - surface
    if abs(g) < 1e-12:
        return -k / d if d else guess
    disc = d * d - 2.0 * g * k
    if disc < 0:
        return guess
    roots = np.array([(-d - math.sqrt(disc)) / g, (-d + math.sqrt(disc)) / g])
    return float(roots[np.argmin(np.abs(roots - guess))])


def _speed_and_errors(v: np.ndarray, var: np.ndarray, scale: float, scale_rel_se: float):
    speed = float(np.hypot(*v))
    se_px = math.sqrt((v[0] ** 2 * var[0] + v[1] ** 2 * var[1])) / speed
    se = scale * math.hypot(se_px, speed * scale_rel_se)
    return speed * scale, se


def check_options(fps: float | None, *, scale_m_per_px: float | None = None,
                  ball_diameter_m: float | None = None, surface_row: float | None = None,
                  gravity_m_s2: float = 9.81) -> None:
    """`InputError` for settings no recording can have (before any frame is read): a frame
    rate that is not a positive number (None: from the file), not exactly one scale, a
    non-finite value, a diameter outside `BALL_DIAMETER_RANGE_M` (in mm, most likely), a
    negative surface row, or a gravity above `MAX_GRAVITY_M_S2`."""
    if fps is not None:
        check_range("fps (--fps)", fps, 0.0, low_open=True, note="frames per second")
    if (scale_m_per_px is None) == (ball_diameter_m is None):
        raise InputError("give exactly one of scale_m_per_px (--scale-m-per-px) or "
                         "ball_diameter_m (--ball-diameter-m)")
    for name, value in (("scale_m_per_px (--scale-m-per-px)", scale_m_per_px),
                        ("ball_diameter_m (--ball-diameter-m)", ball_diameter_m)):
        if value is not None:
            check_range(name, value, 0.0, low_open=True)
    low, high = BALL_DIAMETER_RANGE_M
    if ball_diameter_m is not None and not low <= ball_diameter_m <= high:
        slip = (f"looks like millimetres; use {ball_diameter_m / 1e3:g}"
                if ball_diameter_m > high else "check the unit (metres)")
        raise InputError(f"ball_diameter_m (--ball-diameter-m) {ball_diameter_m:g} m is outside "
                         f"{low:g}..{high:g} m, the sizes of balls: {slip}")
    if surface_row is not None:
        check_range("surface_row (--surface-row)", surface_row, 0.0, unit="px",
                    note="up to the picture's last row; rows count down from 0 at the top")
    check_range("gravity_m_s2 (--gravity-m-s2)", gravity_m_s2, -MAX_GRAVITY_M_S2,
                MAX_GRAVITY_M_S2, unit="m/s^2",
                note="9.81, or 0 for straight lines; in m/s^2, not mm/s^2 or pixels")


def check_surface_row(surface_row: float | None, height_px: int) -> None:
    """`InputError` for a surface row outside a picture `height_px` rows high."""
    if surface_row is not None:
        check_range("surface_row (--surface-row)", surface_row, 0.0, height_px - 1, unit="px",
                    note="the rows of the picture; rows count down from 0 at the top")


def check_speeds(summary: dict) -> None:
    """`InputError` when a measured speed is not finite or above `MAX_BALL_SPEED_M_S` (no ball
    is that fast): the error names the likely slip."""
    low, high = BALL_DIAMETER_RANGE_M
    diameter = 2.0 * summary["ball_radius_px"] * summary["scale_m_per_px"]
    if summary["scale_from"] == "given" and not low <= diameter <= high:
        slip = ("looks like millimetres per pixel; divide by 1000" if diameter > high
                else "check its unit (metres per pixel)")
        raise InputError(f"scale_m_per_px (--scale-m-per-px) {summary['scale_m_per_px']:g} "
                         f"m/px makes the ball {diameter:.3g} m across, outside {low:g}..{high:g} "
                         f"m: {slip}")
    for phase in ("impact", "rebound"):
        speed = summary[f"{phase}_speed_m_s"]
        if not math.isfinite(speed):
            raise InputError(f"video: the {phase} speed is not finite ({speed}); check --fps, "
                             "the scale and --gravity-m-s2")
        if speed > MAX_BALL_SPEED_M_S:
            raise InputError(
                f"video: {phase} speed {speed:g} m/s is above {MAX_BALL_SPEED_M_S:g} m/s, faster "
                f"than any ball sport: likely a wrong frame rate (--fps {summary['fps']:g}: the "
                "recording rate, in frames per second) or a wrong scale (--ball-diameter-m in m, "
                "e.g. 0.072; --scale-m-per-px in m per pixel)")


def measure(detections: list[Detection], fps: float, *, scale_m_per_px: float | None = None,
            ball_diameter_m: float | None = None, surface_row: float | None = None,
            gravity_m_s2: float = 9.81) -> Measurement:
    """Speeds (m/s), angles from the surface normal (deg), normal COR, with standard errors
    (`Measurement.summary`). The settings are checked first (`check_options`), the speeds last
    (`check_speeds`)."""
    if fps is None:
        raise InputError("fps (--fps): the frame rate is needed")
    check_options(fps, scale_m_per_px=scale_m_per_px, ball_diameter_m=ball_diameter_m,
                  surface_row=surface_row, gravity_m_s2=gravity_m_s2)
    found = np.array([d.found and not d.touches_border for d in detections])
    if found.sum() < 2 * MIN_FLIGHT_FRAMES:
        raise InputError(f"video: the ball was found whole in {int(found.sum())} of "
                         f"{len(detections)} frames; at least {2 * MIN_FLIGHT_FRAMES} are needed "
                         "(no ball found? check the lighting, or the ball leaves the picture)")
    residual = np.array([d.residual_px if f else np.nan for d, f in zip(detections, found)])
    good = found & (residual <= RESIDUAL_FACTOR * np.nanmedian(residual) + 0.2)
    bottom = np.array([d.bottom_row if f else np.nan for d, f in zip(detections, found)])
    if surface_row is None:
        surface_row = float(np.nanmax(bottom))
        estimated = True
    else:
        estimated = False
    contact = found & (bottom >= surface_row - CONTACT_MARGIN_PX)
    touching = np.flatnonzero(contact)
    if touching.size == 0:
        raise InputError(f"video: no frame reaches the surface row {surface_row:g} px: the "
                         "impact is not in the video (or --surface-row is wrong)")
    first, last = touching[0], touching[-1]
    free = good & ~contact
    before = np.flatnonzero(free[:first])
    after = last + 1 + np.flatnonzero(free[last + 1:])
    for name, frames in (("before", before), ("after", after)):
        if len(frames) < MIN_FLIGHT_FRAMES:
            raise InputError(f"video: {len(frames)} usable frames {name} the impact; at least "
                             f"{MIN_FLIGHT_FRAMES} are needed")
    flight = np.concatenate([before, after])
    radius_px = _perpendicular_radius(detections, flight)
    radius = float(np.median(radius_px))
    radius_rel_se = float(np.std(radius_px) / math.sqrt(len(radius_px)) / radius)
    if scale_m_per_px is None:
        scale = ball_diameter_m / (2.0 * radius)
        scale_rel_se = radius_rel_se
    else:
        scale, scale_rel_se = scale_m_per_px, 0.0
    g = gravity_m_s2 / scale  # px/s^2 along +row
    centres = np.array([d.centre_px for d in detections])
    t = np.arange(len(detections)) / fps
    phases = [_fit_phase(f, t[f], centres[f, 0], centres[f, 1], g) for f in (before, after)]
    t_in = _meeting_time(phases[0], g, radius, surface_row, t[first])
    t_out = _meeting_time(phases[1], g, radius, surface_row, t[last])
    v_in, v_out = phases[0].velocity(t_in, g), phases[1].velocity(t_out, g)
    var_in = np.array([phases[0].covariance[1, 1], phases[0].covariance[3, 3]])
    var_out = np.array([phases[1].covariance[1, 1], phases[1].covariance[3, 3]])
    s_in, se_in = _speed_and_errors(v_in, var_in, scale, scale_rel_se)
    s_out, se_out = _speed_and_errors(v_out, var_out, scale, scale_rel_se)
    # components normal and tangential to the surface (what a load cell's impulse balances is
    # the normal one); tangential positive along the incoming motion across the image
    across = 1.0 if v_in[0] >= 0 else -1.0
    components = {}
    for phase, v, var, normal in (("impact", v_in, var_in, v_in[1]),
                                  ("rebound", v_out, var_out, -v_out[1])):
        components[f"{phase}_speed_normal_m_s"] = float(normal * scale)
        components[f"{phase}_speed_normal_se_m_s"] = scale * math.hypot(
            math.sqrt(var[1]), normal * scale_rel_se)
        components[f"{phase}_speed_tangential_m_s"] = float(across * v[0] * scale)
        components[f"{phase}_speed_tangential_se_m_s"] = scale * math.hypot(
            math.sqrt(var[0]), v[0] * scale_rel_se)
    cor = float(-v_out[1] / v_in[1])
    cor_se = abs(cor) * math.hypot(math.sqrt(var_out[1]) / v_out[1], math.sqrt(var_in[1]) / v_in[1])
    out = {
        "impact_speed_m_s": s_in, "impact_speed_se_m_s": se_in,
        "rebound_speed_m_s": s_out, "rebound_speed_se_m_s": se_out,
        "impact_angle_deg": math.degrees(math.atan2(v_in[0], v_in[1])),
        "impact_angle_se_deg": _angle_se(v_in, var_in),
        "rebound_angle_deg": math.degrees(math.atan2(v_out[0], -v_out[1])),
        "rebound_angle_se_deg": _angle_se(v_out, var_out),
        **components,
        "cor": cor, "cor_se": cor_se, "speed_ratio": s_out / s_in,
        "impact_time_s": t_in, "rebound_time_s": t_out,
        "scale_m_per_px": scale, "scale_from": "ball_diameter" if scale_m_per_px is None
        else "given", "ball_radius_px": radius, "surface_row_px": surface_row,
        "surface_row_estimated": estimated, "frames": len(detections),
        "frames_before": len(before), "frames_after": len(after),
        "frames_contact": int(last - first + 1), "centre_residual_px":
        [phases[0].residual_px, phases[1].residual_px],
        "gravity_m_s2": gravity_m_s2, "fps": fps}
    check_speeds(out)
    return Measurement(out, tuple(phases), (int(first), int(last)), g)


def side_file(summary: dict, mass_kg: float | None = None, source: str | None = None) -> dict:
    """The JSON side file of the force record taken with this video (docs/video.md): the
    impact and rebound speeds as their components normal to the surface (`impact_speed_m_s`,
    `rebound_speed_m_s`: what features, fit and identify balance the load cell's impulse
    against), and each phase's normal, tangential and total speed and angle from the normal
    (tangential positive along the incoming motion)."""
    out: dict = {"source": source} if source else {}
    for phase in ("impact", "rebound"):
        normal = summary[f"{phase}_speed_normal_m_s"]
        tangential = summary[f"{phase}_speed_tangential_m_s"]
        out[f"{phase}_speed_m_s"] = normal
        out[f"{phase}_speed_normal_m_s"] = normal
        out[f"{phase}_speed_tangential_m_s"] = tangential
        out[f"{phase}_speed_total_m_s"] = summary[f"{phase}_speed_m_s"]
        out[f"{phase}_angle_deg"] = math.degrees(math.atan2(tangential, normal))
    if mass_kg is not None:
        out["mass_kg"] = mass_kg
    return out


def write_side_file(path: str | Path, summary: dict, mass_kg: float | None = None,
                    source: str | None = None) -> str:
    """`side_file` written to `path` as indented JSON (a .json beside the force record:
    test1.csv -> test1.json); returns the path as text."""
    Path(path).write_text(json.dumps(side_file(summary, mass_kg, source), indent=2) + "\n")
    return str(path)


def check_mass(mass_kg: float) -> float:
    """A ball mass (kg) for the side file: a finite number > 0 within the masses of
    `balls.checks.BALL_RANGES`, else `InputError` (grams typed as kg named as such)."""
    from ..balls.checks import BALL_RANGES

    check_range("--mass-kg", mass_kg, 0.0, low_open=True, unit="kg")
    low, high, _ = BALL_RANGES["mass"]
    if not low <= mass_kg <= high:
        slip = (f"looks like grams; use {mass_kg / 1e3:g}" if mass_kg > high
                else "check the unit (kg)")
        raise InputError(f"--mass-kg {mass_kg:g} kg is outside {low:g}..{high:g} kg, the masses "
                         f"of balls: {slip}")
    return mass_kg


def _angle_se(v: np.ndarray, var: np.ndarray) -> float:
    n2 = v @ v
    return math.degrees(math.sqrt((v[1] ** 2 * var[0] + v[0] ** 2 * var[1])) / n2)


def _perpendicular_radius(detections, frames) -> np.ndarray:
    """Each frame's half-width of the blob across its motion (px), from the sub-pixel width
    profiles: blur stretches the blob along the motion, so the widths near the across
    direction are the ball's diameter."""
    centres = np.array([detections[i].centre_px for i in frames])
    radii = []
    for k, i in enumerate(frames):
        step = centres[min(k + 1, len(frames) - 1)] - centres[max(k - 1, 0)]
        across = math.atan2(step[0], -step[1])  # the motion turned by 90 degrees
        gap = np.abs((PROFILE_ANGLES - across + np.pi / 2) % np.pi - np.pi / 2)
        # the median over the directions within 45 degrees of across: one direction alone
        # follows the ball's shading against the local background
        radii.append(0.5 * np.nanmedian(detections[i].widths_px[gap <= np.pi / 4 + 1e-9]))
    radii = np.array(radii)
    return radii[np.isfinite(radii)]
