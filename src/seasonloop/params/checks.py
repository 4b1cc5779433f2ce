"""The building blocks of the params schema: checks of one value, each naming its dotted key in the error.

seasonloop.params.schema composes them into the schema of every section of params.yaml.
"""

from __future__ import annotations

import numbers
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from seasonloop.params.seasons import check_name, check_seasons, parse_pair

Check = Callable[[str, Any], None]  # (dotted key, value) -> None, or a ValueError naming the key

LATITUDE_NAMES = ("lat", "latitude")
LONGITUDE_NAMES = ("lon", "lng", "long", "longitude")


def _fail(key: str, expected: str, value: Any) -> None:
    raise ValueError(f"{key}: expected {expected}, got {value!r}")


def integer(minimum: int | None = None, maximum: int | None = None) -> Check:
    def check(key: str, value: Any) -> None:
        if (
            isinstance(value, bool)
            or not isinstance(value, numbers.Integral)
            or (minimum is not None and int(value) < minimum)
            or (maximum is not None and int(value) > maximum)
        ):
            _fail(
                key,
                "an integer"
                + (f" >= {minimum}" if minimum is not None else "")
                + (f" <= {maximum}" if maximum is not None else ""),
                value,
            )

    return check


def number(
    low: float | None = None, high: float | None = None, low_open: bool = False, high_open: bool = False
) -> Check:
    def check(key: str, value: Any) -> None:
        # numbers.Real: numpy scalars too (a learner built in code may get them); YAML gives int or float
        ok = not isinstance(value, bool) and isinstance(value, numbers.Real)
        ok = ok and (low is None or (float(value) > low if low_open else float(value) >= low))
        ok = ok and (high is None or (float(value) < high if high_open else float(value) <= high))
        if not ok:
            bounds = (
                ("(" if low_open else "[")
                + f"{low if low is not None else '-inf'}, "
                + f"{high if high is not None else 'inf'}"
                + (")" if high_open or high is None else "]")
            )
            _fail(key, f"a number in {bounds}", value)

    return check


def test_fraction(key: str, value: Any) -> None:
    """split.test_fraction: a share of each section up to a half, or 1 (the whole route tested)."""
    try:
        if value != 1:
            number(0, 0.5, low_open=True)(key, value)
    except ValueError:
        _fail(key, "a number in (0, 0.5] or 1", value)


def boolean(key: str, value: Any) -> None:
    if not isinstance(value, bool):
        _fail(key, "true or false", value)


def text(key: str, value: Any) -> None:
    if not isinstance(value, str) or not value:
        _fail(key, "a non-empty string", value)


def optional_text(key: str, value: Any) -> None:
    if not isinstance(value, str):
        _fail(key, "a string ('' for none)", value)


def one_of(*choices: str) -> Check:
    def check(key: str, value: Any) -> None:
        if value not in choices:
            raise ValueError(f"{key}: unknown value {value!r} (known: {', '.join(choices)})")

    return check


def list_of(item: Check, non_empty: bool = True, unique: bool = True) -> Check:
    def check(key: str, value: Any) -> None:
        if isinstance(value, str) or not isinstance(value, Sequence) or (non_empty and not value):
            _fail(key, "a non-empty list" if non_empty else "a list", value)
        for entry in value:
            item(key, entry)
        if unique and len({repr(entry) for entry in value}) != len(value):
            raise ValueError(f"{key}: repeated entry in {list(value)}")

    return check


def seasons(key: str, value: Any) -> None:
    check_seasons(value, key)


def pair(key: str, value: Any) -> None:
    if isinstance(value, str) and value.count("-") > 1:
        # a hyphen inside a name: split against data.seasons (params.schema's check across keys)
        return
    parse_pair(value, key)


def season_map(item: Check, allowed: Sequence[str] | None = None) -> Check:
    """A mapping of traverse name (one of `allowed`, when given) to a value checked by `item`."""

    def check(key: str, value: Any) -> None:
        if not isinstance(value, Mapping):
            _fail(key, "a mapping of traverse to value", value)
        for season, entry in value.items():
            check_name(season, key)
            if allowed is not None and season not in allowed:
                raise ValueError(f"{key}: unknown season '{season}' (known: {', '.join(allowed)})")
            item(f"{key}.{season}", entry)

    return check


def record(fields: Mapping[str, Check]) -> Check:
    """A mapping holding some of `fields` (each optional), each checked as `<key>.<field>`."""

    def check(key: str, value: Any) -> None:
        if not isinstance(value, Mapping):
            _fail(key, f"a mapping of some of {', '.join(fields)}", value)
        for name, entry in value.items():
            if name not in fields:
                raise ValueError(f"{key}.{name}: unknown key (known: {', '.join(fields)})")
            fields[name](f"{key}.{name}", entry)

    return check


def check_degree_columns(columns: Sequence[str]) -> None:
    """Degrees need their columns named: [latitude, longitude] as lat/latitude and lon/lng/long/
    longitude (generic names such as y, x could hold either, and swapped columns still pass a
    range check near the equator)."""
    names = [str(name).lower() for name in columns]
    if len(names) == 2 and names[0] in LATITUDE_NAMES and names[1] in LONGITUDE_NAMES:
        return
    if len(names) == 2 and names[0] in LONGITUDE_NAMES and names[1] in LATITUDE_NAMES:
        problem = "is longitude first; degrees must be [latitude, longitude]"
    else:
        problem = (
            f"are not named as degrees: name them [latitude, longitude] "
            f"({'/'.join(LATITUDE_NAMES)}, {'/'.join(LONGITUDE_NAMES)})"
        )
    raise ValueError(f"data.position_columns: {list(columns)} {problem}")
