"""Intervals and paired tests (seasonloop.significance) on cases with a known answer, and the
per-query outcomes they are computed from (seasonloop.evaluation.outcomes)."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.stats import binomtest

from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.params.schema import check_whole
from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import (
    block_interval,
    block_resampling,
    fraction_interval,
    percentile_interval,
    resampled_ratios,
    stratified_resampling,
    wilson_interval,
)
from seasonloop.significance.means import mean_interval
from seasonloop.significance.paired import holm, mcnemar_exact, paired_difference, with_verdicts
from seasonloop.significance.tables import comparison_tables, pair_comparisons

SETTINGS = StatisticsConfig(level=0.95, block_length=20, resamples=2000, seed=0, alpha=0.05)


@pytest.mark.parametrize(
    ("successes", "trials", "level"), [(0, 10, 0.95), (7, 10, 0.9), (130, 158, 0.95), (158, 158, 0.99)]
)
def test_wilson_interval_is_scipys(successes, trials, level):
    expected = binomtest(successes, trials).proportion_ci(confidence_level=level, method="wilson")
    assert wilson_interval(successes, trials, level) == pytest.approx((expected.low, expected.high), abs=1e-12)


def test_block_resampling_is_seeded_and_inside_the_route():
    resampling = block_resampling(158, SETTINGS)
    starts = resampling.starts
    assert starts.shape == (2000, 8)  # ceil(158 / 20) blocks
    assert list(resampling.lengths) == [20] * 7 + [18] and resampling.n_queries == 158
    assert starts.min() >= 0 and starts.max() <= 158 - 20
    assert np.array_equal(starts, block_resampling(158, SETTINGS).starts)
    other = StatisticsConfig(level=0.95, block_length=20, resamples=2000, seed=1, alpha=0.05)
    assert not np.array_equal(starts, block_resampling(158, other).starts)
    # a block longer than the route is the whole route
    assert np.array_equal(block_resampling(5, SETTINGS).starts, np.zeros((2000, 1), np.int64))


def test_resampled_ratios_are_the_means_of_the_resampled_queries():
    rng = np.random.default_rng(3)
    values, counted = rng.random(53), rng.random(53) < 0.8
    settings = StatisticsConfig(level=0.95, block_length=7, resamples=50, seed=2, alpha=0.05)
    resampling = block_resampling(53, settings)
    # the resample written out: 8 blocks of 7 consecutive queries, cut to 53
    indices = (resampling.starts[:, :, None] + np.arange(7)).reshape(50, -1)[:, :53]
    expected = (values * counted)[indices].sum(axis=1) / counted[indices].sum(axis=1)
    assert np.allclose(resampled_ratios(values * counted, counted, resampling), expected)
    with pytest.raises(ValueError, match="52 queries, resamples of 53"):
        resampled_ratios(values[:52], counted[:52], resampling)


def test_stratified_resampling_keeps_each_routes_blocks_inside_it():
    settings = StatisticsConfig(level=0.95, block_length=7, resamples=300, seed=2, alpha=0.05)
    resampling = stratified_resampling([(4, 30), (1, 45), (9, 5)], settings)
    assert resampling.n_queries == 80 and resampling.starts.shape == (300, 5 + 7 + 1)
    # every block starts and ends inside one route, and a resample has each route's count of queries
    bounds = np.array([0, 30, 75, 80])
    route_of_start = np.searchsorted(bounds, resampling.starts, side="right") - 1
    route_of_end = np.searchsorted(bounds, resampling.starts + resampling.lengths - 1, side="right") - 1
    assert np.array_equal(route_of_start, route_of_end)
    assert [int(resampling.lengths[route_of_start[0] == route].sum()) for route in range(3)] == [30, 45, 5]
    # a route's resamples are its own generator's, whichever routes come before or after it
    alone = block_resampling(45, settings, seed=[settings.seed, 1])
    assert np.array_equal(resampling.starts[:, 5:12] - 30, alone.starts)
    swapped = stratified_resampling([(1, 45), (4, 30), (9, 5)], settings)
    assert np.array_equal(swapped.starts[:, :7], alone.starts)
    with pytest.raises(ValueError, match="repeat"):
        stratified_resampling([(1, 10), (1, 20)], settings)


def test_an_interval_of_a_constant_is_that_constant():
    starts = block_resampling(100, SETTINGS)
    interval = fraction_interval(np.ones(100, bool), np.ones(100, bool), starts, SETTINGS)
    assert interval["block_bootstrap"] == {"low": 1.0, "high": 1.0}
    assert percentile_interval(np.array([np.nan, np.nan]), 0.95) != percentile_interval(np.array([0.5]), 0.95)


def test_runs_of_outcomes_widen_the_block_interval_beyond_wilsons():
    # 160 queries in runs of 20 (a stretch matched, a stretch missed): 8 independent pieces, not 160
    runs = np.repeat(np.array([1, 0, 1, 1, 0, 1, 0, 1], bool), 20)
    interval = fraction_interval(runs, np.ones(160, bool), block_resampling(160, SETTINGS), SETTINGS)
    block = interval["block_bootstrap"]["high"] - interval["block_bootstrap"]["low"]
    wilson = interval["wilson"]["high"] - interval["wilson"]["low"]
    assert block > 1.5 * wilson
    # independent queries: the two agree (within the bootstrap's own noise)
    independent = np.random.default_rng(0).random(2000) < 0.6
    interval = fraction_interval(independent, np.ones(2000, bool), block_resampling(2000, SETTINGS), SETTINGS)
    block = interval["block_bootstrap"]["high"] - interval["block_bootstrap"]["low"]
    wilson = interval["wilson"]["high"] - interval["wilson"]["low"]
    assert block == pytest.approx(wilson, rel=0.2)


def test_recall_counts_only_the_queries_that_have_a_match():
    hits = np.array([1, 0, 1, 1, 0, 0], bool)
    counted = np.array([1, 1, 1, 1, 0, 0], bool)
    interval = fraction_interval(hits, counted, block_resampling(6, SETTINGS), SETTINGS)
    assert interval["wilson"]["low"] == pytest.approx(binomtest(3, 4).proportion_ci(method="wilson").low)


def test_mcnemar_exact_known_values():
    assert mcnemar_exact(0, 0) == 1.0
    assert mcnemar_exact(0, 6) == pytest.approx(2 * 0.5**6)
    assert mcnemar_exact(3, 3) == 1.0


def test_holm_known_values():
    assert np.allclose(holm([0.01, 0.04, 0.03, 0.005]), [0.03, 0.06, 0.06, 0.02])
    assert np.allclose(holm([0.5, 0.9]), [1.0, 1.0])
    assert holm([]).size == 0


def test_identical_learners_make_no_difference():
    correct = np.random.default_rng(1).random(158) < 0.7
    comparison = paired_difference(correct, correct, block_resampling(158, SETTINGS), SETTINGS)
    assert comparison["difference"] == 0.0
    assert (comparison["low"], comparison["high"]) == (0.0, 0.0)
    assert comparison["p_value"] == 1.0
    [judged] = with_verdicts([comparison], SETTINGS.alpha)
    assert judged["verdict"] == "no difference"


def test_one_learner_right_on_every_discordant_query_is_significantly_better():
    rng = np.random.default_rng(2)
    second = rng.random(2000) < 0.5
    first = second | (rng.random(2000) < 0.3)  # right wherever second is, and on ~300 more
    comparison = paired_difference(first, second, block_resampling(2000, SETTINGS), SETTINGS)
    assert comparison["second_only"] == 0 and comparison["first_only"] > 200
    assert comparison["low"] > 0
    judged = with_verdicts(
        [comparison, paired_difference(second, first, block_resampling(2000, SETTINGS), SETTINGS)], 0.05
    )
    assert [entry["verdict"] for entry in judged] == ["better", "worse"]


def test_a_significant_mcnemar_on_one_run_is_not_enough():
    # 400 queries alike but for one run of 20 the first side alone gets right: McNemar counts 20
    # independent wins (p ~ 2e-6); the blocks see one stretch of route, missed by ~12% of resamples
    second = np.random.default_rng(4).random(400) < 0.5
    first = second.copy()
    first[200:220] = True
    second[200:220] = False
    comparison = paired_difference(first, second, block_resampling(400, SETTINGS), SETTINGS)
    assert comparison["p_value"] < 1e-5
    assert comparison["low"] == 0.0
    [judged] = with_verdicts([comparison], 0.05)
    assert judged["verdict"] == "no difference"


def test_paired_comparison_refuses_different_queries():
    with pytest.raises(ValueError, match="not the same queries"):
        paired_difference(np.ones(5, bool), np.ones(6, bool), block_resampling(5, SETTINGS), SETTINGS)


def test_outcomes_round_trip(tmp_path):
    outcomes = QueryOutcomes(
        np.array([3, 4, 9]),
        np.array([True, False, True]),
        np.array([-0.5, -np.inf, -0.25]),
        np.array([True, True, False]),
        np.array([True, False, False]),
    )
    outcomes.to_csv(tmp_path / "pair.csv")
    back = QueryOutcomes.read_csv(tmp_path / "pair.csv")
    for name in ("query_place", "correct", "confidence", "has_match", "hit_at_1"):
        assert np.array_equal(getattr(back, name), getattr(outcomes, name)), name
    (tmp_path / "bad.csv").write_text("query_place,correct\n1,1\n")
    with pytest.raises(ValueError, match=r"bad\.csv: per-query outcomes lack column\(s\) confidence"):
        QueryOutcomes.read_csv(tmp_path / "bad.csv")


def test_a_block_shorter_than_the_sequence_is_refused():
    params = yaml.safe_load(Path("params.yaml").read_text())
    short = copy.deepcopy(params)
    short["statistics"]["block_length"] = params["sequence"]["length"] - 1
    with pytest.raises(ValueError, match="statistics.block_length"):
        check_whole(short)
    short["evaluate"]["matchers"] = ["single"]
    check_whole(short)


def test_no_counted_query_has_no_interval():
    interval = fraction_interval(np.zeros(6, bool), np.zeros(6, bool), block_resampling(6, SETTINGS), SETTINGS)
    assert interval == {"block_bootstrap": None, "wilson": None}


def test_comparison_tables_of_a_run():
    variants = [
        ("cosine", "single", ""),
        ("cosine", "sequence", "+seq"),
        ("cityblock", "single", "@cityblock"),
        ("cityblock", "sequence", "@cityblock+seq"),
    ]
    tables = comparison_tables(["pca", "ica", "cae"], variants)
    assert list(tables) == [
        "learners",
        "learners+seq",
        "learners@cityblock",
        "learners@cityblock+seq",
        "matchers+seq",
        "matchers@cityblock+seq",
        "distances@cityblock",
        "distances@cityblock+seq",
    ]
    assert tables["learners@cityblock"] == [
        ("pca@cityblock", "ica@cityblock"),
        ("pca@cityblock", "cae@cityblock"),
        ("ica@cityblock", "cae@cityblock"),
    ]
    assert tables["matchers@cityblock+seq"][1] == ("ica@cityblock+seq", "ica@cityblock")
    assert tables["distances@cityblock+seq"][2] == ("cae@cityblock+seq", "cae+seq")
    # a run without sequences or extra distances has only its learners' table
    assert list(comparison_tables(["pca", "ica"], variants[:1])) == ["learners"]


def test_pair_comparisons_use_one_set_of_blocks_and_refuse_other_queries():
    rng = np.random.default_rng(6)
    correct = {label: rng.random(60) < 0.6 for label in ("a", "b", "c")}
    tables = {"learners": [("a", "b"), ("a", "c"), ("b", "c")]}
    found = pair_comparisons(lambda label: (np.arange(60), correct[label]), tables, SETTINGS)
    [first, *_] = found["learners"]
    expected = paired_difference(correct["a"], correct["b"], block_resampling(60, SETTINGS), SETTINGS)
    assert {key: first[key] for key in expected} == expected
    assert [row["p_holm"] >= row["p_value"] for row in found["learners"]] == [True] * 3
    shifted = {"a": np.arange(60), "b": np.arange(1, 61), "c": np.arange(60)}
    with pytest.raises(ValueError, match="b: its queries are not those of a"):
        pair_comparisons(lambda label: (shifted[label], correct[label]), tables, SETTINGS)


def test_the_mean_of_one_pair_is_that_pairs_interval():
    correct = np.random.default_rng(3).random(158) < 0.6
    one = fraction_interval(correct, np.ones(158, bool), block_resampling(158, SETTINGS), SETTINGS)
    assert mean_interval([correct], SETTINGS) == pytest.approx(one["block_bootstrap"])


def test_the_mean_resamples_the_same_places_in_every_pair():
    correct = np.repeat(np.random.default_rng(4).random(16) < 0.5, 10)  # runs of 10 along the route
    alone = mean_interval([correct], SETTINGS)
    # the same outcomes in two pairs: a resample draws the same places in both, so their mean is
    # as uncertain as one pair (two pairs resampled on their own would give a narrower interval)
    assert mean_interval([correct, correct], SETTINGS) == pytest.approx(alone)
    # one pair right exactly where the other is wrong: every resample's mean is one half
    assert mean_interval([correct, ~correct], SETTINGS) == pytest.approx({"low": 0.5, "high": 0.5})


def test_a_mean_over_no_pair_is_refused():
    with pytest.raises(ValueError, match="no season pair"):
        mean_interval([], SETTINGS)


def test_block_interval_is_the_evaluate_stages_interval():
    correct = np.repeat(np.random.default_rng(5).random(16) < 0.7, 10)
    drawn = fraction_interval(correct, np.ones(len(correct), bool), block_resampling(len(correct), SETTINGS), SETTINGS)
    assert block_interval(correct, SETTINGS) == drawn["block_bootstrap"]
