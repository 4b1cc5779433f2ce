"""Shared machinery of the two auto-encoders: their training params, device, precision and thread
choice, the held-out validation places, batched inference with the three descriptors, and save/load
of the state_dict. The training loop is in training.py, the arithmetic (precision, denormals) in
arithmetic.py.

torch is imported inside the methods that compute: every stage imports the learner modules to
check params.yaml (seasonloop.models.core.learner), and torch takes a second to import."""

from __future__ import annotations

from abc import abstractmethod
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from seasonloop.data.patchnorm import patch_normalise
from seasonloop.models.core.arithmetic import DEVICES, PRECISIONS
from seasonloop.models.core.learner import EpochCallback, FeatureLearner, select_training_subset, to_float
from seasonloop.params.checks import integer, number, one_of

if TYPE_CHECKING:
    import torch

    from seasonloop.models.core.training import AutoEncoder, TrainingConfig

MODEL_FILE = "model.pt"
AE_DESCRIPTORS = ("code", "output", "output_patchnorm")


class TorchAutoEncoderLearner(FeatureLearner):
    """Common fit/describe/save/load of the auto-encoders; subclasses define the network.

    A subclass's PARAMS extend these (its network's keys). `channels_last` says
    whether the network runs faster with NHWC activations (convolutions under oneDNN/cuDNN do).
    """

    channels_last: bool = False
    LIBRARIES: ClassVar[tuple[str, ...]] = (
        "torch",
        "seasonloop.models.core.arithmetic",
        "seasonloop.models.core.training",
    )
    trains_in_epochs = True
    figures = ("autoencoder",)  # the study's Figure 19: code, output, patch-normalised output

    PARAMS = {
        "max_epochs": integer(1),
        "batch_size": integer(1),
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
        "descriptor": one_of(*AE_DESCRIPTORS),
        "patch_size": integer(1),
        "device": one_of(*DEVICES),
        "max_train_images": integer(0),
    }

    def __init__(self, params: Mapping[str, Any], seed: int = 0):
        super().__init__(params, seed)
        self.model: AutoEncoder | None = None
        self._dtype: torch.dtype | None = None  # the forward pass's, set by fit and load

    @abstractmethod
    def _build_model(self, height: int, width: int) -> AutoEncoder:
        """A freshly initialised network for height x width images."""

    def _check_image_size(self, height: int, width: int) -> None:
        """Raise ValueError if the network cannot take height x width images (subclasses override)."""

    @property
    def network(self) -> AutoEncoder:
        """The trained network (RuntimeError before fit or load)."""
        if self.model is None:
            raise RuntimeError(f"{self.name}: no network yet (fit or load first)")
        return self.model

    def _seeded_model(self) -> AutoEncoder:
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

    def _split_validation(self, images: np.ndarray) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
        """(training images, validation images, record): every image of the held-out places goes
        to validation (augmented copies included), so no validation place is ever trained on."""
        from seasonloop.models.core.training import validation_places

        places = self.train_places
        held_out = validation_places(
            places, self.params["validation_fraction"], self.params["validation_block"], self.seed
        )
        is_validation = np.isin(places, held_out)
        train, train_info = select_training_subset(images[~is_validation], self.params["max_train_images"], self.seed)
        validation, validation_info = select_training_subset(
            images[is_validation], self.params["max_validation_images"], self.seed + 1
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

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        import torch

        from seasonloop.models.core.arithmetic import (
            cpu_has_native_bfloat16,
            flush_denormals,
            resolve_device,
            resolve_precision,
        )
        from seasonloop.models.core.training import deterministic_algorithms, train_until_plateau

        height, width = self.image_shape
        self._check_image_size(height, width)
        patch_size = self.params["patch_size"]
        if self.params["descriptor"] == "output_patchnorm" and (height % patch_size or width % patch_size):
            raise ValueError(
                f"{self._key('patch_size')} = {patch_size} does not divide the image size {height}x{width}"
            )
        device = resolve_device(self.params["device"], self._key("device"))
        flush_denormals(device)  # before torch's first parallel work: in every thread
        self._dtype = resolve_precision(self.params["precision"], device, self._key("precision"))
        self._set_threads()
        train, validation, split_info = self._split_validation(images)
        self.model = self._seeded_model()
        with deterministic_algorithms(device):
            result = train_until_plateau(
                self.model,
                torch.from_numpy(to_float(train)).unsqueeze(1),
                torch.from_numpy(to_float(validation)).unsqueeze(1),
                self._training_config(),
                device=device,
                dtype=self._dtype,
                memory_format=self._memory_format(),
                progress=progress,
                on_epoch=on_epoch,
                description=self.name,
            )
        return {
            **split_info,
            **result.info(),
            "device": str(device),
            "precision": str(self._dtype).removeprefix("torch."),
            "cpu_native_bfloat16": cpu_has_native_bfloat16(),
            "channels_last": self.channels_last,
            "torch_threads": torch.get_num_threads(),
            "n_parameters": sum(parameter.numel() for parameter in self.network.parameters()),
        }

    def _forward_batch(self, images: np.ndarray, decode: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """Code (n, C) and, if `decode`, output (n, H*W) of one batch, as float32 numpy arrays."""
        import torch

        from seasonloop.models.core.arithmetic import autocast

        assert self._dtype is not None, "set with the network, by fit or load"
        model = self.network
        device = next(model.parameters()).device
        inputs = torch.from_numpy(to_float(images)).unsqueeze(1).to(device)
        inputs = inputs.contiguous(memory_format=self._memory_format())
        with torch.inference_mode(), autocast(device, self._dtype):
            code = model.encoder(inputs)
            output = None
            if decode:
                output = model.decoder(code)[:, 0].float().reshape(len(images), -1).cpu().numpy()
            return code.float().flatten(1).cpu().numpy(), output

    def _descriptor_batch(self, images: np.ndarray, descriptor: str) -> np.ndarray:
        code, output = self._forward_batch(images, decode=descriptor != "code")
        if descriptor == "code":
            return code
        assert output is not None, "decoded: the descriptor is not the code"
        if descriptor == "output":
            return output
        return self.patchnorm_output(output, images.shape[1:])

    def patchnorm_output(self, outputs: np.ndarray, image_shape: tuple[int, int]) -> np.ndarray:
        """The "output_patchnorm" descriptors (N, H*W) of outputs (N, H*W) of images of (H, W): what
        describe_as gives, for outputs already at hand (describe_code_and_output's)."""
        return patch_normalise(outputs.reshape(len(outputs), *image_shape), self.params["patch_size"]).reshape(
            len(outputs), -1
        )

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
        return self._in_batches(
            images,
            batch_size,
            lambda batch: self._descriptor_batch(batch, descriptor),
            progress,
            f"{self.name} {descriptor}",
        )

    def describe_code_and_output(
        self, images: np.ndarray, batch_size: int = 1024, progress: bool = False
    ) -> tuple[np.ndarray, np.ndarray]:
        """The code vectors (N, C) and the reconstructed outputs (N, H*W), float32, from one forward
        pass: the study's Figure 19 compares them, and a second pass would redo the encoder."""
        images = self._check_describe_input(images, "describe_code_and_output")
        outputs: list[np.ndarray] = []

        def code_keeping_output(batch: np.ndarray) -> np.ndarray:
            code, output = self._forward_batch(batch)
            assert output is not None, "decoded by default"
            outputs.append(output)
            return code

        codes = self._in_batches(images, batch_size, code_keeping_output, progress, f"{self.name} code and output")
        return codes, np.concatenate(outputs)

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
