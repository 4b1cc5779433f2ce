"""What every stage script shares: reading params.yaml, the pipeline's data folders, and turning bad
input into one clear line.

Stage scripts are thin: they read params, call the seasonloop library and write their outputs.
The helpers here only bind params and pipeline paths to library calls (seasonloop.datasets).
"""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from seasonloop import datasets
from seasonloop.config import check_params, check_seasons

PARAMS_FILE = Path("params.yaml")
# the pipeline's split and augmented training set (their layout: seasonloop.datasets)
SPLIT = Path("data/split")
AUGMENTED = Path("data/augmented")


def load_params(*keys: str, path: Path = PARAMS_FILE) -> dict[str, Any]:
    """params.yaml, with `keys` (the sections or dotted keys the stage reads) checked before any work."""
    if not path.is_file():
        raise FileNotFoundError(f"{path}: parameter file not found (run from the repository root)")
    params = yaml.safe_load(path.read_text()) or {}
    if not isinstance(params, dict):
        raise ValueError(f"{path}: expected a mapping of sections")
    check_params(params, keys)
    return params


def param(params: dict[str, Any], dotted_key: str) -> Any:
    """params["a"]["b"] for "a.b", or a ValueError that names the missing key."""
    value: Any = params
    for part in dotted_key.split("."):
        if not isinstance(value, dict) or part not in value:
            raise ValueError(f"params.yaml: missing key '{dotted_key}'")
        value = value[part]
    return value


def data_seasons(params: dict[str, Any]) -> list[str]:
    return check_seasons(param(params, "data.seasons"), "data.seasons")


def train_seasons(params: dict[str, Any]) -> list[str]:
    """train.seasons, each of which must be among the data's seasons."""
    return check_seasons(param(params, "train.seasons"), "train.seasons", allowed=data_seasons(params))


def training_images(params: dict[str, Any], seasons: list[str]) -> np.ndarray:
    """The concatenated training images of `seasons`, augmented or not as train.augmented says."""
    augmented = AUGMENTED if bool(param(params, "train.augmented")) else None
    return datasets.training_images(SPLIT, augmented, seasons)


def training_places(params: dict[str, Any], seasons: list[str]) -> np.ndarray:
    """The place id of every image that training_images returns."""
    copies = int(param(params, "augment.copies")) if bool(param(params, "train.augmented")) else 0
    return datasets.training_places(SPLIT, seasons, copies)


def test_places() -> np.ndarray:
    """Place ids of the test images, the same for every season (rows of <season>_test.npy)."""
    return datasets.test_places(SPLIT)


def test_images(seasons: list[str]) -> dict[str, np.ndarray]:
    """season -> its (N_test, H, W) test images."""
    return datasets.test_images(SPLIT, seasons)


def stage_main(run: Callable[[], None]) -> Callable[[], None]:
    """Run a stage; expected failures (bad params, missing or corrupt input, a full disk or other
    OS error while writing) print one line, exit 1."""

    @functools.wraps(run)
    def wrapper() -> None:
        try:
            run()
        except (ValueError, OSError, RuntimeError) as error:
            print(f"error: {error}", file=sys.stderr)
            sys.exit(1)

    return wrapper
