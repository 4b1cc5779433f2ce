"""Name -> learner, imported on demand, and loading a saved learner by the name in its learner.json.

Each learner is one module `seasonloop.models.<name>` holding one FeatureLearner subclass, which
declares its params; adding one is that module, one line here and its section in params.yaml. A
stage's work imports only the module it asks for, so a stage that fits `pca` depends (dvc.yaml) on
`models/pca.py` and `models/core/` only; the params check every stage starts with imports each
module to read its declared params (seasonloop.params.registries), which needs no torch or
scikit-learn and shapes no output.
"""

from __future__ import annotations

import importlib
from pathlib import Path

from seasonloop.models.core.learner import FeatureLearner, read_learner_record

# learner name (= its params section and its module under seasonloop.models) -> its class name
LEARNERS: dict[str, str] = {
    "raw_patchnorm": "RawPatchNorm",
    "hog": "HOG",
    "pca": "PCALearner",
    "pca_whiten": "WhitenedPCALearner",
    "ica": "ICALearner",
    "ica_bovw": "ICABoVW",
    "fae": "FullyConnectedAutoEncoder",
    "cae": "ConvolutionalAutoEncoder",
    "precomputed": "PrecomputedDescriptors",
}


def learner_module(name: str) -> str:
    """The dotted module that defines learner `name`."""
    return f"seasonloop.models.{name}"


def get_learner(name: str) -> type[FeatureLearner]:
    """The learner class registered under `name`, importing its module (and only it)."""
    if name not in LEARNERS:
        raise ValueError(f"unknown method '{name}' (known: {', '.join(LEARNERS)})")
    learner: type[FeatureLearner] = getattr(importlib.import_module(learner_module(name)), LEARNERS[name])
    return learner


def load_learner(directory: Path) -> FeatureLearner:
    """Load a saved learner of any kind from its directory."""
    return get_learner(read_learner_record(directory)["name"]).load(directory)
