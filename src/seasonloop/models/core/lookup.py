"""The learners params.yaml may name, and a learner's class from its name, by its module alone:
learner <name> is the one FeatureLearner subclass of the module seasonloop.models.<name> whose
`name` is <name>. Adding one is that module and its section in params.yaml (and its name in
`learners:` to run it), nothing here.

The stages that fit, describe with or draw a learner find it here, so they depend (dvc.yaml) on its
module and models/core only: adding a learner (its module and its params section) reruns none of
the other learners' stages. The name is checked against LEARNERS first.
"""

from __future__ import annotations

import importlib
from pathlib import Path

from seasonloop.models.core.learner import LEARNER_FILE, RUN_KEYS, FeatureLearner, read_learner_record

# learner names, sorted: the modules of seasonloop.models (each its params section); the tables
# list a run's learners in the order of params.yaml's `learners:`
LEARNERS: tuple[str, ...] = tuple(
    sorted(path.stem for path in Path(__file__).parents[1].glob("*.py") if path.stem != "__init__")
)


def get_learner(name: str) -> type[FeatureLearner]:
    """The class of learner `name`, importing its module (and only it)."""
    if name not in LEARNERS:
        raise ValueError(f"unknown learner '{name}' (known: {', '.join(LEARNERS)})")
    dotted = f"seasonloop.models.{name}"
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
    """Load a saved learner of any kind from its directory; a model whose params no longer check
    (saved by code older than a key of its section) is one line naming its learner.json."""
    learner_class = get_learner(read_learner_record(directory)["name"])
    try:
        return learner_class.load(directory)
    except ValueError as error:
        raise ValueError(f"{Path(directory) / LEARNER_FILE}: {error} (saved by other code: fit it again)") from None


def load_fitted_elsewhere(models_dir: Path, name: str, image_shape: tuple[int, ...]) -> tuple[FeatureLearner, dict]:
    """Learner `name` as another run fitted it (models_dir/<name>, train.fitted: elsewhere), checked
    to be that learner and to take images of `image_shape`; (the learner, its fit record: the
    model's facts, and None for its run's, RUN_KEYS: that run's time and threads, not this one's)."""
    learner = load_learner(models_dir / name)
    if learner.name != name:
        raise ValueError(f"{models_dir / name}: holds a '{learner.name}' learner, not '{name}' (train.models_dir)")
    if learner.image_shape != tuple(image_shape):
        raise ValueError(
            f"{models_dir / name}: fitted on {learner.image_shape[0]}x{learner.image_shape[1]} images, this run's "
            f"are {image_shape[0]}x{image_shape[1]} (preprocess.height, preprocess.width)"
        )
    assert learner.fit_info is not None, "a loaded learner carries its fit record"
    return learner, {**learner.fit_info, **dict.fromkeys(RUN_KEYS)}
