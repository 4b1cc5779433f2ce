"""What a place-supervised network's training does (models/place_cnn.py): batches of P places with
K images of each (the GSV-Cities / MixVPR sampler), the multi-similarity loss over the pairs its
miner keeps (pytorch-metric-learning), and a validation that asks what the network is for: recall@1
of the held-out places across traverses. training.until_plateau says when it has learned.

Only the forward pass runs under autocast; the loss, the gradients and the optimiser stay float32.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch
from pytorch_metric_learning import losses, miners
from torch import nn
from tqdm.auto import tqdm

from seasonloop.models.core.arithmetic import autocast
from seasonloop.models.core.learner import EpochCallback, to_float
from seasonloop.models.core.training import TrainingConfig, TrainingResult, adam, until_plateau


class GeM(nn.Module):
    """Generalised mean over the positions of each channel (Radenovic et al. 2019), its exponent
    learned from p: p = 1 is the mean, large p nears the maximum."""

    def __init__(self, p: float, eps: float = 1e-6):
        super().__init__()
        self.p = nn.Parameter(torch.tensor([float(p)]))
        self.eps = eps

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return x.clamp(min=self.eps).pow(self.p).mean(dim=(-2, -1)).pow(1.0 / self.p)


class L2Normalised(nn.Module):
    """Each row scaled to unit length: the descriptors' inner product is their cosine."""

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return nn.functional.normalize(x, dim=1)


def place_batches(
    places: np.ndarray, places_per_batch: int, images_per_place: int, rng: np.random.Generator
) -> list[np.ndarray]:
    """One epoch's batches of rows: the places with two images or more (a place with one has no
    positive to learn from) in a random order, `places_per_batch` of them a batch, each with
    `images_per_place` of its images drawn without replacement (all of them where it has fewer).
    Every place is in one batch an epoch; a last batch of fewer than two places (no negative) is
    dropped."""
    ids, counts = np.unique(places, return_counts=True)
    rows_of = {place: np.flatnonzero(places == place) for place in ids[counts >= 2]}
    order = rng.permutation(np.array(sorted(rows_of), dtype=places.dtype))
    batches = []
    for start in range(0, len(order), places_per_batch):
        chosen = order[start : start + places_per_batch]
        if len(chosen) < 2:
            break
        batches.append(
            np.concatenate(
                [
                    rng.choice(rows_of[place], size=min(images_per_place, len(rows_of[place])), replace=False)
                    for place in chosen
                ]
            )
        )
    return batches


def recall_across_traverses(descriptors: np.ndarray, places: np.ndarray, traverses: np.ndarray) -> float:
    """Recall@1 of every image whose place another traverse shows: is its nearest image (largest
    inner product of the L2-normalised descriptors) of another traverse one of its own place?"""
    similarity = descriptors @ descriptors.T
    similarity[traverses[:, None] == traverses[None, :]] = -np.inf  # its own traverse (and copies): not a match
    shown_elsewhere = ((places[:, None] == places[None, :]) & (traverses[:, None] != traverses[None, :])).any(axis=1)
    nearest = similarity[shown_elsewhere].argmax(axis=1)
    return float(np.mean(places[nearest] == places[shown_elsewhere]))


@dataclass(frozen=True)
class PlaceLoss:
    """The multi-similarity loss and its miner (Wang et al. 2019; GSV-Cities' values: alpha 1,
    beta 50, base 0, epsilon 0.1)."""

    alpha: float
    beta: float
    base: float
    epsilon: float


def describe_in_batches(
    model: nn.Module, images: np.ndarray, batch_size: int, device: torch.device, dtype: torch.dtype
) -> np.ndarray:
    """(N, D) float32 descriptors of uint8 (N, H, W) images, the model in eval mode."""
    model.eval()
    described = []
    with torch.inference_mode():
        for start in range(0, len(images), batch_size):
            batch = torch.from_numpy(to_float(images[start : start + batch_size])).unsqueeze(1).to(device)
            with autocast(device, dtype):
                described.append(model(batch).float().cpu().numpy())
    return np.concatenate(described)


def train_on_places(
    model: nn.Module,
    train: tuple[np.ndarray, np.ndarray],
    validation: tuple[np.ndarray, np.ndarray, np.ndarray],
    images_per_place: int,
    loss: PlaceLoss,
    config: TrainingConfig,
    device: torch.device,
    dtype: torch.dtype = torch.float32,
    memory_format: torch.memory_format = torch.contiguous_format,
    progress: bool = True,
    on_epoch: EpochCallback | None = None,
    description: str = "train",
) -> TrainingResult:
    """Minimise the multi-similarity loss with Adam over batches of config.batch_size //
    images_per_place places until 1 - recall@1 of the validation places across traverses plateaus.

    train: (uint8 images, their place ids); validation: (images, place ids, traverses). The batches
    are drawn from a generator seeded with config.seed, the global RNGs are left alone.
    """
    images, places = train
    rng = np.random.default_rng(config.seed)
    model.to(device=device, memory_format=memory_format)  # one-channel images are NCHW and NHWC alike
    optimiser = adam(model, config.learning_rate)
    loss_function = losses.MultiSimilarityLoss(alpha=loss.alpha, beta=loss.beta, base=loss.base)
    miner = miners.MultiSimilarityMiner(epsilon=loss.epsilon)
    places_per_batch = max(2, config.batch_size // images_per_place)

    def train_epoch(epoch: int) -> float:
        model.train()
        batches = place_batches(places, places_per_batch, images_per_place, rng)
        summed, seen = 0.0, 0
        shown = tqdm(batches, unit="batch", leave=False, desc=f"{description} epoch {epoch}", disable=not progress)
        for rows in shown:
            batch = torch.from_numpy(to_float(images[rows])).unsqueeze(1).to(device)
            labels = torch.from_numpy(places[rows]).to(device)
            optimiser.zero_grad(set_to_none=True)
            with autocast(device, dtype):
                embeddings = model(batch)
            embeddings = embeddings.float()
            value = loss_function(embeddings, labels, miner(embeddings, labels))
            value.backward()
            optimiser.step()
            summed, seen = summed + value.item() * len(rows), seen + len(rows)
            shown.set_postfix(loss=f"{value.item():.4f}")
        return summed / max(seen, 1)

    def validation_error() -> float:
        described = describe_in_batches(model, validation[0], config.batch_size, device, dtype)
        return 1.0 - recall_across_traverses(described, validation[1], validation[2])

    counts = np.unique(places, return_counts=True)[1]
    per_epoch = int(np.minimum(counts[counts >= 2], images_per_place).sum())  # less a dropped last batch
    return until_plateau(model, optimiser, train_epoch, validation_error, config, per_epoch, on_epoch, description)
