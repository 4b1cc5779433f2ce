"""Fully connected auto-encoder: H*W -> hidden -> H*W, sigmoid output, MSE loss, Adam."""

from __future__ import annotations

from torch import nn

from seasonloop.models.core.torch_learner import AutoEncoder, TorchAutoEncoderLearner

ACTIVATIONS = {"sigmoid": nn.Sigmoid, "relu": nn.ReLU}


class FullyConnectedAutoEncoder(TorchAutoEncoderLearner):
    """One hidden layer auto-encoder; descriptor from its code or (patch-normalised) output."""

    name = "fae"
    defaults = {"hidden": 512, "activation": "relu", **TorchAutoEncoderLearner.COMMON_DEFAULTS}

    def _build_model(self, height: int, width: int) -> AutoEncoder:
        n_pixels, hidden = height * width, self.params["hidden"]
        encoder = nn.Sequential(nn.Flatten(), nn.Linear(n_pixels, hidden), ACTIVATIONS[self.params["activation"]]())
        decoder = nn.Sequential(nn.Linear(hidden, n_pixels), nn.Sigmoid(), nn.Unflatten(1, (1, height, width)))
        return AutoEncoder(encoder, decoder)
