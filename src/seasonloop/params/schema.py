"""params.yaml checked whole before any stage works: every section (its keys and checks are declared
with the sections, seasonloop.params.settings), the top-level values, every learner section (checked
against the params its class declares, seasonloop.params.registries) and the checks across sections. Seasons and pairs are in seasonloop.params.seasons, the checks of one value
in seasonloop.params.checks, the names choices may take in the library's registries
(seasonloop.params.registries) or, where no registry holds them, seasonloop.params.choices.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from seasonloop.params.across import check_across
from seasonloop.params.checks import Check, integer, list_of
from seasonloop.params.registries import LEARNERS, check_learner_section, names, registered
from seasonloop.params.seasons import TRAVERSE_KEYS, check_traverses
from seasonloop.params.section_checks import SECTION_CHECKS
from seasonloop.params.settings import SCHEMA

# Top-level keys that are values, not sections.
TOP_LEVEL: dict[str, Check] = {"seed": integer(0), "learners": list_of(registered(LEARNERS))}


def check_params(params: Mapping[str, Any], keys: Sequence[str]) -> None:
    """Check the top-level keys of `params`, then each of `keys` ("split", or one key as "data.seasons").

    Raises a ValueError naming the first unknown, missing or out-of-range key. Learner sections
    are left to the learner classes, which reject unknown keys and bad values.
    """
    learners = names(LEARNERS)
    for name in params:
        if name not in SCHEMA and name not in TOP_LEVEL and name not in learners:
            raise ValueError(f"params.yaml: unknown key '{name}'")
    for key in keys:
        section_name, _, sub = key.partition(".")
        if section_name in learners:
            continue
        if section_name in TOP_LEVEL:
            if section_name not in params:
                raise ValueError(f"params.yaml: missing key '{section_name}'")
            TOP_LEVEL[section_name](section_name, params[section_name])
            continue
        if section_name not in SCHEMA:
            raise ValueError(f"params.yaml: unknown key '{key}'")
        schema = SCHEMA[section_name]
        section = params.get(section_name)
        if not isinstance(section, Mapping):
            raise ValueError(f"params.yaml: missing section '{section_name}'")
        if sub:
            if sub not in schema:
                raise ValueError(f"params.yaml: unknown key '{key}'")
            checked = [sub]
        else:
            unknown = [name for name in section if name not in schema]
            if unknown:
                raise ValueError(f"{section_name}.{unknown[0]}: unknown key (known: {', '.join(schema)})")
            checked = list(schema)
        for name in checked:
            if name not in section:
                raise ValueError(f"params.yaml: missing key '{section_name}.{name}'")
            schema[name](f"{section_name}.{name}", section[name])
            if f"{section_name}.{name}" in TRAVERSE_KEYS:
                check_traverses(f"{section_name}.{name}", section[name], params)
        if not sub and section_name in SECTION_CHECKS:
            SECTION_CHECKS[section_name](section)


def check_whole(params: Mapping[str, Any]) -> None:
    """Check all of params.yaml before any stage works: every section of the schema whole, the
    top-level values and every learner section (a typo anywhere stops the first stage that runs,
    not the stage that reads it), then the checks across sections. Raises a ValueError naming the
    first bad key."""
    check_params(params, [*TOP_LEVEL, *SCHEMA])
    for name in names(LEARNERS):
        if name in params:
            check_learner_section(name, params[name])
    check_across(params)
