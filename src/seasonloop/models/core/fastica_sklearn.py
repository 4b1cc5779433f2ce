"""scikit-learn's FastICA, fitted with its convergence recorded instead of warned: the solver of
ica.solver "sklearn" and of ica_bovw's patch ICA."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
from sklearn.decomposition import FastICA
from sklearn.exceptions import ConvergenceWarning

from seasonloop.models.core.learner import with_contiguous_arrays


def fit_fastica(
    data: np.ndarray,
    n_components: int,
    max_iter: int,
    tol: float,
    seed: int,
    algorithm: str,
    fun: str,
    whiten_solver: str,
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
