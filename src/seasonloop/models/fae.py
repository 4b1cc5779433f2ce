"""Fully connected auto-encoder: H*W -> hidden -> H*W, sigmoid output, MSE loss, Adam."""

from __future__ import annotations

from typing import TYPE_CHECKING

from seasonloop.models.core.autoencoder_learner import TorchAutoEncoderLearner
from seasonloop.params.checks import integer, one_of

if TYPE_CHECKING:
    from seasonloop.models.core.autoencoder_training import AutoEncoder

# fae.activation -> the torch.nn module of the hidden layer
ACTIVATIONS = {"sigmoid": "Sigmoid", "relu": "ReLU"}


class FullyConnectedAutoEncoder(TorchAutoEncoderLearner):
    """One hidden layer auto-encoder; descriptor from its code or (patch-normalised) output."""

    name = "fae"
    TINY_RUN = {"hidden": 32, "max_epochs": 2}
    PARAMS = {"hidden": integer(1), "activation": one_of(*ACTIVATIONS), **TorchAutoEncoderLearner.PARAMS}

    def _build_model(self, height: int, width: int) -> AutoEncoder:
        from torch import nn

        from seasonloop.models.core.autoencoder_training import AutoEncoder

        n_pixels, hidden = height * width, self.params["hidden"]
        activation = getattr(nn, ACTIVATIONS[self.params["activation"]])
        encoder = nn.Sequential(nn.Flatten(), nn.Linear(n_pixels, hidden), activation())
        decoder = nn.Sequential(nn.Linear(hidden, n_pixels), nn.Sigmoid(), nn.Unflatten(1, (1, height, width)))
        return AutoEncoder(encoder, decoder)
