"""VPR-Bench's HOG (VPR_Techniques/HOG_VPR.py): OpenCV's HOGDescriptor of the image resized to
512 x 512, blocks of 16 x 16 pixels every 8, cells of 16, 9 orientation bins; nothing learned.

VPR-Bench matches it by cosine similarity, params.yaml's evaluate.metric. It describes the images every
learner here is given (the study's preprocessed grayscale images), not the dataset's own images as
VPR-Bench does: the comparison with the study's learners is at equal input.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.models.core.learner import EpochCallback, FeatureLearner
from seasonloop.params.checks import integer


class HOG(FeatureLearner):
    """Descriptor = cv2.HOGDescriptor((size, size), (block, block), (block_stride, block_stride),
    (cell, cell), bins).compute(cv2.resize(image, (size, size)))."""

    name = "hog"
    # VPR-Bench's HOG of a 128 px square (2,025 numbers), not of 512 px (35,721): the same code
    TINY_RUN = {"size": 128}
    learns = False
    LIBRARIES = ("cv2",)
    PARAMS = {
        "size": integer(8),  # the image is resized to size x size: HOG's window
        "block": integer(1),
        "block_stride": integer(1),
        "cell": integer(1),
        "bins": integer(1),
    }

    def _validate_params(self) -> None:
        size, block, stride, cell = (self.params[key] for key in ("size", "block", "block_stride", "cell"))
        # OpenCV's own conditions on the window, block, stride and cell
        if block > size or (size - block) % stride:
            raise ValueError(
                f"{self._key('block')} = {block} and {self._key('block_stride')} = {stride} do not tile "
                f"{self._key('size')} = {size} (need block <= size and (size - block) divisible by block_stride)"
            )
        if block % cell or block % stride:
            raise ValueError(
                f"{self._key('cell')} = {cell} and {self._key('block_stride')} = {stride} must divide "
                f"{self._key('block')} = {block}"
            )

    def descriptor(self) -> Any:
        """The configured cv2.HOGDescriptor."""
        import cv2

        size, block, stride, cell = (self.params[key] for key in ("size", "block", "block_stride", "cell"))
        return cv2.HOGDescriptor((size, size), (block, block), (stride, stride), (cell, cell), self.params["bins"])

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        return {"n_train_images": len(images)}

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        import cv2

        hog, size = self.descriptor(), self.params["size"]
        if images.dtype != np.uint8:  # OpenCV's HOG takes 8-bit images, as VPR-Bench's files are
            images = np.clip(np.rint(np.asarray(images) * 255.0), 0, 255).astype(np.uint8)
        return np.stack([hog.compute(cv2.resize(image, (size, size))).ravel() for image in images]).astype(np.float32)

    def _save_state(self, directory: Path) -> None:
        """Nothing is learned; learner.json is the whole model."""

    def _load_state(self, directory: Path) -> None:
        """Nothing is learned; learner.json is the whole model."""
