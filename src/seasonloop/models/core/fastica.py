"""FastICA in torch: the same algorithm as scikit-learn's parallel FastICA.

Centering and whitening as every torch ICA solver (seasonloop.models.core.torch_ica), then the
parallel fixed-point iteration with symmetric decorrelation, scikit-learn's convergence test
(max |abs(diag(W_new @ W.T)) - 1| < tol: its own criterion, "change") and its unit-variance
scaling of the sources, from the initial matrix scikit-learn draws for the same seed. The test
measures how far one step moves W, not how far W is from a stationary point: on image data it
can stay above tol for ever (the study's scale: 400 iterations, change ~0.1) while the relative
gradient, gradient_, says where it stopped.
"""

from __future__ import annotations

import time

import torch
from tqdm.auto import tqdm

from seasonloop.models.core.ica_densities import DENSITIES
from seasonloop.models.core.ica_stationarity import gradient_of_moments
from seasonloop.models.core.torch_ica import TorchICA, symmetric_decorrelation


class TorchFastICA(TorchICA):
    """Parallel FastICA (see TorchICA for the fitted attributes; criterion_ is the last change)."""

    algorithm = "parallel"
    criterion_name = "change"

    def _rotate(
        self, whitened: torch.Tensor, unmixing: torch.Tensor, progress: bool, tol: float, max_iter: int
    ) -> torch.Tensor:
        """The parallel fixed-point iteration from `unmixing`."""
        score = DENSITIES[self.fun].score
        n_samples = whitened.shape[1]
        self.converged_ = False
        bar = tqdm(total=max_iter, desc="FastICA iterations", unit="it", disable=not progress)
        for iteration in range(1, max_iter + 1):  # noqa: B007 (its last value is n_iter_)
            squashed, mean_derivative = score(unmixing @ whitened)
            expectation = squashed @ whitened.T / n_samples  # E[g(y) z^T]
            del squashed
            # the trace's gradient costs a k x k product: E[g(y) y^T] = E[g(y) z^T] W^T
            gradient = gradient_of_moments(expectation @ unmixing.T, mean_derivative)
            self.trace_.append((time.perf_counter() - self.started_, float(gradient.abs().max())))
            updated = symmetric_decorrelation(expectation - mean_derivative[:, None] * unmixing)
            change = float(((updated * unmixing).sum(dim=1).abs() - 1.0).abs().max())
            unmixing = updated
            bar.update()
            bar.set_postfix(change=f"{change:.2g}", tol=f"{tol:.2g}", refresh=False)
            if change < tol:
                self.converged_ = True
                break
        bar.close()
        self.n_iter_ = iteration
        self.criterion_ = change
        return unmixing
