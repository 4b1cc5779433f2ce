"""Training of the torch learners until they have learned: a validation set held out by place,
a learning-rate schedule, early stopping on a validation plateau (or at a maximum number of
epochs, or a wall-clock budget), the best weights kept. What an epoch trains and what the
validation measures are the learner's (autoencoder_training.py: reconstruction;
place_training.py: recall of held-out places); the stopping rule is here, one for all.
"""

from __future__ import annotations

import copy
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np
import torch
from torch import nn

from seasonloop.models.core.learner import EpochCallback


@contextmanager
def deterministic_algorithms(device: torch.device) -> Iterator[None]:
    """Ask torch for deterministic kernels while training, then restore the caller's settings.

    On CUDA some kernels (e.g. nearest-upsampling backward) have no deterministic version, so
    there torch only warns instead of raising. Set through torch._C, the setter that
    torch.use_deterministic_algorithms calls after importing torch._inductor's config only to set
    its flag for torch.compile, which no learner uses: that import costs ~1.1 s of CPU in every
    process that trains (AMD EPYC Zen 4), more than a tiny run's whole fit.
    """
    previous = (
        torch.are_deterministic_algorithms_enabled(),
        torch.is_deterministic_algorithms_warn_only_enabled(),
        torch.backends.cudnn.deterministic,
        torch.backends.cudnn.benchmark,
    )
    torch._C._set_deterministic_algorithms(True, warn_only=device.type != "cpu")
    torch.backends.cudnn.deterministic, torch.backends.cudnn.benchmark = True, False
    try:
        yield
    finally:
        torch._C._set_deterministic_algorithms(previous[0], warn_only=previous[1])
        torch.backends.cudnn.deterministic, torch.backends.cudnn.benchmark = previous[2:]


# Why training stopped; only a plateau means the model has learned what it can from this data.
# diverged: a loss became NaN or infinite (the weights of the best finite epoch are kept).
STOP_PLATEAU, STOP_MAX_EPOCHS, STOP_BUDGET, STOP_DIVERGED = "plateau", "max_epochs", "budget", "diverged"


@dataclass(frozen=True)
class TrainingConfig:
    """How long and how fast to train; see the fae, cae and place_cnn sections of params.yaml."""

    max_epochs: int
    batch_size: int
    learning_rate: float
    patience: int  # epochs without a relative improvement of min_delta -> plateau
    min_delta: float  # relative improvement of the validation loss that counts
    lr_patience: int  # the learning rate is cut at the lr_patience-th epoch without improvement (>= 1)
    lr_factor: float  # ... by this factor (ReduceLROnPlateau)
    budget_seconds: float  # 0: no wall-clock budget
    seed: int


@dataclass
class TrainingResult:
    train_loss: list[float]
    validation_loss: list[float]
    learning_rate: list[float]
    best_epoch: int
    stop_reason: str
    seconds: float
    images_seen: int

    def info(self) -> dict[str, Any]:
        """JSON-ready record for the fit metrics."""
        return {
            "epochs_run": len(self.train_loss),
            "best_epoch": self.best_epoch,
            "best_validation_loss": self.validation_loss[self.best_epoch - 1],
            "final_train_loss": self.train_loss[-1],
            "stop_reason": self.stop_reason,
            "converged": self.stop_reason == STOP_PLATEAU,
            "training_seconds": self.seconds,
            "images_seen": self.images_seen,
            "loss_per_epoch": self.train_loss,
            "validation_loss_per_epoch": self.validation_loss,
            "learning_rate_per_epoch": self.learning_rate,
        }


class _Plateau:
    """The early-stopping bookkeeping: the lowest validation loss (and its weights), and the epoch of
    the last improvement of min_delta.

    The plateau counter restarts only on an improvement of min_delta over the loss of the last such
    improvement; the weights kept are those of the lowest validation loss, however small its lead.
    """

    def __init__(self, min_delta: float):
        self.min_delta = min_delta
        self.best_loss, self.best_epoch = float("inf"), 0
        self.best_state: dict[str, Any] | None = None
        self.reference_loss, self.improved_epoch = float("inf"), 0

    def update(self, epoch: int, loss: float, model: nn.Module) -> None:
        if loss < self.best_loss:
            self.best_loss, self.best_epoch = loss, epoch
            self.best_state = copy.deepcopy(model.state_dict())
        if loss < self.reference_loss * (1 - self.min_delta):
            self.reference_loss, self.improved_epoch = loss, epoch


def _stop_reason(epoch: int, diverged: bool, plateau: _Plateau, config: TrainingConfig, elapsed: float) -> str | None:
    """Why training stops after `epoch` (elapsed seconds in), or None to go on."""
    if diverged:
        # NaN fails every comparison, so without this a diverged run would read as a plateau
        return STOP_DIVERGED
    if epoch - plateau.improved_epoch >= config.patience:
        return STOP_PLATEAU
    if config.budget_seconds and epoch < config.max_epochs and elapsed * (epoch + 1) / epoch > config.budget_seconds:
        return STOP_BUDGET
    return None


def adam(model: nn.Module, learning_rate: float) -> torch.optim.Adam:
    """Adam, fused: one pass over the weights a step instead of one per operation of the update, the
    same update up to float rounding; the per-operation default was ~40% of the FAE's epoch on the
    CPU (benchmarks/speed/bench_training_schedule.py: adam=per_tensor)."""
    return torch.optim.Adam(model.parameters(), lr=learning_rate, fused=True)


def learning_rate_schedule(
    optimiser: torch.optim.Optimizer, config: TrainingConfig
) -> torch.optim.lr_scheduler.ReduceLROnPlateau:
    """ReduceLROnPlateau that cuts the rate at the lr_patience-th epoch in a row without a relative
    improvement of min_delta: torch cuts when the bad epochs *exceed* its patience, hence the - 1."""
    if config.lr_patience < 1:
        raise ValueError(f"lr_patience must be an integer >= 1, got {config.lr_patience!r}")
    return torch.optim.lr_scheduler.ReduceLROnPlateau(
        optimiser,
        mode="min",
        factor=config.lr_factor,
        patience=config.lr_patience - 1,
        threshold=config.min_delta,
        threshold_mode="rel",
    )


def until_plateau(
    model: nn.Module,
    optimiser: torch.optim.Optimizer,
    train_epoch: Callable[[int], float],
    validation_loss_now: Callable[[], float],
    config: TrainingConfig,
    images_per_epoch: int,
    on_epoch: EpochCallback | None = None,
    description: str = "train",
) -> TrainingResult:
    """Train epoch after epoch (train_epoch(epoch) -> its mean training loss) until the validation
    loss (validation_loss_now(), lower is better) plateaus.

    After every epoch the validation loss decides: a new lowest loss keeps a copy of the weights; a
    relative improvement of at least min_delta (same threshold as ReduceLROnPlateau, which cuts the
    learning rate after lr_patience epochs without one) restarts the patience count; training
    stops after `patience` epochs without one (plateau), at max_epochs, or when the next epoch
    would overrun budget_seconds, or as soon as a loss is NaN or infinite (diverged). The model ends
    with the weights of its lowest validation loss.
    on_epoch(epoch, {"train_loss", "validation_loss", "learning_rate"}) runs after each epoch.
    """
    scheduler = learning_rate_schedule(optimiser, config)
    train_loss: list[float] = []
    validation_loss: list[float] = []
    learning_rate: list[float] = []
    plateau = _Plateau(config.min_delta)
    start_time = time.perf_counter()
    stop_reason = STOP_MAX_EPOCHS
    for epoch in range(1, config.max_epochs + 1):
        train_loss.append(train_epoch(epoch))
        learning_rate.append(optimiser.param_groups[0]["lr"])
        validation_loss.append(validation_loss_now())
        diverged = not (np.isfinite(train_loss[-1]) and np.isfinite(validation_loss[-1]))
        if not diverged:
            scheduler.step(validation_loss[-1])
            plateau.update(epoch, validation_loss[-1], model)
        if on_epoch is not None:
            losses = {"train_loss": train_loss[-1], "validation_loss": validation_loss[-1]}
            on_epoch(epoch, {**losses, "learning_rate": learning_rate[-1]})
        stop = _stop_reason(epoch, diverged, plateau, config, time.perf_counter() - start_time)
        if stop:
            stop_reason = stop
            break
    if plateau.best_state is None:
        raise RuntimeError(f"{description}: the validation loss was never finite ({validation_loss})")
    model.load_state_dict(plateau.best_state)
    model.eval()
    seconds, images_seen = time.perf_counter() - start_time, images_per_epoch * len(train_loss)
    return TrainingResult(
        train_loss, validation_loss, learning_rate, plateau.best_epoch, stop_reason, seconds, images_seen
    )


def validation_places(places: np.ndarray, fraction: float, block: int, seed: int) -> np.ndarray:
    """The place ids held out for validation: a seeded random `fraction` of the blocks of `block`
    consecutive distinct place ids (whole blocks, so a validation place's neighbours, which look
    almost the same, are mostly not training places). Never empty, never all places."""
    distinct = np.unique(places)
    blocks = np.array_split(distinct, max(1, -(-len(distinct) // block)))
    if len(blocks) < 2:
        raise ValueError(f"validation needs at least 2 blocks of {block} places, got {len(distinct)} places")
    n_held_out = min(len(blocks) - 1, max(1, round(fraction * len(blocks))))
    chosen = np.random.default_rng(seed).choice(len(blocks), size=n_held_out, replace=False)
    return np.sort(np.concatenate([blocks[index] for index in chosen]))
