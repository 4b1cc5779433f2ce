"""Picard-O in torch: preconditioned L-BFGS for ICA under the orthogonal constraint.

The algorithm of python-picard's `picard(ortho=True, extended=True)` (Ablin, Cardoso and Gramfort,
"Faster ICA under orthogonal constraint", ICASSP 2018; its core_picard, step for step): on the
whitened data it minimises sum_i s_i E[G(y_i)], y = W z, over orthogonal W, with s_i the sign that
makes source i super- or sub-Gaussian (the "extended" rule, as FastICA's fixed point adapts to
either); the relative gradient is the skew part of diag(s) E[g(y) y^T]
(seasonloop.models.core.ica_stationarity), preconditioned by Picard's cheap Hessian approximation
(the row means of g'), with an L-BFGS memory of `memory` steps and a backtracking line search on
W <- expm(alpha D) W. It stops when max |gradient| < tol: the stationarity measure every solver
reports, so its own criterion is the shared one. Its stationary points are FastICA's fixed
points (the paper, section 3); it reaches them where FastICA's fixed-point iteration oscillates.

Differences from python-picard, neither changing the iterates beyond rounding: float32 on
`device` (CPU or CUDA) instead of float64 numpy, with the line search's losses summed in float64
so that a decrease of 1e-8 is still seen; and the sources are recomputed from W every
`refresh_every` iterations (python-picard updates Y <- expm(alpha D) Y throughout), so that float32
rounding does not accumulate between Y and W; W is made orthogonal again at the end.
"""

from __future__ import annotations

import contextlib
import io
import re
import time
from collections import deque

import torch
from tqdm.auto import tqdm

from seasonloop.models.core.ica_densities import DENSITIES, Density
from seasonloop.models.core.ica_stationarity import gradient_of_sources
from seasonloop.models.core.torch_ica import TorchICA, symmetric_decorrelation

# python-picard's defaults
MEMORY = 7
LAMBDA_MIN = 0.01
LINE_SEARCH_TRIES = 10
REFRESH_EVERY = 50


class TorchPicard(TorchICA):
    """Picard-O (see TorchICA for the fitted attributes; criterion_ is the last gradient, max |G|).

    Two counts say why a fit is slow: sign_changes_, the iterations where an extended sign flipped
    (the loss changed, so the L-BFGS memory was dropped), and gradient_steps_, those where the
    L-BFGS direction found no decrease and a plain gradient step was taken."""

    algorithm = "picard-o"
    criterion_name = "gradient"

    def _rotate(
        self, whitened: torch.Tensor, unmixing: torch.Tensor, progress: bool, tol: float, max_iter: int
    ) -> torch.Tensor:
        density = DENSITIES[self.fun]
        n_samples = whitened.shape[1]
        sources = unmixing @ whitened
        memory: deque[tuple[torch.Tensor, torch.Tensor, float]] = deque(maxlen=MEMORY)
        signs: torch.Tensor | None = None
        loss: float | None = None
        previous_gradient = direction = None
        self.converged_ = False
        self.sign_changes_ = self.gradient_steps_ = 0
        fresh = True  # sources = W z computed from W, not updated along the way
        bar = tqdm(total=max_iter, desc="Picard-O iterations", unit="it", disable=not progress)
        for iteration in range(1, max_iter + 1):  # noqa: B007 (its last value is n_iter_)
            if iteration % REFRESH_EVERY == 0 and not fresh:
                unmixing, sources, loss = self._refresh(unmixing, whitened)
                fresh = True
            new_signs, gradient, hessian = _gradient_and_hessian(sources, density, n_samples)
            sign_change = signs is not None and bool((new_signs != signs).any())
            signs = new_signs
            gradient_norm = float(gradient.abs().max())
            self.trace_.append((time.perf_counter() - self.started_, gradient_norm))
            bar.update()
            bar.set_postfix(gradient=f"{gradient_norm:.2g}", tol=f"{tol:.2g}", refresh=False)
            if gradient_norm < tol:
                if fresh:
                    self.converged_ = True
                    break
                # confirm it on fresh sources in the next iteration
                unmixing, sources, loss = self._refresh(unmixing, whitened)
                fresh = True
                continue
            if previous_gradient is not None and direction is not None:
                change = gradient - previous_gradient
                curvature = float((direction * change).sum())
                # a pair without positive curvature (a refresh's rounding, near the optimum) would
                # make the L-BFGS matrix indefinite: skipped, the usual safeguard
                if curvature > 0:
                    memory.append((direction, change, 1.0 / curvature))
            previous_gradient = gradient
            if sign_change:  # the loss itself changed: what L-BFGS learnt of it no longer holds
                self.sign_changes_ += 1
                loss = None
                memory.clear()
            direction = _lbfgs_direction(gradient, hessian, memory)
            accepted, step = _line_search(sources, density, direction, signs, loss, LINE_SEARCH_TRIES)
            if not accepted:  # python-picard: forget the memory, take the gradient step
                self.gradient_steps_ += 1
                memory.clear()
                accepted, step = _line_search(sources, density, -gradient, signs, loss, LINE_SEARCH_TRIES)
            direction, rotation, sources, loss = step
            unmixing = rotation @ unmixing
            fresh = False
        bar.close()
        self.n_iter_ = iteration
        self.criterion_ = gradient_norm
        return unmixing

    @staticmethod
    def _refresh(unmixing: torch.Tensor, whitened: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, None]:
        """W made orthogonal again (rounding of many float32 rotations drifts it by ~1e-6), the
        sources computed afresh from it, and no loss yet."""
        unmixing = symmetric_decorrelation(unmixing.double()).to(unmixing.dtype)
        return unmixing, unmixing @ whitened, None


def _lbfgs_direction(
    gradient: torch.Tensor, hessian: torch.Tensor, memory: deque[tuple[torch.Tensor, torch.Tensor, float]]
) -> torch.Tensor:
    """The L-BFGS two-loop recursion with the Hessian approximation as the initial matrix."""
    q = gradient.clone()
    alphas = []
    for step, change, rho in reversed(memory):
        alpha = rho * float((step * q).sum())
        alphas.append(alpha)
        q -= alpha * change
    z = q / hessian
    z = (z - z.T) / 2
    for (step, change, rho), alpha in zip(memory, reversed(alphas)):
        beta = rho * float((change * z).sum())
        z += (alpha - beta) * step
    return -z


def _gradient_and_hessian(
    sources: torch.Tensor, density: Density, n_samples: int
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """(the extended signs s, the relative gradient, Picard's Hessian approximation) at `sources`."""
    score, mean_derivative = density.score(sources)
    moments = score @ sources.T / n_samples
    del score
    # the extended rule: s_i = sign(E[g'] E[y_i^2] - E[g(y_i) y_i])
    variances = (sources * sources).mean(dim=1)
    signs = torch.sign(mean_derivative * variances - torch.diagonal(moments))
    moments = moments * signs[:, None]
    mean_derivative = mean_derivative * signs
    # Picard's Hessian approximation, regularised to eigenvalues >= LAMBDA_MIN
    off_diagonal = torch.diagonal(moments)
    hessian = 0.5 * (
        mean_derivative[:, None] + mean_derivative[None, :] - off_diagonal[:, None] - off_diagonal[None, :]
    )
    return signs, (moments - moments.T) / 2, hessian.clamp_min(LAMBDA_MIN)


def _loss(sources: torch.Tensor, density: Density, signs: torch.Tensor) -> float:
    """sum_i s_i E[G(y_i)], each row's mean accumulated in float64."""
    return float((density.contrast(sources).sum(dim=1, dtype=torch.float64) * signs.double()).sum()) / sources.shape[1]


def _line_search(
    sources: torch.Tensor,
    density: Density,
    direction: torch.Tensor,
    signs: torch.Tensor,
    loss: float | None,
    tries: int,
) -> tuple[bool, tuple[torch.Tensor, torch.Tensor, torch.Tensor, float]]:
    """Backtracking from step 1: whether the loss decreased, and (the step taken, its rotation
    expm(step), the new sources, their loss); after `tries` halvings the last, smallest step is
    taken (as python-picard does)."""
    if loss is None:
        loss = _loss(sources, density, signs)
    for trial in range(tries):
        step = direction / 2.0**trial
        rotation = torch.linalg.matrix_exp(step)
        moved = rotation @ sources
        new_loss = _loss(moved, density, signs)
        if new_loss == new_loss and new_loss < loss:  # finite and lower
            return True, (step, rotation, moved, new_loss)
    return False, (step, rotation, moved, new_loss)


class LibraryPicard(TorchICA):
    """The same fit with python-picard itself (`picard(ortho=True, extended=True)`, float64 numpy on
    the CPU) in place of TorchPicard's iterations, from the same whitened data and initial matrix:
    the reference implementation, selectable as ica.solver "python_picard" and compared in
    benchmarks/speed/bench_ica.py."""

    algorithm = "picard-o"
    criterion_name = "gradient"

    def _rotate(
        self, whitened: torch.Tensor, unmixing: torch.Tensor, progress: bool, tol: float, max_iter: int
    ) -> torch.Tensor:
        import warnings

        from picard import picard
        from picard.densities import Cube, Exp, Tanh

        # python-picard's densities of the torch ones (ica_densities, alpha 1): its fun="exp" is
        # Exp(alpha=0.1), another contrast, so the objects are passed, not the names
        densities = {"logcosh": Tanh(params={"alpha": 1.0}), "exp": Exp(params={"alpha": 1.0}), "cube": Cube()}
        data = whitened.double().cpu().numpy()
        printed = _TracedPrints(self)
        with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stdout(printed):
            warnings.simplefilter("always")
            _, result, _, n_iter = picard(
                data,
                fun=densities[self.fun],
                ortho=True,
                extended=True,
                whiten=False,
                centering=False,
                return_n_iter=True,
                max_iter=max_iter,
                tol=tol,
                w_init=unmixing.double().cpu().numpy(),
                check_fun=False,
                verbose=True,  # its only report of each iteration's gradient: traced by _TracedPrints
            )
        for warning in caught:
            message = str(warning.message)
            if "did not converge" not in message and "different density than tanh" not in message:
                warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno)
        # the whole unmixing of its input (w_init included)
        rotated = torch.from_numpy(result).to(whitened.device, whitened.dtype)
        self.n_iter_ = int(n_iter) + 1  # its count starts at 0
        # its last gradient norm is only printed: the same measure, from its result
        self.criterion_ = float(gradient_of_sources(rotated @ whitened, self.fun).abs().max())
        self.converged_ = self.criterion_ < tol
        if self.converged_:  # the iteration that met tol stops before printing
            self.trace_.append((time.perf_counter() - self.started_, self.criterion_))
        return rotated


class _TracedPrints(io.TextIOBase):
    """python-picard's verbose lines ("iteration n, gradient norm = g, loss = l"), kept as `ica`'s
    trace_: the gradient at the start of iteration n, timed when the line is printed, after that
    iteration's line search (so up to one iteration later than TorchPicard's, which times it when
    computed); other lines are dropped."""

    LINE = re.compile(r"iteration \d+, gradient norm = ([^,]+),")

    def __init__(self, ica: TorchICA):
        self.ica = ica

    def write(self, text: str) -> int:
        now = time.perf_counter() - self.ica.started_
        for match in self.LINE.finditer(text):
            self.ica.trace_.append((now, float(match.group(1))))
        return len(text)
