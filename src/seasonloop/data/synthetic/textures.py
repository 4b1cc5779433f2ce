"""The route's seeded texture tables (256 x 256, looked up by world coordinates) and their lookup."""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np

from .palette import MID


class Textures:
    """Fine grain in -3..3, smooth unit-variance patches, and random attributes for `noise.slots`.

    Built from the world's generator before the zones, so the draws come in the order pinned.
    """

    def __init__(self, rng: np.random.Generator):
        grain = np.clip(np.rint(rng.normal(0.0, 1.4, (256, 256))), -3, 3)
        # Smooth noise that tiles seamlessly: blur a 3x3 tiling and keep the middle tile.
        tiled = np.tile(rng.normal(0.0, 1.0, (256, 256)).astype(np.float32), (3, 3))
        patches = cv2.GaussianBlur(tiled, (0, 0), 6)[256:512, 256:512]
        patches = (patches - patches.mean()) / patches.std()
        self.patches_flat = patches.astype(np.float32).ravel()
        self.grain_flat = grain.astype(np.float32).ravel()
        self.grain_int_flat = grain.astype(np.int32).ravel()
        self.coarse_flat = (MID + np.rint(1.5 * patches)).astype(np.int32).ravel()
        self.table = rng.random((8, 1 << 16))  # random attributes of trees, looked up by `slots`


def texture(table: np.ndarray, rows: np.ndarray, cols: Any) -> np.ndarray:
    """Look up a flattened 256 x 256 texture table at (row, col) coordinates, wrapping around."""
    return np.take(table, ((rows.astype(np.int32) & 255) << 8) + (cols.astype(np.int32) & 255))
