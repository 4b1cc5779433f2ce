"""The library's registries as params.yaml's checks read them: a choice such as evaluate.metric is
one of the names of the registry that implements it (seasonloop.evaluation.distances.DISTANCES),
and a learner's section is checked against the params its class declares. The registry is the only
list of names; a check reads it when it checks a value, not when params is imported:

- the library imports params (its sections, seasonloop.params.settings), so params cannot import
  the library at its top;
- a check only stops a stage, it never shapes what a stage writes, so a stage depends (dvc.yaml)
  on a registry's module where it uses it, not because its params check reads the names
  (tests/test_stage_deps.py).

A registry is named "module:NAME", NAME a mapping (or tuple) whose keys are the names.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from typing import Any

from seasonloop.params.checks import Check

# the learners' names (each its params section and its module under seasonloop.models), and
# the function that finds a learner's class by its name
LEARNERS = "seasonloop.models.registry:LEARNERS"
LEARNER_LOOKUP = "seasonloop.models.core.lookup:get_learner"

# every registry a check reads (tests/test_config.py resolves each)
READ: set[str] = set()


def registry(where: str) -> Any:
    """The object `where` ("module:NAME") names."""
    module, _, name = where.partition(":")
    return getattr(importlib.import_module(module), name)


def names(where: str) -> tuple[str, ...]:
    """The names registry `where` holds, in its order."""
    return tuple(registry(where))


def registered(where: str) -> Check:
    """A check that a value is one of the names of registry `where`."""
    READ.add(where)

    def check(key: str, value: Any) -> None:
        known = names(where)
        if value not in known:
            raise ValueError(f"{key}: unknown value {value!r} (known: {', '.join(known)})")

    return check


def check_learner_section(name: str, section: Mapping[str, Any]) -> None:
    """Check learner `name`'s params section against the params its class declares (every key
    set: the section holds the only values)."""
    registry(LEARNER_LOOKUP)(name).check_params(section)


def known_learner(name: str) -> str:
    """`name`, if it is a learner's (a stage's argument, checked like params.yaml's `learners`);
    else a ValueError naming the known ones."""
    known = names(LEARNERS)
    if name not in known:
        raise ValueError(f"unknown method '{name}' (known: {', '.join(known)})")
    return name
