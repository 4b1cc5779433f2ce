"""FastICA in torch: the same algorithm as scikit-learn's parallel FastICA, faster at the study's scale.

Centering, whitening (float64 eigen-decomposition of the float32 D x D covariance, or an SVD of the
data), then the parallel fixed-point iteration with symmetric decorrelation, scikit-learn's
convergence test (max |abs(diag(W_new @ W.T)) - 1| < tol) and its unit-variance scaling of the
sources. Arithmetic is float32 on `device` (CPU or CUDA) except that eigen-decomposition; the initial unmixing matrix is drawn exactly as scikit-learn
draws it for the same seed, so both start from the same point. On the CPU a fit is deterministic
for a seed (at a given torch thread count).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np
import torch
from tqdm.auto import tqdm

NONLINEARITIES = ("logcosh", "exp", "cube")
# Rows per block when centring and projecting, so no centred copy of the whole data is made.
BLOCK_ROWS = 8192


def _logcosh(projections: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    squashed = torch.tanh(projections)
    return squashed, 1.0 - (squashed * squashed).mean(dim=1)


def _exp(projections: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    squared = projections * projections
    gaussian = torch.exp(-0.5 * squared)
    return projections * gaussian, ((1.0 - squared) * gaussian).mean(dim=1)


def _cube(projections: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    squared = projections * projections
    return squared * projections, 3.0 * squared.mean(dim=1)


# g(W X) and the sample mean of g'(W X) per component, as in scikit-learn (alpha = 1).
_NONLINEARITY: dict[str, Callable[[torch.Tensor], tuple[torch.Tensor, torch.Tensor]]] = {
    "logcosh": _logcosh,
    "exp": _exp,
    "cube": _cube,
}


def symmetric_decorrelation(unmixing: torch.Tensor) -> torch.Tensor:
    """W <- (W W^T)^(-1/2) W, the nearest orthogonal matrix to W."""
    eigenvalues, eigenvectors = torch.linalg.eigh(unmixing @ unmixing.T)
    # Rounding can give tiny negative eigenvalues; clip as scikit-learn does.
    eigenvalues = eigenvalues.clamp_min(torch.finfo(unmixing.dtype).tiny)
    return (eigenvectors * eigenvalues.rsqrt()) @ eigenvectors.T @ unmixing


def _fix_signs(basis: torch.Tensor) -> torch.Tensor:
    """Make the first entry of each column non-negative (eigenvectors are defined up to sign), as
    scikit-learn does, so results do not depend on the LAPACK / cuSOLVER sign choice."""
    signs = torch.sign(basis[0])
    return basis * torch.where(signs == 0, torch.ones_like(signs), signs)


# A whitening solver: (estimator, data, mean) -> (the values it computed, descending; the
# principal axes as columns, in that order; the data's variance along each). A new solver is one
# function plus one WHITEN_SOLVERS line.
Whitening = Callable[["TorchFastICA", np.ndarray, torch.Tensor], tuple[torch.Tensor, torch.Tensor, torch.Tensor]]


def _eigh_axes(
    ica: TorchFastICA, data: np.ndarray, mean: torch.Tensor
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    n_samples, n_features = data.shape
    # D x D covariance, accumulated block by block: far cheaper than an SVD when n >> D.
    covariance = torch.zeros((n_features, n_features), dtype=torch.float32, device=ica.device)
    for block in ica._blocks(data, mean):
        covariance.addmm_(block.T, block)
    # The eigen-decomposition in float64: in float32 the whitened data is visibly not white
    # (max |covariance - I| 1.4e-3 on benchmarks/bench_ica.py's 256 components, 6e-7 in
    # float64), and FastICA's symmetric decorrelation assumes unit covariance: the iteration
    # then wanders (change ~0.07 after 400 iterations) where scikit-learn's converges. The
    # covariance itself can stay float32, and D x D costs far less than the iterations.
    computed, axes = torch.linalg.eigh((covariance / n_samples).double())
    computed, axes = computed.flip(0), axes.flip(1)  # descending
    return computed, axes, computed


def _svd_axes(
    ica: TorchFastICA, data: np.ndarray, mean: torch.Tensor
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    _, computed, axes_t = torch.linalg.svd(torch.cat(list(ica._blocks(data, mean))), full_matrices=False)
    return computed, axes_t.T, computed**2 / data.shape[0]


WHITEN_SOLVERS: dict[str, Whitening] = {"eigh": _eigh_axes, "svd": _svd_axes}


class TorchFastICA:
    """Parallel FastICA; after `fit`: mean_ (D,), whitening_ (k, D), unmixing_ (k, k) scaled so the
    training sources have unit variance, components_ = unmixing_ @ whitening_, n_iter_, converged_
    and last_change_ (the last change measured by the convergence test)."""

    def __init__(
        self,
        n_components: int,
        max_iter: int = 200,
        tol: float = 1e-4,
        seed: int = 0,
        fun: str = "logcosh",
        whiten_solver: str = "eigh",
        device: str | torch.device = "cpu",
    ):
        if isinstance(n_components, bool) or not isinstance(n_components, (int, np.integer)) or n_components < 1:
            raise ValueError(f"n_components must be an integer >= 1, got {n_components!r}")
        if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 1:
            raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
        if not tol > 0:
            raise ValueError(f"tol must be a positive number, got {tol!r}")
        if fun not in NONLINEARITIES:
            raise ValueError(f"fun must be one of {', '.join(NONLINEARITIES)}, got {fun!r}")
        if whiten_solver not in WHITEN_SOLVERS:
            raise ValueError(f"whiten_solver must be one of {', '.join(WHITEN_SOLVERS)}, got {whiten_solver!r}")
        self.n_components = int(n_components)
        self.max_iter = int(max_iter)
        self.tol = float(tol)
        self.seed = int(seed)
        self.fun = fun
        self.whiten_solver = whiten_solver
        self.device = torch.device(device)
        self.mean_: np.ndarray | None = None
        self.whitening_: np.ndarray | None = None
        self.unmixing_: np.ndarray | None = None
        self.components_: np.ndarray | None = None
        self.n_iter_: int | None = None
        self.converged_: bool | None = None
        self.last_change_: float | None = None

    # ----- fitting -----
    def fit(self, data: np.ndarray, progress: bool = False) -> TorchFastICA:
        """Learn from (n_samples, n_features) data (converted to float32); `progress` shows a bar
        over the fixed-point iterations (minutes each at the study's scale on a CPU)."""
        data = np.asarray(data)
        if data.ndim != 2 or not np.issubdtype(data.dtype, np.number):
            raise ValueError(f"data must be a numeric (n_samples, n_features) array, got shape {data.shape}")
        n_samples, n_features = data.shape
        if self.n_components > min(n_samples, n_features):
            raise ValueError(
                f"n_components = {self.n_components} exceeds min(n_samples, n_features) = {min(n_samples, n_features)}"
            )
        data = np.ascontiguousarray(data, dtype=np.float32)
        if not np.isfinite(data).all():
            raise ValueError("data contains NaN or infinite values")
        mean = torch.from_numpy(data.mean(axis=0, dtype=np.float64).astype(np.float32)).to(self.device)
        whitening = self._whitening(data, mean)
        whitened = self._project(data, mean, whitening)  # (k, n), unit covariance
        unmixing = self._iterate(whitened, progress)
        # scikit-learn's whiten="unit-variance": scale each source to unit standard deviation.
        source_std = (unmixing @ whitened).std(dim=1, correction=0)
        unmixing = unmixing / source_std[:, None]
        self.mean_ = mean.cpu().numpy()
        self.whitening_ = whitening.cpu().numpy()
        self.unmixing_ = unmixing.cpu().numpy()
        self._set_components()
        return self

    def _blocks(self, data: np.ndarray, mean: torch.Tensor) -> Iterator[torch.Tensor]:
        """Centred float32 blocks of rows of data, on the device."""
        for start in range(0, len(data), BLOCK_ROWS):
            yield torch.from_numpy(data[start : start + BLOCK_ROWS]).to(self.device) - mean

    def _whitening(self, data: np.ndarray, mean: torch.Tensor) -> torch.Tensor:
        """(k, D) matrix K with K @ centred.T of unit covariance, from the top-k principal axes."""
        computed, axes, variances = WHITEN_SOLVERS[self.whiten_solver](self, data, mean)
        # A value the solver computed (eigenvalue or singular value) within 10 float32 roundings of
        # the largest cannot be told from zero (the covariance or data is float32): whitening its
        # direction would blow up rounding noise.
        resolved = int((computed > computed[0] * 10 * torch.finfo(torch.float32).eps).sum())
        if self.n_components > resolved:
            hint = " or whiten_solver 'svd'" if self.whiten_solver == "eigh" else ""
            raise ValueError(
                f"n_components = {self.n_components} exceeds the {resolved} directions the centred data "
                f"resolves with whiten_solver {self.whiten_solver!r} in float32 (use fewer components{hint})"
            )
        axes = _fix_signs(axes[:, : self.n_components])
        return (axes / variances[: self.n_components].sqrt()).T.to(torch.float32).contiguous()

    def _project(self, data: np.ndarray, mean: torch.Tensor, whitening: torch.Tensor) -> torch.Tensor:
        """(k, n) whitened data."""
        return torch.cat([whitening @ block.T for block in self._blocks(data, mean)], dim=1)

    def _iterate(self, whitened: torch.Tensor, progress: bool = False) -> torch.Tensor:
        """The parallel fixed-point iteration from scikit-learn's initial matrix for `seed`."""
        nonlinearity = _NONLINEARITY[self.fun]
        n_samples = whitened.shape[1]
        initial = np.random.RandomState(self.seed).normal(size=(self.n_components, self.n_components))
        unmixing = symmetric_decorrelation(torch.from_numpy(initial.astype(np.float32)).to(self.device))
        self.converged_ = False
        bar = tqdm(total=self.max_iter, desc="FastICA iterations", unit="it", disable=not progress)
        for iteration in range(1, self.max_iter + 1):  # noqa: B007 (its last value is n_iter_)
            squashed, mean_derivative = nonlinearity(unmixing @ whitened)
            updated = symmetric_decorrelation(squashed @ whitened.T / n_samples - mean_derivative[:, None] * unmixing)
            change = float(((updated * unmixing).sum(dim=1).abs() - 1.0).abs().max())
            unmixing = updated
            bar.update()
            bar.set_postfix(change=f"{change:.2g}", tol=f"{self.tol:.2g}", refresh=False)
            if change < self.tol:
                self.converged_ = True
                break
        bar.close()
        self.n_iter_ = iteration
        self.last_change_ = change
        return unmixing

    # ----- using a fitted model -----
    def _set_components(self) -> None:
        # numpy, so a model rebuilt from its arrays gives bit-identical components.
        assert self.unmixing_ is not None and self.whitening_ is not None
        self.components_ = np.ascontiguousarray(self.unmixing_ @ self.whitening_, dtype=np.float32)

    def transform(self, data: np.ndarray) -> np.ndarray:
        """(n, D) data -> (n, k) float32 sources: (data - mean_) @ components_.T."""
        if self.components_ is None:
            raise RuntimeError("TorchFastICA: call fit() (or load_arrays) before transform()")
        data = np.asarray(data, dtype=np.float32)
        if data.ndim != 2 or data.shape[1] != self.components_.shape[1]:
            raise ValueError(f"data must have shape (n, {self.components_.shape[1]}), got {data.shape}")
        return (data - self.mean_) @ self.components_.T

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The fitted state as plain numpy arrays (for numpy.savez)."""
        if self.components_ is None:
            raise RuntimeError("TorchFastICA: call fit() before to_arrays()")
        assert self.mean_ is not None and self.whitening_ is not None and self.unmixing_ is not None
        return {
            "mean": self.mean_,
            "whitening": self.whitening_,
            "unmixing": self.unmixing_,
            "n_iter": np.array(self.n_iter_),
            "converged": np.array(self.converged_),
            "last_change": np.array(self.last_change_),
        }

    def load_arrays(self, arrays: dict[str, np.ndarray]) -> TorchFastICA:
        """Restore the state written by `to_arrays`; returns self."""
        missing = sorted({"mean", "whitening", "unmixing", "n_iter", "converged", "last_change"} - set(arrays))
        if missing:
            raise ValueError(f"saved FastICA state lacks array '{missing[0]}'")
        whitening, unmixing = np.asarray(arrays["whitening"]), np.asarray(arrays["unmixing"])
        if whitening.shape[0] != self.n_components or unmixing.shape != (self.n_components,) * 2:
            raise ValueError(
                f"saved FastICA arrays (whitening {whitening.shape}, unmixing {unmixing.shape}) do not "
                f"match n_components = {self.n_components}"
            )
        self.mean_ = np.asarray(arrays["mean"], dtype=np.float32)
        self.whitening_ = whitening.astype(np.float32)
        self.unmixing_ = unmixing.astype(np.float32)
        self.n_iter_ = int(arrays["n_iter"])
        self.converged_ = bool(arrays["converged"])
        self.last_change_ = float(arrays["last_change"])
        self._set_components()
        return self


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
