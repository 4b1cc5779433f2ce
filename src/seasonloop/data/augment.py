"""Training-set augmentation as in the study (Keras ImageDataGenerator settings of its Table 2):
random horizontal flip and random width / height shifts, no rotation, no vertical flip.

Shifts are whole pixels and the border is filled with the nearest edge pixel (Keras' default
fill_mode "nearest"); the whole batch is done with one fancy-indexing gather. An augmented set is
the originals followed by `copies` augmented copies, each in the originals' order:
augmented_places says which place every row shows, for the learners that read it back.
"""

from __future__ import annotations

import numpy as np


def augment_images(
    images: np.ndarray,
    rng: np.random.Generator,
    horizontal_flip: bool = True,
    width_shift: float = 0.3,
    height_shift: float = 0.3,
) -> np.ndarray:
    """One randomly augmented copy of each (H, W) image in `images` (N, H, W)."""
    if images.ndim != 3:
        raise ValueError(f"expected images of shape (N, H, W), got {images.shape}")
    for key, value in (("augment.width_shift", width_shift), ("augment.height_shift", height_shift)):
        if not 0 <= value < 1:
            raise ValueError(f"{key}: must be in [0, 1), got {value}")
    n, height, width = images.shape
    dx = np.rint(rng.uniform(-width_shift, width_shift, n) * width).astype(int)
    dy = np.rint(rng.uniform(-height_shift, height_shift, n) * height).astype(int)
    flip = rng.random(n) < 0.5 if horizontal_flip else np.zeros(n, bool)
    assert isinstance(flip, np.ndarray)
    # output pixel x of a flipped-then-shifted image reads source column W-1-clip(x-dx)
    cols = np.clip(np.arange(width)[None, :] - dx[:, None], 0, width - 1)
    cols = np.where(flip[:, None], width - 1 - cols, cols)
    rows = np.clip(np.arange(height)[None, :] - dy[:, None], 0, height - 1)
    return images[np.arange(n)[:, None, None], rows[:, :, None], cols[:, None, :]]


def augment_training_set(
    images: np.ndarray,
    copies: int,
    seed: int,
    horizontal_flip: bool = True,
    width_shift: float = 0.3,
    height_shift: float = 0.3,
) -> np.ndarray:
    """The originals followed by `copies` augmented copies of each, reproducible from `seed`
    (row layout: augmented_places)."""
    if copies < 0:
        raise ValueError(f"augment.copies: must be >= 0, got {copies}")
    rng = np.random.default_rng(seed)
    parts = [images] + [augment_images(images, rng, horizontal_flip, width_shift, height_shift) for _ in range(copies)]
    return np.concatenate(parts, axis=0)


def augmented_places(places: np.ndarray, copies: int) -> np.ndarray:
    """The place id of every row of augment_training_set(images of `places`, copies, ...)."""
    if copies < 0:
        raise ValueError(f"augment.copies: must be >= 0, got {copies}")
    return np.tile(np.asarray(places), copies + 1)
