"""Find the ball in each frame: background subtraction, the largest moving blob, and a circle
fitted to its edge (NumPy/SciPy).

The background is the per-pixel median over the frames (the ball moves, so each pixel shows
the background in most frames). A pixel is moving when it differs from the background by more
than `threshold_sigmas` robust noise deviations (the MAD of the difference image). The blob's
edge pixels, moved half a pixel outward, are fitted by a circle (algebraic least squares, then
Gauss-Newton on the geometric distance): the centre to a fraction of a pixel. Motion blur
stretches the blob along the motion into a stadium; its centre is the ball's position at
mid-exposure, which shifts every frame's time by the same amount and leaves velocities alone.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ..errors import InputError

#: fewest edge pixels for a circle fit
MIN_EDGE_PIXELS = 12
#: directions (rad, from the column axis) of the sub-pixel width profiles
PROFILE_ANGLES = np.arange(8) * np.pi / 8


@dataclass(frozen=True)
class Detection:
    """The ball in one frame (pixels; column, row), or `found` False."""

    found: bool
    centre_px: tuple[float, float] = (np.nan, np.nan)
    radius_px: float = np.nan
    residual_px: float = np.nan        # rms geometric residual of the circle fit
    bottom_row: float = np.nan         # lowest blob pixel row
    touches_border: bool = False
    edge_px: np.ndarray | None = None  # (k, 2) edge points (column, row)
    #: the blob's width (px) along `PROFILE_ANGLES` from the centre, at half the local contrast
    widths_px: np.ndarray | None = None


def background(frames: np.ndarray) -> np.ndarray:
    return np.median(frames.astype(np.float32), axis=0)


def fit_circle(points: np.ndarray, iterations: int = 10) -> tuple[np.ndarray, float, float]:
    """Centre (2,), radius and rms residual of the circle nearest to `points` (k, 2)."""
    x, y = points[:, 0], points[:, 1]
    a = np.column_stack([x, y, np.ones_like(x)])
    b = x * x + y * y
    (p, q, c), *_ = np.linalg.lstsq(a, b, rcond=None)   # Kasa: x^2 + y^2 = p x + q y + c
    centre = np.array([p / 2.0, q / 2.0])
    radius = np.sqrt(c + centre @ centre)
    for _ in range(iterations):  # geometric refinement
        d = points - centre
        dist = np.hypot(d[:, 0], d[:, 1])
        dist = np.where(dist == 0, 1e-12, dist)
        jac = np.column_stack([-d[:, 0] / dist, -d[:, 1] / dist, -np.ones_like(dist)])
        step, *_ = np.linalg.lstsq(jac, -(dist - radius), rcond=None)
        centre = centre + step[:2]
        radius = radius + step[2]
        if np.abs(step).max() < 1e-6:
            break
    residual = np.hypot(*(points - centre).T) - radius
    return centre, float(radius), float(np.sqrt(np.mean(residual ** 2)))


def _widths(diff: np.ndarray, centre: np.ndarray, radius: float) -> np.ndarray:
    """Width of the blob through its centre along each of `PROFILE_ANGLES` (px): on each side
    the outermost point where the difference profile falls to half its level just inside the
    edge (0.6-0.85 r), so the shading of the ball and the threshold do not bias it."""
    s = np.arange(-1.6 * radius, 1.6 * radius, 0.05)
    out = []
    for angle in PROFILE_ANGLES:
        u = np.array([np.cos(angle), np.sin(angle)])
        cols, rows = centre[0] + s * u[0], centre[1] + s * u[1]
        p = ndimage.map_coordinates(diff, [rows, cols], order=1, mode="nearest")
        edges = []
        for side in (1.0, -1.0):
            inside = (side * s >= 0.6 * radius) & (side * s <= 0.85 * radius)
            half = 0.5 * p[inside].mean()
            idx = np.flatnonzero((side * s >= 0.85 * radius) & (p >= half))
            if idx.size == 0:
                edges.append(np.nan)
                continue
            k = idx[-1] if side > 0 else idx[0]   # the outermost point still above half
            k2 = k + (1 if side > 0 else -1)
            if not 0 <= k2 < len(s) or p[k] == p[k2]:
                edges.append(s[k])
                continue
            edges.append(s[k] + (s[k2] - s[k]) * (p[k] - half) / (p[k] - p[k2]))
        out.append(edges[0] - edges[1])
    return np.array(out)


def detect(frame: np.ndarray, back: np.ndarray, threshold_sigmas: float = 6.0,
           min_area_px: int = 30) -> Detection:
    diff = np.abs(frame.astype(np.float32) - back)
    sigma = 1.4826 * np.median(np.abs(diff - np.median(diff))) + 1e-6
    mask = diff > max(threshold_sigmas * sigma, 4.0)
    mask = ndimage.binary_opening(mask, iterations=1)
    labels, n = ndimage.label(mask)
    if n == 0:
        return Detection(False)
    sizes = ndimage.sum(mask, labels, index=np.arange(1, n + 1))
    biggest = int(np.argmax(sizes)) + 1
    if sizes[biggest - 1] < min_area_px:
        return Detection(False)
    blob = ndimage.binary_fill_holes(labels == biggest)
    edge = blob & ~ndimage.binary_erosion(blob)
    rows, cols = np.nonzero(edge)
    if len(rows) < MIN_EDGE_PIXELS:
        return Detection(False)
    h, w = frame.shape
    border = bool(rows.min() == 0 or cols.min() == 0 or rows.max() == h - 1 or cols.max() == w - 1)
    points = np.column_stack([cols, rows]).astype(float)
    centre, radius, residual = fit_circle(points)
    widths = _widths(diff, centre, radius)
    # the blob keeps the pixels the ball covers by more than about the threshold's share, so
    # its edge pixels lie on the boundary to ~0.1 px (measured on synthetic discs)
    return Detection(True, (float(centre[0]), float(centre[1])), radius, residual,
                     float(rows.max()) + 0.5, border, points, widths)


def _blob_mask(detection: Detection, shape: tuple[int, int], grow_px: float) -> np.ndarray:
    rows, cols = np.ogrid[:shape[0], :shape[1]]
    cx, cy = detection.centre_px
    return (cols - cx) ** 2 + (rows - cy) ** 2 <= (detection.radius_px + grow_px) ** 2


def track(frames: np.ndarray, threshold_sigmas: float = 6.0) -> list[Detection]:
    """One `Detection` per frame of `frames` (n, height, width) grey levels.

    Two passes: the plain median background is spoiled where the ball dwells (near the contact
    point the ball covers a pixel in many frames), so the second background is each pixel's
    median over the frames in which the first pass did not find the ball on it."""
    if frames.ndim != 3 or len(frames) < 3:
        raise InputError(f"video: need at least 3 grey frames, got shape {frames.shape}")
    back = background(frames)
    first = [detect(frame, back, threshold_sigmas) for frame in frames]
    stack = frames.astype(np.float32)
    for i, found in enumerate(first):
        if found.found:
            grow = 3.0 + 0.5 * found.radius_px  # blur and a poor first fit
            stack[i][_blob_mask(found, frames.shape[1:], grow)] = np.nan
    clean = np.nanmedian(stack, axis=0)
    back = np.where(np.isnan(clean), back, clean)
    return [detect(frame, back, threshold_sigmas) for frame in frames]
