"""How far an ICA fit is from its goal: the stationarity measure every solver reports, and, for
data mixed from known sources, the Amari distance to the true mixing.

The stationarity measure (`relative_gradient`): with y = W z and g = G', the relative gradient of
that contrast on the orthogonal group is the skew-symmetric part of diag(s) E[g(y) y^T], where
s_i = sign(E[g'(y_i)] - E[g(y_i) y_i]) says whether source i is treated as super- or sub-Gaussian.
It is zero exactly at FastICA's fixed points (the symmetric decorrelation leaves W unchanged up to
signs iff diag(s) E[g(y) y^T] is symmetric) and it is the quantity Picard-O drives below its tol
(Ablin, Cardoso and Gramfort 2018), so one number, max |entry|, compares every solver.
"""

from __future__ import annotations

import numpy as np
import torch

from seasonloop.models.core.ica_densities import DENSITIES


def gradient_of_moments(moments: torch.Tensor, mean_derivative: torch.Tensor) -> torch.Tensor:
    """The (k, k) skew-symmetric relative gradient from E[g(y) y^T] (k, k) and the row means of
    g'(y) (k,), for sources y of unit variance (module doc)."""
    signs = torch.sign(mean_derivative - torch.diagonal(moments))
    moments = moments * signs[:, None]
    return (moments - moments.T) / 2


def gradient_of_sources(sources: torch.Tensor, fun: str) -> torch.Tensor:
    """The (k, k) skew-symmetric relative gradient of (k, n) sources of unit variance (module doc)."""
    score, mean_derivative = DENSITIES[fun].score(sources)
    moments = score @ sources.T / sources.shape[1]
    del score
    return gradient_of_moments(moments, mean_derivative)


def relative_gradient(sources: np.ndarray | torch.Tensor, fun: str = "logcosh") -> float:
    """max |entry| of the relative gradient (module doc) of (n, k) sources, each standardised to
    zero mean and unit variance first, so that it compares solvers that scale sources differently:
    0 at a stationary point of the ICA contrast; Picard-O's own stopping criterion."""
    values = torch.as_tensor(np.asarray(sources) if isinstance(sources, np.ndarray) else sources)
    values = values.to(torch.float64).T
    values = (values - values.mean(dim=1, keepdim=True)) / values.std(dim=1, correction=0, keepdim=True)
    return float(gradient_of_sources(values, fun).abs().max())


def amari_distance(estimated_unmixing: np.ndarray, true_mixing: np.ndarray) -> float:
    """Amari distance of P = W A (0 iff P is a scaled permutation), normalised to [0, 1].

    W is the estimated (k, D) unmixing, A the true (D, k) mixing matrix.
    """
    product = np.abs(np.asarray(estimated_unmixing, dtype=np.float64) @ np.asarray(true_mixing, dtype=np.float64))
    if product.ndim != 2 or product.shape[0] != product.shape[1]:
        raise ValueError(f"unmixing @ mixing must be square, got shape {product.shape}")
    k = product.shape[0]
    rows = (product.sum(axis=1) / product.max(axis=1) - 1).sum()
    cols = (product.sum(axis=0) / product.max(axis=0) - 1).sum()
    return float((rows + cols) / (2 * k * (k - 1)))
