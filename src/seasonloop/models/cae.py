"""Convolutional auto-encoder of the study's Table 5 ("same" padding throughout)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from seasonloop.models.core.autoencoder_learner import TorchAutoEncoderLearner
from seasonloop.params.checks import integer

if TYPE_CHECKING:
    from seasonloop.models.core.autoencoder_training import AutoEncoder


def three_positive_integers(key: str, value: Any) -> None:
    """The channels or kernels: one positive integer per convolution layer of Table 5."""
    if not isinstance(value, (list, tuple)) or len(value) != 3 or not all(type(v) is int and v >= 1 for v in value):
        raise ValueError(f"{key}: expected a list of 3 positive integers, got {value!r}")


class ConvolutionalAutoEncoder(TorchAutoEncoderLearner):
    """Encoder conv k0 x c0, maxpool 2, conv k1 x c1, conv k2 x c2, maxpool 2; decoder mirrors it with
    nearest up-sampling ("up-pool", each fused with the convolution after it: UpsampledConv2d) and
    ends in a 1-channel sigmoid conv of output_kernel."""

    name = "cae"
    TINY_RUN = {
        "channels": [3, 8, 12],
        "kernels": [5, 3, 3],
        "max_epochs": 1,
        "max_train_images": 64,
        "max_validation_images": 16,
    }
    LIBRARIES = (*TorchAutoEncoderLearner.LIBRARIES, "seasonloop.models.core.upsampling")
    channels_last = True  # oneDNN convolutions are faster on NHWC activations (bench_autoencoders.py)
    PARAMS = {
        "channels": three_positive_integers,
        "kernels": three_positive_integers,
        "output_kernel": integer(1),
        **TorchAutoEncoderLearner.PARAMS,
    }

    def _check_image_size(self, height: int, width: int) -> None:
        if height % 4 or width % 4:
            raise ValueError(
                f"{self.name}: image height and width must be divisible by 4 (two 2x2 poolings), got {height}x{width}"
            )

    def _build_model(self, height: int, width: int) -> AutoEncoder:
        from torch import nn

        from seasonloop.models.core.autoencoder_training import AutoEncoder
        from seasonloop.models.core.upsampling import UpsampledConv2d

        def _conv_relu(in_channels: int, out_channels: int, kernel: int) -> list[nn.Module]:
            return [nn.Conv2d(in_channels, out_channels, kernel, padding="same"), nn.ReLU()]

        (c0, c1, c2), (k0, k1, k2) = self.params["channels"], self.params["kernels"]
        encoder = nn.Sequential(
            *_conv_relu(1, c0, k0), nn.MaxPool2d(2), *_conv_relu(c0, c1, k1), *_conv_relu(c1, c2, k2), nn.MaxPool2d(2)
        )
        decoder = nn.Sequential(
            UpsampledConv2d(c2, c2, k2),
            nn.ReLU(),
            *_conv_relu(c2, c1, k1),
            UpsampledConv2d(c1, c0, k0),
            nn.ReLU(),
            nn.Conv2d(c0, 1, self.params["output_kernel"], padding="same"),
            nn.Sigmoid(),
        )
        return AutoEncoder(encoder, decoder)
