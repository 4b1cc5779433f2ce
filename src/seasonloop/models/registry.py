"""The learners params.yaml may name, in the order the docs and tables list them.

Each learner is one module `seasonloop.models.<name>` holding one FeatureLearner subclass whose
`name` is <name>, which declares its params; adding one is that module, its name here and its
section in params.yaml. The stages find a learner's class by its module alone
(seasonloop.models.core.lookup.get_learner), so a stage that fits `pca` depends (dvc.yaml) on
`models/pca.py` and `models/core/` only, and a new name here reruns no stage's work; the params
check every stage starts with reads these names and each module's declared params
(seasonloop.params.registries), which needs no torch or scikit-learn and shapes no output.
"""

from __future__ import annotations

# learner names (each its params section and its module under seasonloop.models)
LEARNERS: tuple[str, ...] = (
    "raw_patchnorm",
    "hog",
    "pca",
    "pca_whiten",
    "ica",
    "ica_bovw",
    "fae",
    "cae",
    "precomputed",
)
