"""params.yaml checked whole, against the library's registries: which keys choose among which
registry's names (CHOICES), every learner's section against the params its class declares, and a
top-level key that is neither a section nor a value must be a learner's section.

It sits above every package whose registry it reads, so params/ (the ground floor) knows no
registry: a key there that names a registry entry is declared as text (seasonloop.params.settings)
and checked here. A check only stops a stage, it never shapes what a stage writes, so a stage
depends (dvc.yaml) on a registry's module where it uses it, not because this check reads its names
(tests/test_stage_deps.py does not follow this package).
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from typing import Any

from seasonloop.data.ground_truth_kinds import TRUTH_KINDS
from seasonloop.data.preprocess import CONTRASTS
from seasonloop.data.sources import SOURCES
from seasonloop.evaluation.distances import CONFIDENCES, DISTANCES
from seasonloop.evaluation.matchers import MATCHER_REGISTRY
from seasonloop.models.core.lookup import LEARNERS, get_learner
from seasonloop.params import schema
from seasonloop.params.across import check_across
from seasonloop.params.settings import SCHEMA

# key -> the names its value (or each entry of its list) must be one of
CHOICES: dict[str, Collection[str]] = {
    "data.source": SOURCES,
    "data.ground_truth": TRUTH_KINDS,
    "preprocess.contrast": CONTRASTS,
    "evaluate.metric": DISTANCES,
    "evaluate.extra_metrics": DISTANCES,
    "evaluate.confidence": CONFIDENCES,
    "evaluate.matchers": MATCHER_REGISTRY,
    "learners": LEARNERS,
    "ablation.learners": LEARNERS,
}


def value_of(params: Mapping[str, Any], key: str) -> Any:
    """params' value at dotted `key` (checked present by schema.check_params)."""
    value: Any = params
    for part in key.split("."):
        value = value[part]
    return value


def check_choice(params: Mapping[str, Any], key: str) -> None:
    """The value of choice `key` (a name, or a list of names) is among its registry's names."""
    value = value_of(params, key)
    known = tuple(CHOICES[key])
    for name in value if isinstance(value, (list, tuple)) else [value]:
        if name not in known:
            raise ValueError(f"{key}: unknown value {name!r} (known: {', '.join(known)})")


def check_params(params: Mapping[str, Any], keys: Sequence[str]) -> None:
    """Check each of `keys` of `params` (a section, one key of one, a top-level value or a learner's
    section), the choices among them against their registries; a ValueError names the first bad
    key."""
    schema.check_params(params, [key for key in keys if key.partition(".")[0] not in LEARNERS])
    for key in keys:
        if key in LEARNERS:
            get_learner(key).check_params(params.get(key) or {})
            continue
        for choice in CHOICES:
            if choice == key or choice.startswith(f"{key}."):
                check_choice(params, choice)


def check_whole(params: Mapping[str, Any]) -> None:
    """Check all of params.yaml before any stage works: no unknown top-level key, every section and
    value whole, every choice, every learner section present (a typo anywhere stops the first stage
    that runs, not the stage that reads it), then the checks across sections."""
    for name in params:
        if name not in SCHEMA and name not in schema.TOP_LEVEL and name not in LEARNERS:
            raise ValueError(f"params.yaml: unknown key '{name}'")
    check_params(params, [*schema.TOP_LEVEL, *SCHEMA, *(name for name in LEARNERS if name in params)])
    check_across(params)
