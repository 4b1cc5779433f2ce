"""The auto-encoders' learner: training to their reconstruction's validation plateau, and their
three descriptors (the code, the output, the patch-normalised output), computed in batches.

torch is imported inside the methods that compute (torch_learner.py says why)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from seasonloop.data.patchnorm import patch_normalise
from seasonloop.models.core.learner import EpochCallback, to_float
from seasonloop.models.core.torch_learner import TorchLearner
from seasonloop.params.checks import integer, one_of

if TYPE_CHECKING:
    pass

AE_DESCRIPTORS = ("code", "output", "output_patchnorm")


class TorchAutoEncoderLearner(TorchLearner):
    """Common fit/describe of the auto-encoders; subclasses define the network (_build_model returns
    an autoencoder_training.AutoEncoder)."""

    LIBRARIES: ClassVar[tuple[str, ...]] = (*TorchLearner.LIBRARIES, "seasonloop.models.core.autoencoder_training")
    figures = ("autoencoder",)  # the study's Figure 19: code, output, patch-normalised output

    PARAMS = {**TorchLearner.PARAMS, "descriptor": one_of(*AE_DESCRIPTORS), "patch_size": integer(1)}

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        import torch

        from seasonloop.models.core.autoencoder_training import train_until_plateau
        from seasonloop.models.core.training import deterministic_algorithms

        height, width = self.image_shape
        self._check_image_size(height, width)
        patch_size = self.params["patch_size"]
        if self.params["descriptor"] == "output_patchnorm" and (height % patch_size or width % patch_size):
            raise ValueError(
                f"{self._key('patch_size')} = {patch_size} does not divide the image size {height}x{width}"
            )
        device, arithmetic = self._start_fit()
        train, validation, split_info = self._split_validation()
        self.model = self._seeded_model()
        with deterministic_algorithms(device):
            result = train_until_plateau(
                self.model,
                torch.from_numpy(to_float(images[train])).unsqueeze(1),
                torch.from_numpy(to_float(images[validation])).unsqueeze(1),
                self._training_config(),
                device=device,
                dtype=self._dtype,
                memory_format=self._memory_format(),
                progress=progress,
                on_epoch=on_epoch,
                description=self.name,
            )
        return {**split_info, **result.info(), **arithmetic, "n_parameters": self._n_parameters()}

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
