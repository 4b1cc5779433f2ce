"""What a params.yaml section is: a frozen dataclass whose fields are its keys, each declared with
the check its value must pass (`setting`), and which checks and builds itself from params.yaml
(`from_params`). The sections themselves are in seasonloop.params.settings.

    split = SplitConfig.from_params(params)      # checks params["split"], then builds
    make_split(n_places, split, ...)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import Any, ClassVar, TypeVar

from seasonloop.params.checks import Check
from seasonloop.params.seasons import TRAVERSE_KEYS, check_traverses
from seasonloop.params.section_checks import SECTION_CHECKS


def setting(check: Check) -> Any:
    """A section field whose value must pass `check` (read into the schema)."""
    return field(metadata={"check": check})


SectionT = TypeVar("SectionT", bound="Section")


def _frozen(value: Any) -> Any:
    """Lists (and lists of lists) as tuples; mappings as plain dicts of frozen values."""
    if isinstance(value, Mapping):
        return {key: _frozen(entry) for key, entry in value.items()}
    if isinstance(value, (list, tuple)):
        return tuple(_frozen(entry) for entry in value)
    return value


@dataclass(frozen=True)
class Section:
    """Base of the typed sections; `NAME` is the params.yaml section a subclass reads."""

    NAME: ClassVar[str]

    @classmethod
    def checks(cls) -> dict[str, Check]:
        """The section's keys and the check of each, in declaration order."""
        return {entry.name: entry.metadata["check"] for entry in fields(cls)}

    @classmethod
    def check(cls, params: Mapping[str, Any], key: str = "") -> None:
        """Check section NAME of `params` whole (every key present, none unknown, then the checks
        across its keys), or only its `key`; a ValueError names the first bad key."""
        checks = cls.checks()
        section = params.get(cls.NAME)
        if not isinstance(section, Mapping):
            raise ValueError(f"params.yaml: missing section '{cls.NAME}'")
        if key:
            if key not in checks:
                raise ValueError(f"params.yaml: unknown key '{cls.NAME}.{key}'")
        else:
            unknown = [name for name in section if name not in checks]
            if unknown:
                raise ValueError(f"{cls.NAME}.{unknown[0]}: unknown key (known: {', '.join(checks)})")
        for name in [key] if key else checks:
            dotted = f"{cls.NAME}.{name}"
            if name not in section:
                raise ValueError(f"params.yaml: missing key '{dotted}'")
            checks[name](dotted, section[name])
            if dotted in TRAVERSE_KEYS:
                check_traverses(dotted, section[name], params)
        if not key and cls.NAME in SECTION_CHECKS:
            SECTION_CHECKS[cls.NAME](section)

    @classmethod
    def from_params(cls: type[SectionT], params: Mapping[str, Any]) -> SectionT:
        """Check section `NAME` of `params` (a bad key raises a ValueError that names it), then build
        the dataclass from it."""
        cls.check(params)
        section = params[cls.NAME]
        return cls(**{entry.name: _frozen(section[entry.name]) for entry in fields(cls)})

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        return tuple(entry.name for entry in fields(cls))
