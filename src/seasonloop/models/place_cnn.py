"""A small convolutional network trained with place labels, the field's way of learning a place
(GSV-Cities, MixVPR): its descriptor, a GeM-pooled and L2-normalised vector, is trained so that
images of one training place in other traverses lie close (the multi-similarity loss over P places
x K images a batch), until recall@1 of held-out training places across traverses plateaus."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from seasonloop.models.core.learner import EpochCallback
from seasonloop.models.core.torch_learner import TorchLearner
from seasonloop.params.checks import integer, list_of, number, one_of

if TYPE_CHECKING:
    from torch import nn


# how the first layer halves the image for the second: pool (its convolution at full size, then a
# 2x2 max pool, as between the later layers) | stride (its convolution strides by 2: a quarter of
# its positions; an epoch 2.1 s against 2.7 at the default widths, validation recall lower:
# benchmarks/studies/choose_place_cnn.py)
FIRST_DOWNSAMPLING = ("pool", "stride")


class PlaceCNN(TorchLearner):
    """Convolutions (3x3, batch norm, ReLU; a 2x2 max pool between two, or the first strided:
    first_downsampling), GeM pooling of the last channels, a linear layer to `dim`, L2-normalised."""

    name = "place_cnn"
    channels_last = True  # oneDNN's NHWC convolutions and pooling: 1.5x faster a batch here (benchmarks.md)
    min_traverses = 2  # a place seen in two conditions at least: what the loss learns from
    TINY_RUN = {"channels": [4, 8], "dim": 16, "max_epochs": 2}
    LIBRARIES = (*TorchLearner.LIBRARIES, "pytorch_metric_learning", "seasonloop.models.core.place_training")
    PARAMS = {
        "channels": list_of(integer(1), unique=False),
        "dim": integer(1),
        "first_downsampling": one_of(*FIRST_DOWNSAMPLING),
        "gem_p": number(1, None),
        "images_per_place": integer(2),
        "loss_alpha": number(0, None, low_open=True),
        "loss_beta": number(0, None, low_open=True),
        "loss_base": number(-1, 1),
        "miner_epsilon": number(0, None),
        **TorchLearner.PARAMS,
    }

    def _validate_params(self) -> None:
        if self.params["first_downsampling"] == "stride" and len(self.params["channels"]) < 2:
            raise ValueError(
                f"{self._key('first_downsampling')} = stride: the first layer strides instead of the pool before "
                f"the second, and {self._key('channels')} has one layer"
            )
        if self.params["batch_size"] < 2 * self.params["images_per_place"]:
            raise ValueError(
                f"{self._key('batch_size')} = {self.params['batch_size']}: a batch needs two places or more of "
                f"{self._key('images_per_place')} = {self.params['images_per_place']} images"
            )

    def _check_image_size(self, height: int, width: int) -> None:
        pooled = 2 ** (len(self.params["channels"]) - 1)
        if height % pooled or width % pooled:
            raise ValueError(
                f"{self._key('channels')}: {len(self.params['channels'])} layers pool by {pooled}, which does not "
                f"divide the image size {height}x{width}"
            )

    def _build_model(self, height: int, width: int) -> nn.Module:
        from torch import nn

        from seasonloop.models.core.place_training import GeM, L2Normalised

        layers: list[nn.Module] = []
        before = 1
        widths = self.params["channels"]
        strided = self.params["first_downsampling"] == "stride"
        for index, channels in enumerate(widths):
            if index and not (index == 1 and strided):
                layers.append(nn.MaxPool2d(2))
            stride = 2 if index == 0 and strided else 1
            layers += [nn.Conv2d(before, channels, 3, stride=stride, padding=1), nn.BatchNorm2d(channels), nn.ReLU()]
            before = channels
        head = [GeM(self.params["gem_p"]), nn.Linear(before, self.params["dim"]), L2Normalised()]
        return nn.Sequential(*layers, *head)

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        from seasonloop.models.core.place_training import PlaceLoss, train_on_places
        from seasonloop.models.core.training import deterministic_algorithms

        traverses = np.unique(self.train_traverses)
        if len(traverses) < self.min_traverses:
            raise ValueError(
                f"{self.name}: every training image is of one traverse (train.seasons): place supervision needs "
                "places seen in two traverses or more"
            )
        self._check_image_size(*self.image_shape)
        device, arithmetic = self._start_fit()
        train, validation, split_info = self._split_validation()
        self.model = self._seeded_model()
        places, loss = (
            self.train_places,
            PlaceLoss(
                self.params["loss_alpha"],
                self.params["loss_beta"],
                self.params["loss_base"],
                self.params["miner_epsilon"],
            ),
        )
        with deterministic_algorithms(device):
            result = train_on_places(
                self.model,
                (images[train], places[train]),
                (images[validation], places[validation], self.train_traverses[validation]),
                self.params["images_per_place"],
                loss,
                self._training_config(),
                device=device,
                dtype=self._dtype,
                memory_format=self._memory_format(),
                progress=progress,
                on_epoch=on_epoch,
                description=self.name,
            )
        info = result.info()
        return {
            **split_info,
            **info,
            "best_validation_recall": 1.0 - info["best_validation_loss"],
            "n_traverses": len(traverses),
            **arithmetic,
            "n_parameters": self._n_parameters(),
        }

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        from seasonloop.models.core.place_training import describe_in_batches

        assert self._dtype is not None, "set with the network, by fit or load"
        device = next(self.network.parameters()).device
        return describe_in_batches(self.network, images, len(images), device, self._dtype)
