"""params.yaml's sections and top-level values checked (the sections' keys and checks are declared
with them, seasonloop.params.settings). What needs the library's
registries (a choice among their names, a learner's section, a top-level key that is a learner's)
is checked above them, by seasonloop.registries, which calls this and the checks across sections
(seasonloop.params.across).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from seasonloop.params.checks import Check, integer, list_of, text
from seasonloop.params.settings import SECTIONS

# Top-level keys that are values, not sections (`learners` names learners: seasonloop.registries).
TOP_LEVEL: dict[str, Check] = {"seed": integer(0), "learners": list_of(text)}
BY_NAME = {section.NAME: section for section in SECTIONS}


def check_params(params: Mapping[str, Any], keys: Sequence[str]) -> None:
    """Check each of `keys` of `params`: a section ("split"), one key of one ("data.seasons") or a
    top-level value ("seed"). Raises a ValueError naming the first unknown, missing or out-of-range
    key."""
    for key in keys:
        section_name, _, sub = key.partition(".")
        if section_name in TOP_LEVEL and not sub:
            if section_name not in params:
                raise ValueError(f"params.yaml: missing key '{section_name}'")
            TOP_LEVEL[section_name](section_name, params[section_name])
        elif section_name in BY_NAME:
            BY_NAME[section_name].check(params, sub)
        else:
            raise ValueError(f"params.yaml: unknown key '{key}'")
