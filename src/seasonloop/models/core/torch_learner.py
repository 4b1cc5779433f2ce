"""What the torch learners share: their training params, device, precision and thread choice, the
held-out validation places, a network seeded from the learner's seed, and save/load of its
state_dict. The auto-encoders' descriptors are in autoencoder_learner.py, the place-supervised
network's in models/place_cnn.py; the training loop is in training.py, the arithmetic (precision,
denormals) in arithmetic.py.

torch is imported inside the methods that compute: every stage imports the learner modules to
check params.yaml (seasonloop.models.core.learner), and torch takes a second to import."""

from __future__ import annotations

from abc import abstractmethod
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from seasonloop.models.core.arithmetic import DEVICES, PRECISIONS
from seasonloop.models.core.learner import FeatureLearner, select_training_subset
from seasonloop.params.checks import integer, number, one_of

if TYPE_CHECKING:
    import torch
    from torch import nn

    from seasonloop.models.core.training import TrainingConfig

MODEL_FILE = "model.pt"


class TorchLearner(FeatureLearner):
    """A learner whose model is a torch network trained in epochs until its validation plateau;
    subclasses build the network and say what an epoch trains.

    A subclass's PARAMS extend these. `channels_last` says whether the network runs faster with NHWC
    activations (convolutions under oneDNN/cuDNN do).
    """

    channels_last: bool = False
    LIBRARIES: ClassVar[tuple[str, ...]] = (
        "torch",
        "seasonloop.models.core.arithmetic",
        "seasonloop.models.core.training",
    )
    trains_in_epochs = True

    PARAMS = {
        "max_epochs": integer(1),
        "batch_size": integer(1),  # images a training batch
        "learning_rate": number(0, None, low_open=True),
        # stop when the validation loss has not improved by min_delta (relative) for `patience`
        # epochs in a row; halve the learning rate at the lr_patience-th such epoch in a row
        "patience": integer(1),
        "min_delta": number(0, 1, high_open=True),
        "lr_patience": integer(1),
        "lr_factor": number(0, 1, low_open=True, high_open=True),
        "budget_seconds": number(0),  # wall-clock cap on training (0: none); machine-dependent
        # of the training places (whole blocks), never test places
        "validation_fraction": number(0, 1, high_open=True),
        "validation_block": integer(1),  # consecutive places per held-out block
        "max_validation_images": integer(0),  # 0: every image of the validation places
        "precision": one_of(*PRECISIONS),  # autocast of the forward pass
        "threads": integer(0),  # torch CPU threads; 0: torch's default (recorded either way)
        "device": one_of(*DEVICES),
        "max_train_images": integer(0),
    }

    def __init__(self, params: Mapping[str, Any], seed: int = 0):
        super().__init__(params, seed)
        self.model: nn.Module | None = None
        self._dtype: torch.dtype | None = None  # the forward pass's, set by fit and load

    @abstractmethod
    def _build_model(self, height: int, width: int) -> nn.Module:
        """A freshly initialised network for height x width images."""

    def _check_image_size(self, height: int, width: int) -> None:
        """Raise ValueError if the network cannot take height x width images (subclasses override)."""

    @property
    def network(self) -> nn.Module:
        """The trained network (RuntimeError before fit or load)."""
        if self.model is None:
            raise RuntimeError(f"{self.name}: no network yet (fit or load first)")
        return self.model

    def _seeded_model(self) -> nn.Module:
        """Build the network with weights drawn from `seed`, leaving the global torch RNG untouched."""
        import torch

        with torch.random.fork_rng(devices=[]):
            torch.manual_seed(self.seed)
            return self._build_model(*self.image_shape)

    def _memory_format(self) -> torch.memory_format:
        import torch

        return torch.channels_last if self.channels_last else torch.contiguous_format

    def _set_threads(self) -> None:
        import torch

        if self.params["threads"]:
            torch.set_num_threads(self.params["threads"])

    def _training_config(self) -> TrainingConfig:
        from seasonloop.models.core.training import TrainingConfig

        return TrainingConfig(
            max_epochs=self.params["max_epochs"],
            batch_size=self.params["batch_size"],
            learning_rate=float(self.params["learning_rate"]),
            patience=self.params["patience"],
            min_delta=float(self.params["min_delta"]),
            lr_patience=self.params["lr_patience"],
            lr_factor=float(self.params["lr_factor"]),
            budget_seconds=float(self.params["budget_seconds"]),
            seed=self.seed,
        )

    def _split_validation(self) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
        """(rows of the training images, rows of the validation images, record): every image of the
        held-out places goes to validation (augmented copies included), so no validation place is
        ever trained on."""
        from seasonloop.models.core.training import validation_places

        places = self.train_places
        held_out = validation_places(
            places, self.params["validation_fraction"], self.params["validation_block"], self.seed
        )
        is_validation = np.isin(places, held_out)
        train, train_info = select_training_subset(
            np.flatnonzero(~is_validation), self.params["max_train_images"], self.seed
        )
        validation, validation_info = select_training_subset(
            np.flatnonzero(is_validation), self.params["max_validation_images"], self.seed + 1
        )
        return (
            train,
            validation,
            {
                **train_info,
                "n_validation_places": len(held_out),
                "n_validation_images_available": validation_info["n_train_images_available"],
                "n_validation_images": validation_info["n_train_images"],
            },
        )

    def _start_fit(self) -> tuple[torch.device, dict[str, Any]]:
        """The device, precision and threads of a fit, set before torch's first parallel work; (the
        device, the record of them)."""
        import torch

        from seasonloop.models.core.arithmetic import (
            cpu_has_native_bfloat16,
            flush_denormals,
            resolve_device,
            resolve_precision,
        )

        device = resolve_device(self.params["device"], self._key("device"))
        flush_denormals(device)  # before torch's first parallel work: in every thread
        self._dtype = resolve_precision(self.params["precision"], device, self._key("precision"))
        self._set_threads()
        return device, {
            "device": str(device),
            "precision": str(self._dtype).removeprefix("torch."),
            "cpu_native_bfloat16": cpu_has_native_bfloat16(),
            "channels_last": self.channels_last,
            "torch_threads": torch.get_num_threads(),
        }

    def _n_parameters(self) -> int:
        return sum(parameter.numel() for parameter in self.network.parameters())

    def _save_state(self, directory: Path) -> None:
        import torch

        torch.save(self.network.state_dict(), directory / MODEL_FILE)

    def _load_state(self, directory: Path) -> None:
        import torch

        from seasonloop.models.core.arithmetic import resolve_precision

        # A model trained on CUDA still loads (on the CPU) where CUDA is absent.
        # Precision is resolved again for the machine that loads it ('auto' may differ).
        use_cuda = self.params["device"] != "cpu" and torch.cuda.is_available()
        device = torch.device("cuda" if use_cuda else "cpu")
        self._dtype = resolve_precision(self.params["precision"], device, self._key("precision"))
        self._set_threads()
        self.model = self._seeded_model()
        self.model.load_state_dict(torch.load(directory / MODEL_FILE, map_location="cpu", weights_only=True))
        self.model.to(device=device, memory_format=self._memory_format()).eval()
