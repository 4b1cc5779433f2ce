"""PCA baseline (Lowry & Milford): drop the first, condition-dependent components, keep the next ones."""

from __future__ import annotations

from seasonloop.models.core.projection import PrincipalComponentLearner


class PCALearner(PrincipalComponentLearner):
    """Descriptor = projections on principal components [n_discard, n_discard + n_keep): the first
    n_discard, which carry most of the change of light and season, are dropped."""

    name = "pca"
    defaults = {"n_discard": 100, "n_keep": 100, "svd_solver": "covariance_eigh"}
