"""The study's image preprocessing: grayscale, 32x64, contrast enhanced.

to_gray shrinks the colour frames; CONTRASTS (the registry of preprocess.contrast methods) and
enhance_image_contrast enhance them; frame_statistics measures them for the split.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

# cv2 is imported in the functions that use it: every stage's params check imports this module
# (its CONTRASTS), and most stages touch no image


def to_gray(frames: np.ndarray, height: int, width: int) -> np.ndarray:
    """(N, h, w, 3) BGR uint8 -> (N, height, width) uint8 grayscale, shrunk with area averaging."""
    if frames.ndim != 4 or frames.shape[-1] != 3:
        raise ValueError(f"expected colour frames of shape (N, h, w, 3), got {frames.shape}")
    import cv2

    out = np.empty((len(frames), height, width), dtype=np.uint8)
    for i, frame in enumerate(frames):
        gray = cv2.cvtColor(frame, cv2.COLOR_BGR2GRAY)
        out[i] = cv2.resize(gray, (width, height), interpolation=cv2.INTER_AREA)
    return out


# One function per preprocess.contrast value, (images, clahe_clip, clahe_grid) -> images; each
# image is enhanced independently. A new method is one function plus one CONTRASTS line.
ContrastMethod = Callable[[np.ndarray, float, int], np.ndarray]


def _no_contrast(images: np.ndarray, clahe_clip: float, clahe_grid: int) -> np.ndarray:
    return images.copy()


def _equalize(images: np.ndarray, clahe_clip: float, clahe_grid: int) -> np.ndarray:
    import cv2

    return np.stack([cv2.equalizeHist(image) for image in images]) if len(images) else images.copy()


def _clahe(images: np.ndarray, clahe_clip: float, clahe_grid: int) -> np.ndarray:
    import cv2

    clahe = cv2.createCLAHE(clipLimit=float(clahe_clip), tileGridSize=(int(clahe_grid), int(clahe_grid)))
    return np.stack([clahe.apply(image) for image in images]) if len(images) else images.copy()


# preprocess.contrast is checked against these names (seasonloop.registries)
CONTRASTS: dict[str, ContrastMethod] = {"clahe": _clahe, "equalize": _equalize, "none": _no_contrast}


def enhance_image_contrast(images: np.ndarray, method: str, clahe_clip: float, clahe_grid: int) -> np.ndarray:
    """Contrast-enhance each (H, W) uint8 image independently with CONTRASTS[method]."""
    if method not in CONTRASTS:
        raise ValueError(f"preprocess.contrast: unknown method '{method}' (known: {', '.join(CONTRASTS)})")
    return CONTRASTS[method](images, clahe_clip, clahe_grid)


def frame_statistics(gray: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per-frame mean brightness and mean absolute change from the previous frame.

    Computed on the grayscale frames before contrast enhancement, which would brighten tunnels.
    The first frame's change is +inf (it has no predecessor and must not look like a stop).
    """
    brightness = gray.reshape(len(gray), -1).mean(axis=1)
    change = np.full(len(gray), np.inf)
    if len(gray) > 1:
        diff = np.abs(gray[1:].astype(np.int16) - gray[:-1].astype(np.int16))
        change[1:] = diff.reshape(len(diff), -1).mean(axis=1)
    return brightness, change
