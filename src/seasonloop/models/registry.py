"""Name -> learner class, and loading a saved learner by the name in its learner.json."""

from __future__ import annotations

from pathlib import Path

from seasonloop.models.base import FeatureLearner, read_learner_record
from seasonloop.models.cae import ConvolutionalAutoEncoder
from seasonloop.models.fae import FullyConnectedAutoEncoder
from seasonloop.models.ica import ICALearner
from seasonloop.models.ica_bovw import ICABoVW
from seasonloop.models.pca import PCALearner
from seasonloop.models.pca_whiten import WhitenedPCALearner
from seasonloop.models.raw_patchnorm import RawPatchNorm

LEARNERS: dict[str, type[FeatureLearner]] = {
    RawPatchNorm.name: RawPatchNorm,
    PCALearner.name: PCALearner,
    WhitenedPCALearner.name: WhitenedPCALearner,
    ICALearner.name: ICALearner,
    ICABoVW.name: ICABoVW,
    FullyConnectedAutoEncoder.name: FullyConnectedAutoEncoder,
    ConvolutionalAutoEncoder.name: ConvolutionalAutoEncoder,
}


def get_learner(name: str) -> type[FeatureLearner]:
    """The learner class registered under `name`."""
    if name not in LEARNERS:
        raise ValueError(f"unknown method '{name}' (known: {', '.join(LEARNERS)})")
    return LEARNERS[name]


def load_learner(directory: Path) -> FeatureLearner:
    """Load a saved learner of any kind from its directory."""
    return get_learner(read_learner_record(directory)["name"]).load(directory)
