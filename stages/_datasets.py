"""The pipeline's split and augmented sets, for the stages that read them: binds params and the
pipeline's folders to seasonloop.data.datasets (where their layout is described)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from _common import param
from seasonloop.data import datasets

SPLIT = Path("data/split")
AUGMENTED = Path("data/augmented")


def training_images(params: dict[str, Any], seasons: list[str]) -> np.ndarray:
    """The concatenated training images of `seasons`, augmented or not as train.augmented says."""
    augmented = AUGMENTED if bool(param(params, "train.augmented")) else None
    return datasets.training_images(SPLIT, augmented, seasons)


def training_places(params: dict[str, Any], seasons: list[str]) -> np.ndarray:
    """The place id of every image that training_images returns."""
    copies = int(param(params, "augment.copies")) if bool(param(params, "train.augmented")) else 0
    return datasets.training_places(SPLIT, seasons, copies)


def test_images(seasons: list[str]) -> dict[str, np.ndarray]:
    """season -> its (N_test, H, W) test images."""
    return datasets.test_images(SPLIT, seasons)
