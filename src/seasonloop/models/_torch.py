"""Shared torch machinery of the two auto-encoders: device choice, deterministic training loop,
batched inference with the three descriptors, and save/load of the state_dict."""

from __future__ import annotations

from abc import abstractmethod
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import torch
from torch import nn
from tqdm.auto import tqdm

from seasonloop.models.base import EpochCallback, FeatureLearner, select_training_subset, to_float
from seasonloop.patchnorm import patch_normalise

DEVICES = ("auto", "cpu", "cuda")
AE_DESCRIPTORS = ("code", "output", "output_patchnorm")
MODEL_FILE = "model.pt"


def resolve_device(requested: str, key: str) -> torch.device:
    """'auto' -> cuda if available else cpu; 'cuda' without CUDA -> ValueError naming `key`."""
    if requested == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    if requested == "cuda" and not torch.cuda.is_available():
        raise ValueError(f"{key} = 'cuda' but CUDA is not available on this machine")
    return torch.device(requested)


class AutoEncoder(nn.Module):
    """encoder: (B, 1, H, W) -> code; decoder: code -> (B, 1, H, W) in [0, 1]."""

    def __init__(self, encoder: nn.Module, decoder: nn.Module):
        super().__init__()
        self.encoder = encoder
        self.decoder = decoder

    def forward(self, images: torch.Tensor) -> torch.Tensor:
        return self.decoder(self.encoder(images))


@contextmanager
def deterministic_algorithms(device: torch.device) -> Iterator[None]:
    """Ask torch for deterministic kernels while training, then restore the caller's settings.

    On CUDA some kernels (e.g. nearest-upsampling backward) have no deterministic version, so
    there torch only warns instead of raising.
    """
    previous = (
        torch.are_deterministic_algorithms_enabled(),
        torch.is_deterministic_algorithms_warn_only_enabled(),
        torch.backends.cudnn.deterministic,
        torch.backends.cudnn.benchmark,
    )
    torch.use_deterministic_algorithms(True, warn_only=device.type != "cpu")
    torch.backends.cudnn.deterministic, torch.backends.cudnn.benchmark = True, False
    try:
        yield
    finally:
        torch.use_deterministic_algorithms(previous[0], warn_only=previous[1])
        torch.backends.cudnn.deterministic, torch.backends.cudnn.benchmark = previous[2:]


def train_autoencoder(
    model: nn.Module,
    images: torch.Tensor,
    epochs: int,
    batch_size: int,
    learning_rate: float,
    seed: int,
    device: torch.device,
    progress: bool = True,
    on_epoch: EpochCallback | None = None,
    description: str = "train",
) -> list[float]:
    """Minimise the MSE reconstruction loss with Adam; return the mean training loss per epoch.

    images: (N, 1, H, W) float32 on the CPU; batches are moved to `device` one at a time.
    Shuffling uses its own generator seeded with `seed`; on_epoch(epoch (1-based), {"loss": ...})
    runs after each epoch.
    """
    generator = torch.Generator().manual_seed(seed)
    optimiser = torch.optim.Adam(model.parameters(), lr=learning_rate)
    loss_function = nn.MSELoss()
    model.to(device).train()
    mean_losses = []
    with deterministic_algorithms(device):
        for epoch in range(1, epochs + 1):
            order = torch.randperm(len(images), generator=generator)
            summed_loss = 0.0
            batches = tqdm(
                range(0, len(images), batch_size),
                desc=f"{description} epoch {epoch}/{epochs}",
                unit="batch",
                disable=not progress,
                leave=False,
            )
            for start in batches:
                batch = images[order[start : start + batch_size]].to(device)
                optimiser.zero_grad(set_to_none=True)
                loss = loss_function(model(batch), batch)
                loss.backward()
                optimiser.step()
                summed_loss += loss.item() * len(batch)
                batches.set_postfix(loss=f"{loss.item():.5f}")
            mean_losses.append(summed_loss / len(images))
            if on_epoch is not None:
                on_epoch(epoch, {"loss": mean_losses[-1]})
    model.eval()
    return mean_losses


class TorchAutoEncoderLearner(FeatureLearner):
    """Common fit/describe/save/load of the auto-encoders; subclasses define the network.

    Subclass defaults must include the keys of COMMON_DEFAULTS.
    """

    COMMON_DEFAULTS = {
        "epochs": 20,
        "batch_size": 128,
        "learning_rate": 1e-3,
        "descriptor": "output_patchnorm",
        "patch_size": 8,
        "device": "auto",
        "max_train_images": 0,
    }

    def __init__(self, params: Mapping[str, Any] | None = None, seed: int = 0):
        super().__init__(params, seed)
        self.model: AutoEncoder | None = None

    @abstractmethod
    def _build_model(self, height: int, width: int) -> AutoEncoder:
        """A freshly initialised network for height x width images."""

    def _check_image_size(self, height: int, width: int) -> None:
        """Raise ValueError if the network cannot take height x width images (subclasses override)."""

    def _validate_params(self) -> None:
        for key in ("epochs", "batch_size", "patch_size"):
            self._check_int(key, 1)
        self._check_int("max_train_images", 0)
        self._check_positive_float("learning_rate")
        self._check_choice("descriptor", AE_DESCRIPTORS)
        self._check_choice("device", DEVICES)

    def _seeded_model(self) -> AutoEncoder:
        """Build the network with weights drawn from `seed`, leaving the global torch RNG untouched."""
        with torch.random.fork_rng(devices=[]):
            torch.manual_seed(self.seed)
            return self._build_model(*self.input_shape)

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        height, width = self.input_shape
        self._check_image_size(height, width)
        patch_size = self.params["patch_size"]
        if self.params["descriptor"] == "output_patchnorm" and (height % patch_size or width % patch_size):
            raise ValueError(
                f"{self._key('patch_size')} = {patch_size} does not divide the image size {height}x{width}"
            )
        device = resolve_device(self.params["device"], self._key("device"))
        subset, subset_info = select_training_subset(images, self.params["max_train_images"], self.seed)
        self.model = self._seeded_model()
        losses = train_autoencoder(
            self.model,
            torch.from_numpy(to_float(subset)).unsqueeze(1),
            epochs=self.params["epochs"],
            batch_size=self.params["batch_size"],
            learning_rate=self.params["learning_rate"],
            seed=self.seed,
            device=device,
            progress=progress,
            on_epoch=on_epoch,
            description=self.name,
        )
        return {
            **subset_info,
            "device": str(device),
            "n_parameters": sum(parameter.numel() for parameter in self.model.parameters()),
            "final_loss": losses[-1],
            "loss_per_epoch": losses,
        }

    def _forward_batch(self, images: np.ndarray, decode: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """Code (n, C) and, if `decode`, output (n, H*W) of one batch, as numpy arrays."""
        device = next(self.model.parameters()).device
        inputs = torch.from_numpy(to_float(images)).unsqueeze(1).to(device)
        with torch.inference_mode():
            code = self.model.encoder(inputs)
            output = self.model.decoder(code)[:, 0].reshape(len(images), -1).cpu().numpy() if decode else None
            return code.flatten(1).cpu().numpy(), output

    def _descriptor_batch(self, images: np.ndarray, descriptor: str) -> np.ndarray:
        code, output = self._forward_batch(images, decode=descriptor != "code")
        if descriptor == "code":
            return code
        if descriptor == "output":
            return output
        return patch_normalise(output.reshape(images.shape), self.params["patch_size"]).reshape(len(images), -1)

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        return self._descriptor_batch(images, self.params["descriptor"])

    def describe_as(
        self, images: np.ndarray, descriptor: str, batch_size: int = 1024, progress: bool = False
    ) -> np.ndarray:
        """(N, D) float32 descriptors of one kind ("code", "output" or "output_patchnorm") from the
        trained model, whatever the `descriptor` param says."""
        if descriptor not in AE_DESCRIPTORS:
            raise ValueError(f"descriptor must be one of {', '.join(AE_DESCRIPTORS)}, got {descriptor!r}")
        images = self._check_describe_input(images, "describe_as")
        return self._in_batches(images, batch_size, lambda batch: self._descriptor_batch(batch, descriptor),
                                progress, f"{self.name} {descriptor}")

    def describe_code_and_output(
        self, images: np.ndarray, batch_size: int = 1024, progress: bool = False
    ) -> tuple[np.ndarray, np.ndarray]:
        """The code vectors (N, C) and the reconstructed outputs (N, H*W), float32, from one forward
        pass: the study's Figure 19 compares them, and a second pass would redo the encoder."""
        images = self._check_describe_input(images, "describe_code_and_output")
        outputs: list[np.ndarray] = []

        def code_keeping_output(batch: np.ndarray) -> np.ndarray:
            code, output = self._forward_batch(batch)
            outputs.append(output)
            return code

        codes = self._in_batches(images, batch_size, code_keeping_output, progress, f"{self.name} code and output")
        return codes, np.concatenate(outputs)

    def _save_state(self, directory: Path) -> None:
        torch.save(self.model.state_dict(), directory / MODEL_FILE)

    def _load_state(self, directory: Path) -> None:
        # A model trained on CUDA still loads (on the CPU) where CUDA is absent.
        use_cuda = self.params["device"] != "cpu" and torch.cuda.is_available()
        self.model = self._seeded_model()
        self.model.load_state_dict(torch.load(directory / MODEL_FILE, map_location="cpu", weights_only=True))
        self.model.to(torch.device("cuda" if use_cuda else "cpu")).eval()
