"""The densities of the torch ICA solvers (the values of `fun`): each solver's score g = G' with the
mean of g', and the contrast G, as scikit-learn's FastICA and python-picard define them."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import torch


@dataclass(frozen=True)
class Density:
    """One value of `fun`: score(y) -> (g(y), the row means of g'(y)) for (k, n) sources, and
    contrast(y) -> G(y) elementwise (up to a constant), the negative log-likelihood Picard minimises."""

    score: Callable[[torch.Tensor], tuple[torch.Tensor, torch.Tensor]]
    contrast: Callable[[torch.Tensor], torch.Tensor]


def _logcosh_score(sources: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    squashed = torch.tanh(sources)
    return squashed, 1.0 - (squashed * squashed).mean(dim=1)


def _logcosh_contrast(sources: torch.Tensor) -> torch.Tensor:
    # log cosh y + log 2 = y + log(1 + exp(-2y)); softplus stays exact where exp(-2y) overflows
    return sources + torch.nn.functional.softplus(-2.0 * sources)


def _exp_score(sources: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    squared = sources * sources
    gaussian = torch.exp(-0.5 * squared)
    return sources * gaussian, ((1.0 - squared) * gaussian).mean(dim=1)


def _cube_score(sources: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    squared = sources * sources
    return squared * sources, 3.0 * squared.mean(dim=1)


# g = G' and G as in scikit-learn's FastICA (alpha = 1) and python-picard's densities.
DENSITIES: dict[str, Density] = {
    "logcosh": Density(_logcosh_score, _logcosh_contrast),
    "exp": Density(_exp_score, lambda sources: -torch.exp(-0.5 * sources * sources)),
    "cube": Density(_cube_score, lambda sources: 0.25 * sources**4),
}
NONLINEARITIES = tuple(DENSITIES)
