"""Checks across sections of params.yaml that no one section can make (run by schema.check_whole)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from seasonloop.params.seasons import parse_pair


def check_across(params: Mapping[str, Any]) -> None:
    """Every check of this module on a whole, section-checked params.yaml."""
    check_whole_route(params)
    check_sampled_sequences(params)


def check_whole_route(params: Mapping[str, Any]) -> None:
    """split.test_fraction 1 tests every place and trains on every place: a season that is both
    trained on and evaluated would be matched against images the learner was fitted on."""
    if params["split"]["test_fraction"] != 1:
        return
    seasons = list(params["data"]["seasons"])

    def evaluated(pairs: Sequence[Any]) -> set[str]:
        # a pair not both in data.seasons is skipped, so not evaluated
        parsed = [parse_pair(entry, "evaluate.pairs", seasons) for entry in pairs]
        return {season for pair in parsed if set(pair) <= set(seasons) for season in pair}

    fits = [("train.seasons", params["train"]["seasons"], evaluated(params["evaluate"]["pairs"]))]
    fits.append(("train.seasons", params["train"]["seasons"], evaluated([params["report"]["example_pair"]])))
    if params["cae_widths"]["widths"]:
        fits.append(("train.seasons", params["train"]["seasons"], evaluated(params["cae_widths"]["pairs"])))
    if params["ablation"]["methods"]:
        tested = evaluated([params["ablation"]["pair"]])
        fits += [("ablation.training_seasons", listed, tested) for listed in params["ablation"]["training_seasons"]]
    for key, trained, tested in fits:
        both = sorted(set(trained) & tested)
        if both:
            raise ValueError(
                f"{key}: {', '.join(both)} is also evaluated, and split.test_fraction 1 trains on every place "
                "(the learners would see the test images); train on other seasons"
            )


def check_sampled_sequences(params: Mapping[str, Any]) -> None:
    """SeqSLAM needs consecutive places; split.test_every leaves gaps of k places between tests."""
    sampled = {season: k for season, k in params["split"]["test_every"].items() if k > 1}
    if sampled and "sequence" in params["evaluate"]["matchers"]:
        season, k = next(iter(sampled.items()))
        raise ValueError(
            f"split.test_every.{season}: every {k}th place leaves no sequence to match; set evaluate.matchers: [single]"
        )
