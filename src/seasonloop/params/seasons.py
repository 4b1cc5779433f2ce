"""The four seasons of the route, the study's test pairs, and the checks on season and pair names.

A pair "A-B" has its database from season A and its queries from season B. Every check names the
params key it checks in its error.
"""

from __future__ import annotations

from collections.abc import Sequence

SEASONS: tuple[str, ...] = ("summer", "spring", "fall", "winter")

# The study's six test pairs (its Table 4): "A-B" = database from season A, queries from season B.
STUDY_PAIRS: tuple[tuple[str, str], ...] = (
    ("summer", "fall"),
    ("summer", "spring"),
    ("spring", "fall"),
    ("winter", "summer"),
    ("winter", "fall"),
    ("winter", "spring"),
)


def check_seasons(seasons: Sequence[str], key: str, allowed: Sequence[str] = SEASONS) -> list[str]:
    """Return `seasons` as a list, or raise naming `key` for an unknown, repeated or empty list."""
    if isinstance(seasons, str) or not isinstance(seasons, Sequence) or len(seasons) == 0:
        raise ValueError(f"{key}: expected a non-empty list of seasons, got {seasons!r}")
    for season in seasons:
        if season not in allowed:
            raise ValueError(f"{key}: unknown season '{season}' (known: {', '.join(allowed)})")
    if len(set(seasons)) != len(seasons):
        raise ValueError(f"{key}: repeated season in {list(seasons)}")
    return list(seasons)


def pair_name(database: str, query: str) -> str:
    return f"{database}-{query}"


def parse_pair(name: str, key: str = "pair") -> tuple[str, str]:
    parts = name.split("-")
    if len(parts) != 2:
        raise ValueError(f"{key}: '{name}' is not of the form <database season>-<query season>")
    check_seasons(parts, key)
    return parts[0], parts[1]


def available_pairs(seasons: Sequence[str], pairs: Sequence[str]) -> list[tuple[str, str]]:
    """The pairs (given as 'A-B' names) whose two seasons are both in `seasons`, in order."""
    chosen = [parse_pair(name, "evaluate.pairs") for name in pairs]
    return [(a, b) for a, b in chosen if a in seasons and b in seasons]


def pair_present(
    name: str, seasons: Sequence[str], pairs: Sequence[str], key: str
) -> tuple[tuple[str, str], str | None]:
    """The pair `name` (checked, named by `key`) if both its seasons are in `seasons`, else the first
    of `pairs` that is (else the first two seasons), with a one-line note saying so (None if kept)."""
    database, query = parse_pair(name, key)
    if database in seasons and query in seasons:
        return (database, query), None
    if len(seasons) < 2:
        raise ValueError(f"{key}: a pair needs two seasons and data.seasons has only {list(seasons)}")
    present = available_pairs(seasons, pairs)
    chosen = present[0] if present else (seasons[0], seasons[1])
    return chosen, f"{key} {name} needs a season not in data.seasons: using {pair_name(*chosen)}"
