"""Convolutional auto-encoder of the study's Table 5 ("same" padding throughout)."""

from __future__ import annotations

from torch import nn

from seasonloop.models.core.torch_learner import AutoEncoder, TorchAutoEncoderLearner


def _conv_relu(in_channels: int, out_channels: int, kernel: int) -> list[nn.Module]:
    return [nn.Conv2d(in_channels, out_channels, kernel, padding="same"), nn.ReLU()]


class ConvolutionalAutoEncoder(TorchAutoEncoderLearner):
    """Encoder conv k0 x c0, maxpool 2, conv k1 x c1, conv k2 x c2, maxpool 2; decoder mirrors it with
    nearest up-sampling ("up-pool") and ends in a 1-channel sigmoid conv of output_kernel."""

    name = "cae"
    channels_last = True  # oneDNN convolutions are faster on NHWC activations (bench_autoencoders.py)
    defaults = {
        "channels": [96, 256, 384],
        "kernels": [11, 5, 3],
        "output_kernel": 3,
        **TorchAutoEncoderLearner.COMMON_DEFAULTS,
        # Full-size CAE is ~9 GMAC per 32x64 image forward: train on a subset by default.
        "batch_size": 64,
        "max_train_images": 512,
        "max_validation_images": 128,
    }

    def _check_image_size(self, height: int, width: int) -> None:
        if height % 4 or width % 4:
            raise ValueError(
                f"{self.name}: image height and width must be divisible by 4 (two 2x2 poolings), got {height}x{width}"
            )

    def _build_model(self, height: int, width: int) -> AutoEncoder:
        (c0, c1, c2), (k0, k1, k2) = self.params["channels"], self.params["kernels"]
        encoder = nn.Sequential(
            *_conv_relu(1, c0, k0), nn.MaxPool2d(2), *_conv_relu(c0, c1, k1), *_conv_relu(c1, c2, k2), nn.MaxPool2d(2)
        )
        decoder = nn.Sequential(
            nn.Upsample(scale_factor=2, mode="nearest"),
            *_conv_relu(c2, c2, k2),
            *_conv_relu(c2, c1, k1),
            nn.Upsample(scale_factor=2, mode="nearest"),
            *_conv_relu(c1, c0, k0),
            nn.Conv2d(c0, 1, self.params["output_kernel"], padding="same"),
            nn.Sigmoid(),
        )
        return AutoEncoder(encoder, decoder)
