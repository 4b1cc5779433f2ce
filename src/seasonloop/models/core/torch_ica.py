"""What the torch ICA solvers share: centring and whitening, and the fitted model (mean,
whitening, unmixing) as numpy arrays.

An ICA fit here is: centre; whiten to the top-k principal axes (float64 eigen-decomposition of the
float32 D x D covariance, or an SVD of the data); find an orthogonal unmixing W of the whitened data
z (the solver: FastICA's fixed point in fastica.py, Picard-O's L-BFGS in picard.py); scale each
source to unit variance, as scikit-learn's whiten="unit-variance". Both solvers start from the
matrix scikit-learn draws for the same seed and optimise the same contrast, sum_i E[G(w_i z)]
(G = log cosh for fun "logcosh"), over orthogonal W.

The stationarity measure every solver reports: seasonloop.models.core.ica_stationarity.
"""

from __future__ import annotations

import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator
from typing import ClassVar

import numpy as np
import torch

from seasonloop.models.core.ica_densities import NONLINEARITIES
from seasonloop.models.core.ica_stationarity import relative_gradient

# Rows per block when centring and projecting, so no centred copy of the whole data is made.
BLOCK_ROWS = 8192
STORED_RETRIES = 3  # times a solver goes on when its iterate met tol and the stored model did not


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
Whitening = Callable[["TorchICA", np.ndarray, torch.Tensor], tuple[torch.Tensor, torch.Tensor, torch.Tensor]]


def _eigh_axes(ica: TorchICA, data: np.ndarray, mean: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    n_samples, n_features = data.shape
    # D x D covariance, accumulated block by block: far cheaper than an SVD when n >> D.
    covariance = torch.zeros((n_features, n_features), dtype=torch.float32, device=ica.device)
    for block in ica._blocks(data, mean):
        covariance.addmm_(block.T, block)
    # The eigen-decomposition in float64: in float32 the whitened data is visibly not white
    # (max |covariance - I| 1.4e-3 on 256 components, 6e-7 in float64), and both solvers assume
    # unit covariance. The covariance itself can stay float32, and D x D costs far less than the
    # iterations.
    computed, axes = torch.linalg.eigh((covariance / n_samples).double())
    computed, axes = computed.flip(0), axes.flip(1)  # descending
    return computed, axes, computed


def _svd_axes(ica: TorchICA, data: np.ndarray, mean: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    _, computed, axes_t = torch.linalg.svd(torch.cat(list(ica._blocks(data, mean))), full_matrices=False)
    return computed, axes_t.T, computed**2 / data.shape[0]


WHITEN_SOLVERS: dict[str, Whitening] = {"eigh": _eigh_axes, "svd": _svd_axes}

# the iterations' arithmetic (ica.precision); whitening and the saved model are float32 either way
PRECISIONS = {"float32": torch.float32, "float64": torch.float64}
STATE_KEYS = ("mean", "whitening", "unmixing", "n_iter", "converged", "criterion", "gradient")


class TorchICA(ABC):
    """ICA in torch on `device` (CPU or CUDA), whitening in float32 and the iterations in
    `precision` (float32 or float64); every setting explicit (params.yaml's ica section holds the
    values). A subclass sets `algorithm` and `criterion_name` (what its own stopping test measures)
    and implements `_rotate`.

    After `fit`: mean_ (D,), whitening_ (k, D) in float32, unmixing_ (k, k) scaled so the training
    sources have unit variance and components_ = unmixing_ @ whitening_, both in the iterations'
    precision, n_iter_, converged_ (the solver's own test met within max_iter), criterion_ (its
    last value), gradient_ (the stationarity measure every solver reports, ica_stationarity's
    relative_gradient, of the sources the stored model gives the training data) and trace_ (seconds
    since fit began, whitening included, and the gradient at each iteration's start). On the CPU a
    fit is deterministic for a seed (at a given torch thread count)."""

    algorithm: ClassVar[str]
    criterion_name: ClassVar[str]

    def __init__(
        self,
        n_components: int,
        max_iter: int,
        tol: float,
        seed: int,
        fun: str,
        whiten_solver: str,
        device: str | torch.device,
        precision: str,
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
        if precision not in PRECISIONS:
            raise ValueError(f"precision must be one of {', '.join(PRECISIONS)}, got {precision!r}")
        self.n_components = int(n_components)
        self.max_iter = int(max_iter)
        self.tol = float(tol)
        self.seed = int(seed)
        self.fun = fun
        self.whiten_solver = whiten_solver
        self.device = torch.device(device)
        self.precision = precision
        self.dtype = PRECISIONS[precision]
        self.mean_: np.ndarray | None = None
        self.whitening_: np.ndarray | None = None
        self.unmixing_: np.ndarray | None = None
        self.components_: np.ndarray | None = None
        self.n_iter_: int | None = None
        self.converged_: bool | None = None
        self.criterion_: float | None = None
        self.gradient_: float | None = None

    # ----- fitting -----
    def fit(self, data: np.ndarray, progress: bool = False) -> TorchICA:
        """Learn from (n_samples, n_features) data (converted to float32); `progress` shows a bar
        over the iterations (seconds each at the study's scale on a CPU)."""
        data = np.asarray(data)
        if data.ndim != 2 or not np.issubdtype(data.dtype, np.number):
            raise ValueError(f"data must be a numeric (n_samples, n_features) array, got shape {data.shape}")
        n_samples, n_features = data.shape
        if self.n_components > min(n_samples, n_features):
            raise ValueError(
                f"n_components = {self.n_components} exceeds min(n_samples, n_features) = {min(n_samples, n_features)}"
            )
        # (seconds since fit began, relative gradient) at the start of every iteration, for
        # benchmarks/speed/bench_ica.py's time to reach a gradient and stay below it
        self.started_ = time.perf_counter()
        self.trace_: list[tuple[float, float]] = []
        data = np.ascontiguousarray(data, dtype=np.float32)
        if not np.isfinite(data).all():
            raise ValueError("data contains NaN or infinite values")
        mean = torch.from_numpy(data.mean(axis=0, dtype=np.float64).astype(np.float32)).to(self.device)
        whitening = self._whitening(data, mean)
        whitened = self._project(data, mean, whitening).to(self.dtype)  # (k, n), unit covariance
        unmixing = self._rotate(whitened, self._initial_unmixing(), progress, self.tol, self.max_iter)
        self.mean_ = mean.cpu().numpy()
        self.whitening_ = whitening.cpu().numpy()
        self._store(unmixing, whitened, data)
        # The stored model's float32 sources can miss tol by their rounding where the iterate met it
        # (a fold of the default route's every-place run: 1.0006e-7 against 1e-7): the solver then
        # goes on from where it stopped, aiming at a tenth of its aim, within what is left of max_iter.
        aim, retries = self.tol, 0
        while self._stored_misses_tol() and retries < STORED_RETRIES:
            aim, retries, done = aim / 10, retries + 1, self.n_iter_ or 0
            unmixing = self._rotate(whitened, unmixing, progress, aim, self.max_iter - done)
            self.n_iter_ = done + (self.n_iter_ or 0)
            self._store(unmixing, whitened, data)
        return self

    def _stored_misses_tol(self) -> bool:
        """A gradient solver's iterate met tol, the stored model did not, and iterations are left."""
        gradient, n_iter = self.gradient_, self.n_iter_
        return (
            self.criterion_name == "gradient"
            and bool(self.converged_)
            and gradient is not None
            and gradient >= self.tol
            and n_iter is not None
            and n_iter < self.max_iter
        )

    def _store(self, unmixing: torch.Tensor, whitened: torch.Tensor, data: np.ndarray) -> None:
        """The model of the orthogonal `unmixing`, each source scaled to unit variance (scikit-learn's
        whiten="unit-variance"), and gradient_, the stationarity of the sources it gives `data`."""
        # kept in the iterations' precision: rounded to float32, a converged float64 unmixing of 512
        # components gave a stored model's gradient of 1.8e-7 against the solver's 9.4e-8 (tol 1e-7)
        scaled = unmixing / (unmixing @ whitened).std(dim=1, correction=0)[:, None]
        self.unmixing_ = scaled.cpu().numpy()
        self._set_components()
        # judged on the model as stored and as it describes images (float32 sources), not on the
        # solver's own iterate
        self.gradient_ = relative_gradient(
            np.concatenate(
                [self.transform(data[start : start + BLOCK_ROWS]) for start in range(0, len(data), BLOCK_ROWS)]
            ),
            self.fun,
        )

    def _blocks(
        self, data: np.ndarray, mean: torch.Tensor, dtype: torch.dtype = torch.float32
    ) -> Iterator[torch.Tensor]:
        """Centred blocks of rows of (float32) data, in `dtype`, on the device."""
        for start in range(0, len(data), BLOCK_ROWS):
            yield torch.from_numpy(data[start : start + BLOCK_ROWS]).to(self.device, dtype) - mean.to(dtype)

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
        """(k, n) whitened data, in the iterations' precision: in float64 centred and projected as
        `transform` computes a stored model's sources, so that the gradient the solver reaches is
        the stored model's."""
        whitening = whitening.to(self.dtype)
        return torch.cat([whitening @ block.T for block in self._blocks(data, mean, self.dtype)], dim=1)

    def _initial_unmixing(self) -> torch.Tensor:
        """scikit-learn's (and python-picard's) initial matrix for `seed`, made orthogonal."""
        initial = np.random.RandomState(self.seed).normal(size=(self.n_components, self.n_components))
        return symmetric_decorrelation(torch.from_numpy(initial).to(self.device, self.dtype))

    @abstractmethod
    def _rotate(
        self, whitened: torch.Tensor, unmixing: torch.Tensor, progress: bool, tol: float, max_iter: int
    ) -> torch.Tensor:
        """The orthogonal (k, k) unmixing of (k, n) whitened data, from `unmixing`, its own test
        below `tol` within `max_iter` iterations; sets n_iter_, converged_ and criterion_."""

    # ----- using a fitted model -----
    def _set_components(self) -> None:
        # numpy, so a model rebuilt from its arrays gives bit-identical components; in the unmixing's
        # precision (float64 when the iterations were)
        assert self.unmixing_ is not None and self.whitening_ is not None
        whitening = self.whitening_.astype(self.unmixing_.dtype)
        self.components_ = np.ascontiguousarray(self.unmixing_ @ whitening, dtype=self.unmixing_.dtype)

    def transform(self, data: np.ndarray) -> np.ndarray:
        """(n, D) data -> (n, k) float32 sources: (data - mean_) @ components_.T, computed in float64
        (cheap here) so that another CPU's BLAS kernels, which round float32 products differently,
        give the same float32 sources."""
        if self.components_ is None or self.mean_ is None:
            raise RuntimeError(f"{type(self).__name__}: call fit() (or load_arrays) before transform()")
        data = np.asarray(data, dtype=np.float32)
        if data.ndim != 2 or data.shape[1] != self.components_.shape[1]:
            raise ValueError(f"data must have shape (n, {self.components_.shape[1]}), got {data.shape}")
        centred = data.astype(np.float64) - self.mean_.astype(np.float64)
        return (centred @ self.components_.T.astype(np.float64)).astype(np.float32)

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The fitted state as plain numpy arrays (for numpy.savez)."""
        if self.components_ is None:
            raise RuntimeError(f"{type(self).__name__}: call fit() before to_arrays()")
        assert self.mean_ is not None and self.whitening_ is not None and self.unmixing_ is not None
        return {
            "mean": self.mean_,
            "whitening": self.whitening_,
            "unmixing": self.unmixing_,
            "n_iter": np.array(self.n_iter_),
            "converged": np.array(self.converged_),
            "criterion": np.array(self.criterion_),
            "gradient": np.array(self.gradient_),
        }

    def load_arrays(self, arrays: dict[str, np.ndarray]) -> TorchICA:
        """Restore the state written by `to_arrays`; returns self."""
        missing = [key for key in STATE_KEYS if key not in arrays]
        if missing:
            raise ValueError(f"saved ICA state lacks array '{missing[0]}'")
        whitening, unmixing = np.asarray(arrays["whitening"]), np.asarray(arrays["unmixing"])
        if whitening.shape[0] != self.n_components or unmixing.shape != (self.n_components,) * 2:
            raise ValueError(
                f"saved ICA arrays (whitening {whitening.shape}, unmixing {unmixing.shape}) do not "
                f"match n_components = {self.n_components}"
            )
        self.mean_ = np.asarray(arrays["mean"], dtype=np.float32)
        self.whitening_ = whitening.astype(np.float32)
        self.unmixing_ = unmixing.astype(np.float64 if unmixing.dtype == np.float64 else np.float32)
        self.n_iter_ = int(arrays["n_iter"])
        self.converged_ = bool(arrays["converged"])
        self.criterion_ = float(arrays["criterion"])
        self.gradient_ = float(arrays["gradient"])
        self._set_components()
        return self
