"""The auto-encoders' network and what their training minimises: the mean squared reconstruction
error, epoch by epoch over shuffled batches, until the validation loss plateaus
(training.until_plateau).

Only the forward pass runs under autocast; the loss, the gradients' accumulation in the float32
weights and the optimiser state stay float32.
"""

from __future__ import annotations

import torch
from torch import nn
from tqdm.auto import tqdm

from seasonloop.models.core.arithmetic import autocast
from seasonloop.models.core.learner import EpochCallback
from seasonloop.models.core.training import TrainingConfig, TrainingResult, adam, until_plateau


class AutoEncoder(nn.Module):
    """encoder: (B, 1, H, W) -> code; decoder: code -> (B, 1, H, W) in [0, 1]."""

    def __init__(self, encoder: nn.Module, decoder: nn.Module):
        super().__init__()
        self.encoder = encoder
        self.decoder = decoder

    def forward(self, images: torch.Tensor) -> torch.Tensor:
        return self.decoder(self.encoder(images))


def mean_loss(
    model: nn.Module,
    images: torch.Tensor,
    batch_size: int,
    device: torch.device,
    dtype: torch.dtype,
    memory_format: torch.memory_format,
) -> float:
    """Mean squared reconstruction error over `images` (computed in float32)."""
    model.eval()
    summed = 0.0
    with torch.inference_mode():
        for start in range(0, len(images), batch_size):
            batch = images[start : start + batch_size].to(device).contiguous(memory_format=memory_format)
            with autocast(device, dtype):
                output = model(batch)
            summed += nn.functional.mse_loss(output.float(), batch, reduction="sum").item()
    return summed / images[0].numel() / len(images)


def _train_epoch(
    model: nn.Module,
    train_images: torch.Tensor,
    order: torch.Tensor,
    optimiser: torch.optim.Optimizer,
    batch_size: int,
    device: torch.device,
    dtype: torch.dtype,
    memory_format: torch.memory_format,
    batches_description: str,
    progress: bool,
) -> float:
    """One pass over train_images in `order`; returns the mean training loss."""
    model.train()
    summed = 0.0
    batches = tqdm(
        range(0, len(train_images), batch_size),
        unit="batch",
        leave=False,
        desc=batches_description,
        disable=not progress,
    )
    for first in batches:
        batch = train_images[order[first : first + batch_size]].to(device)
        batch = batch.contiguous(memory_format=memory_format)
        optimiser.zero_grad(set_to_none=True)
        with autocast(device, dtype):
            output = model(batch)
        loss = nn.functional.mse_loss(output.float(), batch)
        loss.backward()
        optimiser.step()
        summed += loss.item() * len(batch)
        batches.set_postfix(loss=f"{loss.item():.5f}")
    return summed / len(train_images)


def train_until_plateau(
    model: nn.Module,
    train_images: torch.Tensor,
    validation_images: torch.Tensor,
    config: TrainingConfig,
    device: torch.device,
    dtype: torch.dtype = torch.float32,
    memory_format: torch.memory_format = torch.contiguous_format,
    progress: bool = True,
    on_epoch: EpochCallback | None = None,
    description: str = "train",
) -> TrainingResult:
    """Minimise the MSE reconstruction loss with Adam until the validation loss plateaus
    (training.until_plateau says when).

    images: (N, 1, H, W) float32 on the CPU, moved to `device` a batch at a time. Shuffling has its
    own generator seeded from config.seed, so the global torch RNG is left alone.
    """
    generator = torch.Generator().manual_seed(config.seed)
    model.to(device=device, memory_format=memory_format)
    optimiser = adam(model, config.learning_rate)

    def train_epoch(epoch: int) -> float:
        order = torch.randperm(len(train_images), generator=generator)
        batches = (model, train_images, order, optimiser, config.batch_size, device, dtype, memory_format)
        return _train_epoch(*batches, f"{description} epoch {epoch}/{config.max_epochs}", progress)

    def validation_loss() -> float:
        return mean_loss(model, validation_images, config.batch_size, device, dtype, memory_format)

    return until_plateau(
        model, optimiser, train_epoch, validation_loss, config, len(train_images), on_epoch, description
    )
