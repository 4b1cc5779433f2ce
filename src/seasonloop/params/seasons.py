"""Traverses (the seasons of the study, or any named run along the route), the study's test pairs,
and the checks on traverse names and pairs.

A traverse may have any name that can be a file name (Gardens Point's day_left, a RobotCar date
2014-12-09-13-21-02, ...): it names files and the rows and columns of every table. The four seasons
are the synthetic route's traverses and the keys of the study's own numbers. A pair has its
database from one traverse and its queries from another: [database, query] in params, or the
string "database-query", split at the one hyphen that leaves two traverses of data.seasons. Every
check names the params key it checks in its error.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from typing import Any

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

# not in a traverse name: path separators and NUL (it names files), and the separators of result
# names ("<pair>@<metric>+seq", seasonloop.evaluation.matchers.result_suffix)
FORBIDDEN_CHARACTERS = "/\\\0@+"
MAX_NAME_LENGTH = 100


def check_name(name: Any, key: str) -> str:
    """`name` if it can name a traverse (a file name: 1 to MAX_NAME_LENGTH printable characters, not
    starting with '.' or '-', no FORBIDDEN_CHARACTERS, no surrounding spaces), else a ValueError naming `key`."""
    if not isinstance(name, str):
        raise ValueError(
            f"{key}: {name!r} is not a traverse name (YAML read it as {type(name).__name__}: put it in quotes)"
        )
    if (
        not name
        or len(name) > MAX_NAME_LENGTH
        or name.strip() != name
        or name.startswith((".", "-"))
        or not name.isprintable()
        or any(character in FORBIDDEN_CHARACTERS for character in name)
    ):
        raise ValueError(
            f"{key}: '{name}' cannot name a traverse (it names files: 1 to {MAX_NAME_LENGTH} printable "
            f"characters, not starting with '.' or '-', without / \\ @ + or surrounding spaces)"
        )
    return name


def check_seasons(seasons: Any, key: str, allowed: Collection[str] | None = None) -> list[str]:
    """`seasons` as a list of traverse names, or a ValueError naming `key` for a bad, unknown
    (not in `allowed`, when given), repeated or empty list."""
    if isinstance(seasons, str) or not isinstance(seasons, Sequence) or len(seasons) == 0:
        raise ValueError(f"{key}: expected a non-empty list of traverses, got {seasons!r}")
    for season in seasons:
        check_name(season, key)
        if allowed is not None and season not in allowed:
            raise ValueError(f"{key}: unknown traverse '{season}' (known: {', '.join(allowed)})")
    if len(set(seasons)) != len(seasons):
        raise ValueError(f"{key}: repeated traverse in {list(seasons)}")
    return list(seasons)


def pair_name(database: str, query: str) -> str:
    """The pair's name in file names and tables: "database-query"."""
    return f"{database}-{query}"


def _splits(name: str) -> list[tuple[str, str]]:
    return [(name[:i], name[i + 1 :]) for i, character in enumerate(name) if character == "-"]


def parse_pair(value: Any, key: str = "pair", known: Collection[str] | None = None) -> tuple[str, str]:
    """(database, query) of a pair given as [database, query] or as "database-query".

    A string is split at its hyphen; with several (a hyphen inside a name), at the one hyphen that
    leaves two traverses of `known` (data.seasons); one that is split either no way or several ways
    is an error asking for the list form. Raises a ValueError naming `key`."""
    if isinstance(value, (list, tuple)):
        if len(value) != 2:
            raise ValueError(f"{key}: a pair is [database, query], got {list(value)!r}")
        database, query = (check_name(name, key) for name in value)
    elif isinstance(value, str):
        splits = _splits(value)
        matches = [split for split in splits if known is not None and split[0] in known and split[1] in known]
        if len(matches) > 1:
            ways = " or ".join(f"[{a}, {b}]" for a, b in matches)
            raise ValueError(
                f"{key}: '{value}' names two traverses of data.seasons in {len(matches)} ways: write {ways}"
            )
        if matches:
            database, query = matches[0]
        elif len(splits) == 1:
            database, query = (check_name(name, key) for name in splits[0])
        else:
            raise ValueError(
                f"{key}: '{value}' is not <database>-<query> with one hyphen between two traverses"
                + (" of data.seasons" if known is not None and splits else "")
                + ": write it as [database, query]"
            )
    else:
        raise ValueError(f"{key}: expected a pair such as summer-fall or [database, query], got {value!r}")
    if database == query:
        raise ValueError(f"{key}: a pair needs two traverses, got {database!r} twice")
    return database, query


def available_pairs(seasons: Sequence[str], pairs: Sequence[Any], key: str = "evaluate.pairs") -> list[tuple[str, str]]:
    """The pairs whose two traverses are both in `seasons`, in order; two pairs whose names would be
    one file name (a-b + c and a + b-c) are an error."""
    chosen = [parse_pair(value, key, known=seasons) for value in pairs]
    present = [(a, b) for a, b in chosen if a in seasons and b in seasons]
    names: dict[str, tuple[str, str]] = {}
    for pair in present:
        other = names.setdefault(pair_name(*pair), pair)
        if other != pair:
            raise ValueError(f"{key}: {list(other)} and {list(pair)} would share the name {pair_name(*pair)}")
    return present


def pair_present(
    name: Any, seasons: Sequence[str], pairs: Sequence[Any], key: str
) -> tuple[tuple[str, str], str | None]:
    """The pair `name` (checked, named by `key`) if both its traverses are in `seasons`, else the
    first of `pairs` that is (else the first two traverses), with a one-line note saying so (None
    if kept)."""
    database, query = parse_pair(name, key, known=seasons)
    if database in seasons and query in seasons:
        return (database, query), None
    if len(seasons) < 2:
        raise ValueError(f"{key}: a pair needs two traverses and data.seasons has only {list(seasons)}")
    present = available_pairs(seasons, pairs)
    chosen = present[0] if present else (seasons[0], seasons[1])
    return (
        chosen,
        f"{key} {pair_name(database, query)} needs a traverse not in data.seasons: using {pair_name(*chosen)}",
    )


# Keys that name traverses, and how: "list" of names, "lists" of them, "pair", "pairs", "map" keys.
TRAVERSE_KEYS: dict[str, str] = {
    "data.seasons": "seasons",
    "data.video_files": "map",
    "data.offsets": "map",
    "train.seasons": "list",
    "evaluate.pairs": "pairs",
    "ablation.pair": "pair",
    "ablation.training_seasons": "lists",
    "report.example_pair": "pair",
    "cae_widths.pairs": "pairs",
}


def check_traverses(key: str, value: Any, params: Mapping[str, Any]) -> None:
    """Every traverse `key` names is one of data.seasons or one of the study's four seasons (whose
    pairs are skipped where data.seasons lacks them): a typo is an error, not a silently skipped pair.
    With source synthetic, data.seasons itself must be seasons of the synthetic route."""
    data = params.get("data")
    if not isinstance(data, Mapping):
        return
    try:
        known = check_seasons(data["seasons"], "data.seasons")
    except (KeyError, ValueError):
        return  # data.seasons is checked (and fails) where it is read
    if key == "data.seasons":
        if data.get("source") == "synthetic":
            check_seasons(value, key, allowed=SEASONS)
        return
    kind = TRAVERSE_KEYS[key]
    names = {
        "map": lambda: list(value),
        "list": lambda: list(value),
        "lists": lambda: [name for names in value for name in names],
        "pair": lambda: list(parse_pair(value, key, known=known)),
        "pairs": lambda: [name for entry in value for name in parse_pair(entry, key, known=known)],
    }[kind]()
    allowed = list(dict.fromkeys([*known, *SEASONS]))
    for name in names:
        if name not in allowed:
            raise ValueError(f"{key}: unknown traverse '{name}' (data.seasons: {', '.join(known)})")
