"""Checks across sections of params.yaml that no one section can make (run by seasonloop.registries.check_whole)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from seasonloop.params.seasons import parse_pair


def check_across(params: Mapping[str, Any]) -> None:
    """Every check of this module on a whole, section-checked params.yaml."""
    check_whole_route(params)
    check_sampled_sequences(params)
    check_fit_threads(params)


def check_whole_route(params: Mapping[str, Any]) -> None:
    """split.test_fraction 1 tests every place and trains on every place: the learners may train on
    a database traverse (the map a robot has before it drives) but not on a query traverse of an
    evaluated pair, whose images they would then match. (The training-season ablation leaves such
    lists out itself, saying so: seasonloop.ablations.training_seasons.)"""
    if params["split"]["test_fraction"] != 1 or params["train"]["fitted"] == "elsewhere":
        return  # a split's training places are not tested; learners fitted elsewhere train on nothing here
    seasons = list(params["data"]["seasons"])
    evaluated = [
        ("evaluate.pairs", params["evaluate"]["pairs"]),
        ("report.example_pair", [params["report"]["example_pair"]]),
    ]
    if params["cae_widths"]["widths"]:
        evaluated.append(("cae_widths.pairs", params["cae_widths"]["pairs"]))
    tested: dict[str, str] = {}  # query traverse -> the first evaluated pair it is the query of
    for key, pairs in evaluated:
        for database, query in (parse_pair(entry, key, seasons) for entry in pairs):
            # a pair not both in data.seasons is skipped, so not evaluated
            if {database, query} <= set(seasons):
                tested.setdefault(query, f"{database}-{query}")
    seen = sorted(set(params["train"]["seasons"]) & set(tested))
    if seen:
        raise ValueError(
            f"train.seasons: {', '.join(seen)} is the query traverse of {', '.join(tested[q] for q in seen)}, and "
            "split.test_fraction 1 trains on every place (the learners would see the queries); train on the "
            "database traverse (the map) or on other seasons"
        )


def check_sampled_sequences(params: Mapping[str, Any]) -> None:
    """SeqSLAM needs consecutive places; split.test_every leaves gaps of k places between tests."""
    sampled = {season: k for season, k in params["split"]["test_every"].items() if k > 1}
    if sampled and "sequence" in params["evaluate"]["matchers"]:
        season, k = next(iter(sampled.items()))
        raise ValueError(
            f"split.test_every.{season}: every {k}th place leaves no sequence to match; set evaluate.matchers: [single]"
        )


def check_fit_threads(params: Mapping[str, Any]) -> None:
    """Fits at once share the cores: each needs its thread count stated, since a fit's bytes depend on
    it (the libraries' default is every core, which jobs at once would not have)."""
    if params["train"]["jobs"] > 1 and not params["train"]["threads"]:
        raise ValueError(
            f"train.jobs: {params['train']['jobs']} fits at once need train.threads set (a fit's bytes "
            "depend on its threads; e.g. train.threads: 1 with train.jobs: 2 on 2 cores)"
        )
