"""Patch normalisation (as in SeqSLAM): normalise every small image patch independently."""

from __future__ import annotations

import numpy as np

PATCH_NORM_MODES = ("zscore", "minmax")


def _patch_shape(patch_size: int | tuple[int, int]) -> tuple[int, int]:
    """Return (patch_height, patch_width) from an int or a pair; reject non-positive sizes."""
    if isinstance(patch_size, (int, np.integer)):
        shape = (int(patch_size), int(patch_size))
    else:
        try:
            patch_height, patch_width = patch_size
        except (TypeError, ValueError):
            raise ValueError(f"patch_size must be an int or a pair of ints, got {patch_size!r}") from None
        shape = (int(patch_height), int(patch_width))
    if min(shape) < 1:
        raise ValueError(f"patch_size must be positive, got {patch_size!r}")
    return shape


def patch_normalise(
    images: np.ndarray, patch_size: int | tuple[int, int] = 8, mode: str = "zscore", eps: float = 1e-6
) -> np.ndarray:
    """Normalise each non-overlapping patch of each image independently.

    images: (N, H, W) or (H, W), any real dtype. Returns float32 of the same shape.
    mode "zscore": each patch to zero mean and unit (population) standard deviation;
    mode "minmax": each patch linearly to [0, 1].
    eps: floor on a patch's std (zscore) or range (minmax), so flat patches map to 0
    instead of dividing by zero.
    """
    if mode not in PATCH_NORM_MODES:
        raise ValueError(f"mode must be one of {', '.join(PATCH_NORM_MODES)}, got {mode!r}")
    array = np.asarray(images)
    if array.ndim not in (2, 3):
        raise ValueError(f"images must have shape (N, H, W) or (H, W), got shape {array.shape}")
    patch_height, patch_width = _patch_shape(patch_size)
    height, width = array.shape[-2:]
    if height % patch_height or width % patch_width:
        raise ValueError(f"image size {height}x{width} is not divisible by patch_size {patch_height}x{patch_width}")
    stack = array.reshape(-1, height, width).astype(np.float32)
    # (N, rows, patch_height, cols, patch_width): axes 2 and 4 run inside one patch.
    patches = stack.reshape(stack.shape[0], height // patch_height, patch_height, width // patch_width, patch_width)
    if mode == "zscore":
        centre = patches.mean(axis=(2, 4), keepdims=True)
        scale = patches.std(axis=(2, 4), keepdims=True)
    else:
        centre = patches.min(axis=(2, 4), keepdims=True)
        scale = patches.max(axis=(2, 4), keepdims=True) - centre
    normalised = (patches - centre) / np.maximum(scale, np.float32(eps))
    return normalised.reshape(array.shape).astype(np.float32, copy=False)
