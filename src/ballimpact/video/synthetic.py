"""Synthetic high-speed videos of a ball bouncing off a horizontal surface, with known speeds
(for verifying the tracker): a shaded disc, motion blur over the exposure, a textured
background, sensor noise and 8-bit quantisation.

Image convention: rows grow downward; the surface is the row `surface_row`; gravity acts along
+row. The ball arrives from the upper left at `angle_deg` from the surface normal and leaves
with normal and tangential COR `cor_normal`, `cor_tangential`; during the contact time the
ball is drawn flattened against the surface (those frames are not used by the tracker).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.ndimage import gaussian_filter


@dataclass(frozen=True)
class SyntheticImpact:
    speed_m_s: float = 20.0
    angle_deg: float = 20.0           # from the surface normal
    cor_normal: float = 0.5
    cor_tangential: float = 0.8
    fps: float = 10000.0
    exposure_fraction: float = 0.5    # shutter open over this fraction of the frame interval
    ball_diameter_m: float = 0.072
    scale_m_per_px: float = 0.0015
    contact_time_s: float = 1e-3
    travel_diameters: float = 3.0     # the ball's path in view before and after contact
    width_px: int = 400
    height_px: int = 320
    surface_row: float = 300.0
    noise: float = 3.0                # grey levels (of 255), standard deviation
    texture: float = 25.0             # grey-level amplitude of the background texture
    gravity_m_s2: float = 9.81
    seed: int = 0

    @property
    def radius_px(self) -> float:
        return 0.5 * self.ball_diameter_m / self.scale_m_per_px

    def velocities_px_s(self) -> tuple[np.ndarray, np.ndarray]:
        """Ball-centre velocity (column, row) px/s at the start and at the end of contact."""
        a = math.radians(self.angle_deg)
        v_in = self.speed_m_s / self.scale_m_per_px * np.array([math.sin(a), math.cos(a)])
        v_out = np.array([self.cor_tangential * v_in[0], -self.cor_normal * v_in[1]])
        return v_in, v_out

    def centre_px(self, t_s: np.ndarray) -> np.ndarray:
        """Ball centre (column, row) at times t_s (s); contact from t = 0 to contact_time_s."""
        g = self.gravity_m_s2 / self.scale_m_per_px
        v_in, v_out = self.velocities_px_s()
        touch = np.array([0.25 * self.width_px, self.surface_row - self.radius_px])
        t = np.asarray(t_s, dtype=float)[:, None]
        before = touch + v_in * t + 0.5 * np.array([0.0, g]) * t ** 2
        leave = touch + np.array([0.5 * (v_in[0] + v_out[0]) * self.contact_time_s, 0.0])
        ta = t - self.contact_time_s
        after = leave + v_out * ta + 0.5 * np.array([0.0, g]) * ta ** 2
        during = touch + np.array([1.0, 0.0]) * (0.5 * (v_in[0] + v_out[0]) * t)
        return np.where(t < 0, before, np.where(t > self.contact_time_s, after, during))

    def truth(self) -> dict:
        """What the tracker should report: speeds (m/s) and angles (deg from the normal) just
        before and just after contact, and the normal COR."""
        v_in, v_out = self.velocities_px_s()
        s = self.scale_m_per_px
        return {"impact_speed_m_s": float(np.hypot(*v_in) * s),
                "rebound_speed_m_s": float(np.hypot(*v_out) * s),
                "impact_angle_deg": self.angle_deg,
                "rebound_angle_deg": float(math.degrees(math.atan2(v_out[0], -v_out[1]))),
                "cor": self.cor_normal}

    def frame_times_s(self) -> np.ndarray:
        """Frames while the ball travels `travel_diameters` before and after contact."""
        v_in, v_out = self.velocities_px_s()
        path = self.travel_diameters * 2.0 * self.radius_px
        before = math.ceil(path / np.hypot(*v_in) * self.fps)
        after = math.ceil(path / np.hypot(*v_out) * self.fps)
        n_contact = math.ceil(self.contact_time_s * self.fps)
        return np.arange(-before, n_contact + after) / self.fps


def _background(shape: tuple[int, int], texture: float, rng) -> np.ndarray:
    smooth = gaussian_filter(rng.standard_normal(shape), 6.0)
    fine = gaussian_filter(rng.standard_normal(shape), 1.5)
    field = smooth / smooth.std() + 0.5 * fine / fine.std()
    return 110.0 + texture * field / 1.5


def render(impact: SyntheticImpact, supersample: int = 4, blur_steps: int = 9) -> np.ndarray:
    """The frames (n, height, width) as uint8. Each frame averages `blur_steps` positions over
    the exposure; each pixel averages `supersample`^2 sub-pixel samples of the disc (an even
    count: no sample at the pixel centre, so an edge through it covers half the pixel)."""
    rng = np.random.default_rng(impact.seed)
    h, w = impact.height_px, impact.width_px
    background = _background((h, w), impact.texture, rng)
    background[int(math.ceil(impact.surface_row)):, :] = 40.0  # the surface, dark
    r = impact.radius_px
    offsets = (np.arange(supersample) + 0.5) / supersample - 0.5
    frames = []
    for t0 in impact.frame_times_s():
        exposure = impact.exposure_fraction / impact.fps
        times = t0 + (np.arange(blur_steps) + 0.5) / blur_steps * exposure
        centres = impact.centre_px(times)
        coverage = np.zeros((h, w))
        shade = np.zeros((h, w))
        for cx, cy in centres:
            c0, c1 = int(max(0, cx - r - 2)), int(min(w, cx + r + 3))
            r0, r1 = int(max(0, cy - r - 2)), int(min(h, cy + r + 3))
            if c0 >= c1 or r0 >= r1:
                continue
            cols = np.arange(c0, c1)[None, :, None, None] + offsets[None, None, None, :]
            rows = np.arange(r0, r1)[:, None, None, None] + offsets[None, None, :, None]
            dx, dy = cols - cx, rows - cy
            inside = (dx ** 2 + dy ** 2 <= r * r) & (rows < impact.surface_row)
            light = 200.0 + 45.0 * (-(dx + dy) / (1.414 * r))   # lit from the upper left
            coverage[r0:r1, c0:c1] += inside.mean(axis=(2, 3))
            shade[r0:r1, c0:c1] += (inside * light).mean(axis=(2, 3))
        coverage /= blur_steps
        shade /= blur_steps
        image = background * (1.0 - coverage) + shade
        image += impact.noise * rng.standard_normal((h, w))
        frames.append(np.clip(np.round(image), 0, 255).astype(np.uint8))
    return np.stack(frames)
