"""Principal components of the training images, as a learner: the base of pca and pca_whiten."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from seasonloop.models.core.learner import EpochCallback, FeatureLearner, to_float, with_contiguous_arrays
from seasonloop.params.checks import integer, one_of

if TYPE_CHECKING:
    from sklearn.decomposition import PCA

ESTIMATOR_FILE = "pca.joblib"
# scikit-learn's PCA(svd_solver=...) values
SVD_SOLVERS = ("auto", "full", "covariance_eigh", "arpack", "randomized")


# the params of a learner on components [n_discard, n_discard + n_keep)
PRINCIPAL_COMPONENT_PARAMS = {"n_discard": integer(0), "n_keep": integer(1), "svd_solver": one_of(*SVD_SOLVERS)}


def to_pixels64(images: np.ndarray) -> np.ndarray:
    """(N, H, W) images -> (N, H*W) float64 pixels in [0, 1]. The principal components are computed
    and applied in float64: BLAS kernels of other CPUs (OpenBLAS picks them per CPU) sum in another
    order, and float32 rounding of X^T X then moved the components enough to change matches;
    float64 keeps those differences far below the float32 descriptors' last bit."""
    return to_float(images).reshape(len(images), -1).astype(np.float64)


class PrincipalComponentLearner(FeatureLearner):
    """Descriptor = projections on principal components [n_discard, n_discard + n_keep) of
    scikit-learn's PCA; a subclass sets `name` and `PARAMS` (PRINCIPAL_COMPONENT_PARAMS and its own)."""

    LIBRARIES = ("sklearn.decomposition", "joblib")

    def __init__(self, params: Mapping[str, Any], seed: int = 0):
        super().__init__(params, seed)
        self.estimator: PCA | None = None

    @property
    def n_components(self) -> int:
        return self.params["n_discard"] + self.params["n_keep"]

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        from sklearn.decomposition import PCA

        flat = to_pixels64(images)
        # arpack cannot compute all min(n_samples, n_features) components.
        limit = min(flat.shape) - (1 if self.params["svd_solver"] == "arpack" else 0)
        if self.n_components > limit:
            raise ValueError(
                f"{self._key('n_discard')} + {self._key('n_keep')} = {self.n_components} exceeds "
                f"{limit}, the most components {len(flat)} images of {flat.shape[1]} pixels allow "
                f"with svd_solver {self.params['svd_solver']!r}"
            )
        self.estimator = with_contiguous_arrays(
            PCA(n_components=self.n_components, svd_solver=self.params["svd_solver"], random_state=self.seed).fit(flat)
        )
        ratios = self.estimator.explained_variance_ratio_
        n_discard = self.params["n_discard"]
        return {
            "n_train_images": len(flat),
            "n_components": self.n_components,
            "explained_variance_ratio_discarded": float(ratios[:n_discard].sum()),
            "explained_variance_ratio_kept": float(ratios[n_discard:].sum()),
        }

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        assert self.estimator is not None, "describe checks that the learner is fitted"
        return self.estimator.transform(to_pixels64(images))[:, self.params["n_discard"] :]

    def reconstruct(self, images: np.ndarray, start: int, stop: int) -> np.ndarray:
        """(N, H, W) float32 images rebuilt from components [start, stop) only (plus the mean if start == 0)."""
        images = self._check_describe_input(images, "reconstruct")
        if not 0 <= start < stop <= self.n_components:
            raise ValueError(f"component range [{start}, {stop}) must satisfy 0 <= start < stop <= {self.n_components}")
        assert self.estimator is not None
        projections = self.estimator.transform(to_pixels64(images))[:, start:stop]
        rebuilt = projections @ self.estimator.components_[start:stop]
        if start == 0:
            rebuilt = rebuilt + self.estimator.mean_
        return rebuilt.reshape(images.shape).astype(np.float32)

    def _save_state(self, directory: Path) -> None:
        import joblib

        joblib.dump(self.estimator, directory / ESTIMATOR_FILE)

    def _load_state(self, directory: Path) -> None:
        import joblib

        self.estimator = joblib.load(directory / ESTIMATOR_FILE)
