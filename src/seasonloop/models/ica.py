"""Global ICA: FastICA on whole training images; descriptor = projection on the unmixing matrix."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import joblib
import numpy as np
from sklearn.decomposition import FastICA
from sklearn.exceptions import ConvergenceWarning

from seasonloop.models.base import (
    EpochCallback,
    FeatureLearner,
    select_training_subset,
    to_float,
    with_contiguous_arrays,
)

ESTIMATOR_FILE = "fastica.joblib"
ICA_ALGORITHMS = ("parallel", "deflation")
ICA_FUNCTIONS = ("logcosh", "exp", "cube")
WHITEN_SOLVERS = ("eigh", "svd")


def fit_fastica(
    data: np.ndarray,
    n_components: int,
    max_iter: int,
    tol: float,
    seed: int,
    algorithm: str = "parallel",
    fun: str = "logcosh",
    whiten_solver: str = "eigh",
) -> tuple[FastICA, dict[str, Any]]:
    """Fit sklearn FastICA (centering, unit-variance whitening, fixed-point iteration) on
    (n_samples, n_features) data.

    ConvergenceWarnings are captured into the returned convergence record instead of being
    printed; any other warning is passed on.
    """
    estimator = FastICA(
        n_components=n_components,
        algorithm=algorithm,
        whiten="unit-variance",
        fun=fun,
        max_iter=max_iter,
        tol=tol,
        whiten_solver=whiten_solver,
        random_state=seed,
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        estimator.fit(data)
    convergence_messages = []
    for warning in caught:
        if issubclass(warning.category, ConvergenceWarning):
            convergence_messages.append(str(warning.message))
        else:
            warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno)
    # sklearn warns exactly when the fixed-point iteration hits max_iter without meeting tol.
    record = {
        "n_iter": int(estimator.n_iter_),
        "max_iter": int(max_iter),
        "converged": not convergence_messages,
        "convergence_warnings": convergence_messages,
    }
    return with_contiguous_arrays(estimator), record


class ICALearner(FeatureLearner):
    """FastICA on flattened training images; descriptor = its sources (transform)."""

    name = "ica"
    defaults = {
        "n_components": 128,
        "algorithm": "parallel",
        "fun": "logcosh",
        "max_iter": 400,
        "tol": 1e-4,
        "whiten_solver": "eigh",
        "max_train_images": 0,
    }

    def __init__(self, params: Mapping[str, Any] | None = None, seed: int = 0):
        super().__init__(params, seed)
        self.estimator: FastICA | None = None

    def _validate_params(self) -> None:
        self._check_int("n_components", 1)
        self._check_choice("algorithm", ICA_ALGORITHMS)
        self._check_choice("fun", ICA_FUNCTIONS)
        self._check_int("max_iter", 1)
        self._check_positive_float("tol")
        self._check_choice("whiten_solver", WHITEN_SOLVERS)
        self._check_int("max_train_images", 0)

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        subset, subset_info = select_training_subset(images, self.params["max_train_images"], self.seed)
        flat = to_float(subset).reshape(len(subset), -1)
        limit = min(flat.shape)
        if self.params["n_components"] > limit:
            # FastICA would silently lower it; make the caller choose.
            raise ValueError(
                f"{self._key('n_components')} = {self.params['n_components']} exceeds {limit}, the most "
                f"{len(flat)} training images of {flat.shape[1]} pixels allow"
            )
        self.estimator, convergence = fit_fastica(
            flat,
            n_components=self.params["n_components"],
            max_iter=self.params["max_iter"],
            tol=self.params["tol"],
            seed=self.seed,
            algorithm=self.params["algorithm"],
            fun=self.params["fun"],
            whiten_solver=self.params["whiten_solver"],
        )
        return {**subset_info, "n_components": self.params["n_components"], **convergence}

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        return self.estimator.transform(to_float(images).reshape(len(images), -1))

    def _save_state(self, directory: Path) -> None:
        joblib.dump(self.estimator, directory / ESTIMATOR_FILE)

    def _load_state(self, directory: Path) -> None:
        self.estimator = joblib.load(directory / ESTIMATOR_FILE)
