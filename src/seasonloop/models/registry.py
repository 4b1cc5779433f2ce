"""The learners params.yaml may name: the modules of this package.

Each learner is one module `seasonloop.models.<name>` holding one FeatureLearner subclass whose
`name` is <name>, which declares its params; adding one is that module and its section in
params.yaml (and its name in `learners:` to run it), nothing here. The stages find a learner's
class by its module alone (seasonloop.models.core.lookup.get_learner), so a stage that fits `pca`
depends (dvc.yaml) on `models/pca.py` and `models/core/` only, and a new module reruns no stage's
work; the params check every stage starts with reads these names and each module's declared params
(seasonloop.params.registries), which needs no torch or scikit-learn and shapes no output.
"""

from __future__ import annotations

from pathlib import Path

# learner names, sorted: the modules beside this one (each its params section); the tables list a
# run's learners in the order of params.yaml's `learners:`
LEARNERS: tuple[str, ...] = tuple(
    sorted(path.stem for path in Path(__file__).parent.glob("*.py") if path.stem not in ("__init__", "registry"))
)
