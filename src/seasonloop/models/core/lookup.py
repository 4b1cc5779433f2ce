"""A learner's class from its name, by its module alone: learner <name> is the FeatureLearner
subclass of seasonloop.models.<name> whose `name` is <name>.

The stages that fit, describe with or draw a learner find it here, so they depend (dvc.yaml) on its
module and models/core only: adding a learner (its module and its params section) reruns none of
the other learners' stages. The name is checked against the registry (the package's modules) as
params.yaml's checks read it (seasonloop.params.registries: not a stage's dep).
"""

from __future__ import annotations

import importlib
from pathlib import Path

from seasonloop.models.core.learner import FeatureLearner, read_learner_record
from seasonloop.params.registries import known_learner


def get_learner(name: str) -> type[FeatureLearner]:
    """The class of learner `name`, importing its module (and only it)."""
    dotted = f"seasonloop.models.{known_learner(name)}"
    try:
        module = importlib.import_module(dotted)
    except ModuleNotFoundError as missing:
        if missing.name != dotted:  # the learner's module is there; something it imports is not
            raise
        raise ValueError(f"no learner '{name}': there is no module {dotted}") from None
    found = [
        value
        for value in vars(module).values()
        if isinstance(value, type)
        and issubclass(value, FeatureLearner)
        and value.__module__ == module.__name__
        and getattr(value, "name", None) == name
    ]
    if len(found) != 1:
        raise ValueError(f"{module.__name__}: expected one FeatureLearner subclass named '{name}', found {len(found)}")
    return found[0]


def load_learner(directory: Path) -> FeatureLearner:
    """Load a saved learner of any kind from its directory."""
    return get_learner(read_learner_record(directory)["name"]).load(directory)
