"""Whitened PCA: the top principal components scaled to unit variance, global ICA without its rotation.

FastICA centres and whitens the data (the top-k principal axes, each scaled to unit variance), then
learns an unmixing matrix that is orthogonal in that whitened space. An orthogonal map changes no
cosine or Euclidean distance, so under those metrics ICA with k components and this learner with
n_discard 0 and n_keep k match images identically (tests/test_models.py checks it); under L1
(`evaluate.metric: cityblock`) the rotation, i.e. independence, can matter.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from seasonloop.models.core.learner import EpochCallback, select_training_subset
from seasonloop.models.core.projection import PRINCIPAL_COMPONENT_PARAMS, PrincipalComponentLearner
from seasonloop.params.checks import integer

# A kept component below this many roundings (of the solver's float type: float64, see
# core/projection.py) of the scale its solver works at cannot be told from zero: scaling it to unit
# variance would blow up rounding noise.
RESOLVED_ROUNDINGS = 10


class WhitenedPCALearner(PrincipalComponentLearner):
    """Descriptor = projections on principal components [n_discard, n_discard + n_keep), each divided
    by its standard deviation on the training images (population, as FastICA's whitening)."""

    name = "pca_whiten"
    TINY_RUN = {"n_keep": 16, "svd_solver": "arpack"}  # as pca's
    PARAMS = {**PRINCIPAL_COMPONENT_PARAMS, "max_train_images": integer(0)}

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        # The same seeded subset as ICA's max_train_images, so both can see the same images.
        subset, subset_info = select_training_subset(images, self.params["max_train_images"], self.seed)
        info = super()._fit(subset, progress, on_epoch)
        resolved = self._resolved_components()
        if self.n_components > resolved:
            raise ValueError(
                f"{self._key('n_discard')} + {self._key('n_keep')} = {self.n_components} exceeds the {resolved} "
                f"components the training images resolve with svd_solver "
                f"{self.params['svd_solver']!r} (keep fewer)"
            )
        return {**subset_info, **info}

    def _resolved_components(self) -> int:
        """How many leading components lie above rounding noise for the fitted solver."""
        assert self.estimator is not None
        tolerance = RESOLVED_ROUNDINGS * np.finfo(self.estimator.components_.dtype).eps
        variances = np.asarray(self.estimator.explained_variance_, dtype=np.float64)
        if self.params["svd_solver"] == "covariance_eigh":
            # sklearn forms the uncentred X^T X and subtracts n mean mean^T: eigenvalues carry
            # rounding of the uncentred second moment, whose largest eigenvalue is <= var_0 + |mean|^2.
            scale = variances[0] + float(np.sum(np.asarray(self.estimator.mean_, dtype=np.float64) ** 2))
            return int((variances > tolerance * scale).sum())
        # The SVD solvers centre first and resolve singular values to ~eps of the largest.
        singular = np.asarray(self.estimator.singular_values_, dtype=np.float64)
        return int((singular > tolerance * singular[0]).sum())

    @property
    def kept_std(self) -> np.ndarray:
        """Population standard deviation of each kept component on the training images (sklearn's
        explained_variance_ divides by n - 1)."""
        assert self.estimator is not None, "kept_std needs the fitted PCA"
        n_samples = self.estimator.n_samples_
        variances = np.asarray(self.estimator.explained_variance_[self.params["n_discard"] :], dtype=np.float64)
        return np.sqrt(variances * (n_samples - 1) / n_samples)

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        return super()._describe_batch(images) / self.kept_std
