"""PCA baseline (Lowry & Milford): drop the first, condition-dependent components, keep the next ones."""

from __future__ import annotations

from seasonloop.models.core.projection import PRINCIPAL_COMPONENT_PARAMS, PrincipalComponentLearner


class PCALearner(PrincipalComponentLearner):
    """Descriptor = projections on principal components [n_discard, n_discard + n_keep): the first
    n_discard, which carry most of the change of light and season, are dropped."""

    name = "pca"
    figures = ("pca_projection",)  # the study's Figure 2
    # arpack: exact to its tolerance, and ~1.2 s less CPU a fit than covariance_eigh, whose
    # eigendecomposition of the pixel covariance costs the same for 1,170 images as for 100,000
    TINY_RUN = {"n_discard": 3, "n_keep": 20, "svd_solver": "arpack"}
    PARAMS = PRINCIPAL_COMPONENT_PARAMS
