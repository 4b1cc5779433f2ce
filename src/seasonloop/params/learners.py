"""The params of every learner's section, each key with its check: one source for every range and
choice a learner accepts. The whole params.yaml is checked with them before any stage works
(seasonloop.params.schema.check_whole), and each learner class checks its params with the same
checks when it is built (seasonloop.models.core.learner). Checks across keys or against the data
(the ICA solver's algorithms, the CAE's image size, PCA's rank) stay in the learner classes.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from seasonloop.params.checks import Check, integer, number, one_of, text

SVD_SOLVERS = ("auto", "full", "covariance_eigh", "arpack", "randomized")
ICA_ALGORITHMS = ("parallel", "deflation")
ICA_FUNCTIONS = ("logcosh", "exp", "cube")
ICA_PRECISIONS = ("float32", "float64")  # the ICA iterations' arithmetic
KMEANS_KINDS = ("minibatch", "full")
PATCH_NORM_MODES = ("zscore", "minmax")
DEVICES = ("auto", "cpu", "cuda")
PRECISIONS = ("auto", "float32", "bfloat16")
AE_DESCRIPTORS = ("code", "output", "output_patchnorm")
# names of registries that live beside their code (so that this module imports no learner);
# tests/test_config.py keeps each equal to its registry
ICA_SOLVER_NAMES = ("picard", "python_picard", "fastica", "sklearn")  # seasonloop.models.ica.ICA_SOLVERS
WHITEN_SOLVER_NAMES = ("eigh", "svd")  # seasonloop.models.core.torch_ica.WHITEN_SOLVERS
ACTIVATION_NAMES = ("sigmoid", "relu")  # seasonloop.models.fae.ACTIVATIONS

POSITIVE = number(0, None, low_open=True)


def three_positive_integers(key: str, value: Any) -> None:
    """The CAE's channels or kernels: one positive integer per convolution layer of Table 5."""
    if not isinstance(value, (list, tuple)) or len(value) != 3 or not all(type(v) is int and v >= 1 for v in value):
        raise ValueError(f"{key}: expected a list of 3 positive integers, got {value!r}")


TRAINING: dict[str, Check] = {
    "max_epochs": integer(1),
    "batch_size": integer(1),
    "learning_rate": POSITIVE,
    "patience": integer(1),
    "min_delta": number(0, 1, high_open=True),
    "lr_patience": integer(1),
    "lr_factor": number(0, 1, low_open=True, high_open=True),
    "budget_seconds": number(0),
    "validation_fraction": number(0, 1, high_open=True),
    "validation_block": integer(1),
    "max_validation_images": integer(0),
    "precision": one_of(*PRECISIONS),
    "threads": integer(0),
    "descriptor": one_of(*AE_DESCRIPTORS),
    "patch_size": integer(1),
    "device": one_of(*DEVICES),
    "max_train_images": integer(0),
}

PCA: dict[str, Check] = {"n_discard": integer(0), "n_keep": integer(1), "svd_solver": one_of(*SVD_SOLVERS)}

LEARNER_SCHEMA: dict[str, dict[str, Check]] = {
    "raw_patchnorm": {"patch_size": integer(1), "mode": one_of(*PATCH_NORM_MODES)},
    "pca": PCA,
    "pca_whiten": {**PCA, "max_train_images": integer(0)},
    "ica": {
        "n_components": integer(1),
        "algorithm": one_of(*ICA_ALGORITHMS),
        "fun": one_of(*ICA_FUNCTIONS),
        "max_iter": integer(1),
        "tol": POSITIVE,
        "change_tol": POSITIVE,
        "whiten_solver": one_of(*WHITEN_SOLVER_NAMES),
        "max_train_images": integer(0),
        "solver": one_of(*ICA_SOLVER_NAMES),
        "device": one_of(*DEVICES),
        "precision": one_of(*ICA_PRECISIONS),
    },
    "ica_bovw": {
        "patch_size": integer(1),
        "stride": integer(1),
        "n_train_patches": integer(2),
        "n_components": integer(1),
        "n_words": integer(1),
        "kmeans": one_of(*KMEANS_KINDS),
        "max_iter": integer(1),
        "tol": POSITIVE,
    },
    "fae": {"hidden": integer(1), "activation": one_of(*ACTIVATION_NAMES), **TRAINING},
    "cae": {
        "channels": three_positive_integers,
        "kernels": three_positive_integers,
        "output_kernel": integer(1),
        **TRAINING,
    },
    "precomputed": {"dir": text},
}


def check_learner(name: str, params: Mapping[str, Any]) -> None:
    """Check the keys given for learner `name` (a partial section is fine: the learner's defaults fill
    the rest); a ValueError names the first unknown key or bad value."""
    schema = LEARNER_SCHEMA[name]
    if not isinstance(params, Mapping):
        raise ValueError(f"{name}: expected a mapping of the learner's params, got {params!r}")
    for key, value in params.items():
        if key not in schema:
            raise ValueError(f"{name}.{key}: unknown key (known: {', '.join(schema)})")
        schema[key](f"{name}.{key}", value)
