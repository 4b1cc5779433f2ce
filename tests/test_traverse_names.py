"""Traverses named as the field's datasets name them: any name that can be a file name, hyphens
included, with pairs given as [database, query] or as one string split against data.seasons."""

from __future__ import annotations

import datetime
from pathlib import Path

import pytest
import yaml

from seasonloop.params.seasons import available_pairs, check_name, pair_name, parse_pair
from seasonloop.registries.choices import check_whole

REPO = Path(__file__).resolve().parents[1]
GARDENS_POINT = ["day_left", "day_right", "night_right"]
DATES = ["2014-12-09-13-21-02", "2014-12-16-18-44-24"]


def params_with(**sections) -> dict:
    params = yaml.safe_load((REPO / "params.yaml").read_text())
    for name, values in sections.items():
        params[name].update(values)
    return params


def test_gardens_point_names_and_list_pairs_pass_the_whole_check():
    params = params_with(
        data={"source": "frames", "seasons": GARDENS_POINT},
        train={"seasons": ["day_left", "day_right"]},
        evaluate={"pairs": [["day_left", "night_right"], "day_right-night_right"]},
        ablation={"pair": ["day_left", "night_right"], "training_seasons": [["day_left"], ["day_left", "day_right"]]},
        report={"example_pair": "day_left-night_right"},
        cae_widths={"pairs": [["day_left", "night_right"]]},
    )
    check_whole(params)
    pairs = params["evaluate"]["pairs"]
    assert available_pairs(GARDENS_POINT, pairs) == [("day_left", "night_right"), ("day_right", "night_right")]


def test_a_hyphenated_date_pair_is_split_where_both_halves_are_traverses():
    pair = f"{DATES[0]}-{DATES[1]}"
    assert parse_pair(pair, "evaluate.pairs", known=DATES) == tuple(DATES)
    assert pair_name(*DATES) == pair  # the file name is the same string
    check_whole(params_with(data={"source": "frames", "seasons": DATES}, evaluate={"pairs": [pair]}))
    # without data.seasons to split against, or against other traverses: the list form is asked for
    with pytest.raises(ValueError, match=r"^evaluate\.pairs: .* write it as \[database, query\]$"):
        parse_pair(pair, "evaluate.pairs", known=["summer", "fall"])


def test_a_string_that_splits_two_ways_is_an_error_and_so_are_two_pairs_of_one_name():
    names = ["a-b", "c", "a", "b-c"]
    with pytest.raises(
        ValueError, match=r"'a-b-c' names two traverses of data.seasons in 2 ways: write \[a, b-c\] or \[a-b, c\]"
    ):
        parse_pair("a-b-c", "evaluate.pairs", known=names)
    with pytest.raises(ValueError, match=r"would share the name a-b-c"):
        available_pairs(names, [["a-b", "c"], ["a", "b-c"]])


@pytest.mark.parametrize(
    "name, message",
    [
        ("day/left", "cannot name a traverse"),
        (".hidden", "cannot name a traverse"),
        ("-day", "cannot name a traverse"),
        ("day@left", "cannot name a traverse"),
        ("day+left", "cannot name a traverse"),
        (" day", "cannot name a traverse"),
        ("", "cannot name a traverse"),
        ("x" * 101, "cannot name a traverse"),
        (datetime.date(2014, 12, 9), "YAML read it as date: put it in quotes"),
        (True, "YAML read it as bool"),
    ],
)
def test_a_name_that_cannot_be_a_file_name_is_refused_in_one_line(name, message):
    with pytest.raises(ValueError, match=message) as error:
        check_name(name, "data.seasons")
    assert str(error.value).startswith("data.seasons: ") and "\n" not in str(error.value)
    with pytest.raises(ValueError, match=message):
        check_whole(params_with(data={"source": "frames", "seasons": ["day_left", name]}))


def test_the_synthetic_route_has_the_four_seasons_and_a_typo_is_still_an_error():
    with pytest.raises(
        ValueError, match=r"^data\.seasons: unknown traverse 'day' \(known: summer, spring, fall, winter\)$"
    ):
        check_whole(params_with(data={"seasons": ["summer", "day"]}))
    # the study's pairs are skipped where data.seasons lacks them; another unknown name is a typo
    check_whole(params_with(data={"source": "frames", "seasons": GARDENS_POINT}))
    with pytest.raises(ValueError, match=r"^train\.seasons: unknown traverse 'day_lft' \(data\.seasons: day_left"):
        check_whole(params_with(data={"source": "frames", "seasons": GARDENS_POINT}, train={"seasons": ["day_lft"]}))
    with pytest.raises(ValueError, match=r"a pair needs two traverses, got 'day_left' twice"):
        parse_pair(["day_left", "day_left"], "evaluate.pairs")
