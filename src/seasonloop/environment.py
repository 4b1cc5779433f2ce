"""What a result was computed with: torch's thread count, the Python and library versions.

Recorded beside every fit (metrics/fit/<learner>.json), because a timing or a float32 sum means
little without the threads and the BLAS-bearing libraries that produced it.
"""

from __future__ import annotations

import platform
from importlib.metadata import version
from typing import Any

import torch

PACKAGES = ("numpy", "scikit-learn", "torch", "opencv-python-headless")


def software_environment() -> dict[str, Any]:
    """{"torch_threads", "python", <package>: <version> for each of PACKAGES}."""
    return {
        "torch_threads": torch.get_num_threads(),
        "python": platform.python_version(),
        **{package: version(package) for package in PACKAGES},
    }


def fit_record(fit_seconds: float, n_train_images: int, train_seasons: list[str], info: dict[str, Any]) -> dict[str, Any]:
    """The JSON record of one learner's fit: its wall time, training set, the learner's own info
    (iterations, convergence, ...) and the software environment."""
    return {
        "fit_seconds": fit_seconds,
        "n_train_images": n_train_images,
        "train_seasons": train_seasons,
        "info": info,
        "environment": software_environment(),
    }
