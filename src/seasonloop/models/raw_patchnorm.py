"""SeqSLAM single-image baseline: the patch-normalised image itself is the descriptor."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.data.patchnorm import PATCH_NORM_MODES, patch_normalise
from seasonloop.models.core.learner import EpochCallback, FeatureLearner
from seasonloop.params.checks import integer, one_of


class RawPatchNorm(FeatureLearner):
    """No learning: descriptor = patch_normalise(image).ravel()."""

    name = "raw_patchnorm"
    learns = False
    PARAMS = {"patch_size": integer(1), "mode": one_of(*PATCH_NORM_MODES)}

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        height, width = self.image_shape
        patch_size = self.params["patch_size"]
        if height % patch_size or width % patch_size:
            raise ValueError(
                f"{self._key('patch_size')} = {patch_size} does not divide the image size {height}x{width}"
            )
        return {"n_train_images": len(images)}

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        normalised = patch_normalise(images, self.params["patch_size"], self.params["mode"])
        return normalised.reshape(len(images), -1)

    def _save_state(self, directory: Path) -> None:
        """Nothing is learned; learner.json is the whole model."""

    def _load_state(self, directory: Path) -> None:
        """Nothing is learned; learner.json is the whole model."""
