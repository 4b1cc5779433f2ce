"""PCA baseline (Lowry & Milford): drop the first, condition-dependent components, keep the next ones."""

from __future__ import annotations

from seasonloop.models.core.projection import PRINCIPAL_COMPONENT_PARAMS, PrincipalComponentLearner


class PCALearner(PrincipalComponentLearner):
    """Descriptor = projections on principal components [n_discard, n_discard + n_keep): the first
    n_discard, which carry most of the change of light and season, are dropped."""

    name = "pca"
    PARAMS = PRINCIPAL_COMPONENT_PARAMS
