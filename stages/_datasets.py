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


def in_data_order(params: dict[str, Any], seasons: list[str]) -> list[str]:
    """`seasons` in data.seasons order: a training set is a set of seasons, so the same seasons
    listed in another order give the same images in the same order (and the same fit)."""
    return [season for season in param(params, "data.seasons") if season in seasons]


def training_images(params: dict[str, Any], seasons: list[str], fold: int = -1, folds: int = 1) -> np.ndarray:
    """The concatenated training images of `seasons` (in data.seasons order) of fold `fold` of
    `folds` (-1: the study's split), augmented or not as train.augmented says."""
    augmented = datasets.fold_dir(AUGMENTED, fold, folds) if bool(param(params, "train.augmented")) else None
    return datasets.training_images(datasets.fold_dir(SPLIT, fold, folds), augmented, in_data_order(params, seasons))


def training_places(params: dict[str, Any], seasons: list[str], fold: int = -1, folds: int = 1) -> np.ndarray:
    """The place id of every image that training_images returns."""
    copies = int(param(params, "augment.copies")) if bool(param(params, "train.augmented")) else 0
    return datasets.training_places(datasets.fold_dir(SPLIT, fold, folds), in_data_order(params, seasons), copies)


def training_traverses(params: dict[str, Any], seasons: list[str], fold: int = -1, folds: int = 1) -> np.ndarray:
    """The traverse (index in `seasons`, in data.seasons order) of every image that training_images
    returns."""
    copies = int(param(params, "augment.copies")) if bool(param(params, "train.augmented")) else 0
    ordered = in_data_order(params, seasons)
    return datasets.training_traverses(datasets.fold_dir(SPLIT, fold, folds), ordered, copies)


def test_images(seasons: list[str]) -> dict[str, np.ndarray]:
    """season -> its (N_test, H, W) test images."""
    return datasets.test_images(SPLIT, seasons)
