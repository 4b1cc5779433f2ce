"""Tests for seasonloop.reporting.across_runs: two runs of the same queries, each learner against
itself, with the pipeline's paired test."""

from __future__ import annotations

import numpy as np
import pytest

from seasonloop.params.settings import StatisticsConfig
from seasonloop.reporting.across_runs import runs_against, runs_against_markdown
from seasonloop.significance.tables import table_verdicts

SETTINGS = StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05)
VARIANTS = [("cosine", "single", ""), ("cosine", "sequence", "+seq")]
PLACES = np.arange(400)


def reader(correct: dict[tuple[str, str], np.ndarray], places: np.ndarray = PLACES):
    """A run's outcomes: (learner, suffix) -> correct on every query of every pair."""
    return lambda learner, pair, suffix: (places, correct[(learner, suffix)])


def outcomes(rate: float, seed: int) -> np.ndarray:
    # runs along the route: blocks of 8 queries share one outcome
    return np.repeat(np.random.default_rng(seed).random(PLACES.size // 8) < rate, 8)


def test_each_learner_is_compared_with_itself_in_the_other_run_as_the_paired_test_says():
    here = {("ica", ""): outcomes(0.8, 0), ("ica", "+seq"): outcomes(0.9, 1), ("pca", ""): outcomes(0.5, 2)}
    here[("pca", "+seq")] = outcomes(0.6, 3)
    elsewhere = {key: value.copy() for key, value in here.items()}
    elsewhere[("ica", "")] = outcomes(0.2, 4)  # a large drop: found
    record = runs_against(
        {"here": reader(here), "elsewhere": reader(elsewhere)}, ["ica", "pca"], VARIANTS, ["winter-summer"], SETTINGS
    )
    single = record["pairs"]["winter-summer"]["runs"]
    assert [(row["first"], row["second"]) for row in single] == [
        ("ica (here)", "ica (elsewhere)"),
        ("pca (here)", "pca (elsewhere)"),
    ]
    # the same numbers as the compare stage's table of these two comparisons
    expected = table_verdicts([(here[(learner, "")], elsewhere[(learner, "")]) for learner in ("ica", "pca")], SETTINGS)
    assert [row["difference"] for row in single] == [row["difference"] for row in expected]
    assert [row["verdict"] for row in single] == ["better", "no difference"]
    assert single[1]["difference"] == 0.0
    markdown = runs_against_markdown(record)
    assert record["order"]["tables"] == ["runs", "runs+seq"]
    assert (
        "| learner | winter-summer | winter-summer+seq |" in markdown
        and "| ica | " in markdown
        and "▲ [+" in markdown
        and "Each learner here against itself elsewhere" in markdown
    )


def test_runs_of_other_queries_are_refused():
    here = {(learner, suffix): outcomes(0.5, 0) for learner in ("ica",) for _, _, suffix in VARIANTS}
    other = reader(here, PLACES + 1)
    with pytest.raises(ValueError, match="its queries are not those of"):
        runs_against({"here": reader(here), "elsewhere": other}, ["ica"], VARIANTS, ["winter-summer"], SETTINGS)
    with pytest.raises(ValueError, match="compare two runs, not 1"):
        runs_against({"here": reader(here)}, ["ica"], VARIANTS, ["winter-summer"], SETTINGS)
