"""Reading a high-speed recording as grey frames: a video file through OpenCV (MP4, AVI, ...),
a folder of images (PNG, JPEG, TIFF, BMP; sorted by name), or an `.npz` holding `frames`."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..errors import InputError, InputWarning

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp")


def _grey(image: np.ndarray) -> np.ndarray:
    image = np.asarray(image, dtype=np.float32)
    if image.ndim == 3:  # RGB(A): luminance
        image = image[..., :3] @ np.array([0.299, 0.587, 0.114], dtype=np.float32)
    if image.max() <= 1.0:  # matplotlib reads PNG as 0-1 floats
        image = image * 255.0
    return image


def read_frames(path: str | Path) -> tuple[np.ndarray, float | None]:
    """(frames (n, height, width) grey levels 0-255, the file's frame rate or None)."""
    path = Path(path)
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
        if not files:
            raise InputError(f"{path}: no images ({', '.join(IMAGE_SUFFIXES)}) in the folder")
        import matplotlib.image as mpimg

        try:
            frames = [_grey(mpimg.imread(p)) for p in files]
        except (OSError, ValueError) as error:
            raise InputError(f"{path}: cannot read an image ({error})") from None
        if len({f.shape for f in frames}) > 1:
            raise InputError(f"{path}: the images differ in size")
        return np.stack(frames), None
    if not path.is_file():
        raise InputError(f"{path}: no such file or folder")
    if path.suffix.lower() == ".npz":
        try:
            with np.load(path, allow_pickle=False) as data:
                frames = np.asarray(data["frames"], dtype=np.float32)
                fps = float(data["fps_hz"]) if "fps_hz" in data else None
        except (OSError, ValueError, KeyError) as error:
            raise InputError(f"{path}: not an .npz with a 'frames' array ({error})") from None
        if frames.ndim == 4:
            frames = np.stack([_grey(f) for f in frames])
        return frames, fps
    try:
        import cv2
    except ModuleNotFoundError:
        raise InputError(f"{path}: reading video files needs OpenCV "
                         "(pip install 'ballimpact[video]'); an image folder or .npz needs "
                         "nothing more") from None
    capture = cv2.VideoCapture(str(path))
    frames = []
    try:
        while capture.isOpened():
            ok, image = capture.read()
            if not ok:
                break
            frames.append(cv2.cvtColor(image, cv2.COLOR_BGR2GRAY).astype(np.float32))
        fps = capture.get(cv2.CAP_PROP_FPS) or None
    finally:
        capture.release()
    if not frames:
        raise InputError(f"{path}: unreadable video (OpenCV found no frames)")
    return np.stack(frames), fps


def frame_rate(given: float | None, from_file: float | None, path: Path) -> float:
    if given is not None:
        return given
    if from_file:
        warnings.warn(f"{path}: frame rate {from_file:g} fps from the file; high-speed cameras "
                      "often store the playback rate there: give --fps", InputWarning,
                      stacklevel=2)
        return from_file
    raise InputError(f"{path}: the frame rate is unknown: give --fps")


def write_frames_npz(path: Path, frames: np.ndarray, fps_hz: float) -> None:
    np.savez_compressed(path, frames=frames, fps_hz=np.float64(fps_hz))
