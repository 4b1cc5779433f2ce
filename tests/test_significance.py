"""Intervals and paired tests (seasonloop.significance) on cases with a known answer, and the
per-query outcomes they are computed from (seasonloop.evaluation.outcomes). Their real coverage and
error rates on simulated routes: tests/test_calibration.py."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.fft import dct
from scipy.stats import binomtest
from scipy.stats import t as student

from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import (
    Runs,
    cosine_degrees,
    cosine_variance,
    fraction_interval,
    mean_variance,
    min_queries,
    persistence,
    route_interval,
    wilson_interval,
)
from seasonloop.significance.means import mean_interval
from seasonloop.significance.paired import holm, paired_difference, with_verdicts
from seasonloop.significance.tables import comparison_tables, pair_comparisons

SETTINGS = StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05)


@pytest.mark.parametrize(
    ("successes", "trials", "level"), [(0, 10, 0.95), (7, 10, 0.9), (130, 158, 0.95), (158, 158, 0.99)]
)
def test_wilson_interval_is_scipys(successes, trials, level):
    expected = binomtest(successes, trials).proportion_ci(confidence_level=level, method="wilson")
    assert wilson_interval(successes, trials, level) == pytest.approx((expected.low, expected.high), abs=1e-12)


def test_degrees_grow_as_n_to_the_two_thirds():
    assert [cosine_degrees(n, SETTINGS) for n in (20, 49, 158, 3259, 27592)] == [1, 2, 4, 32, 136]
    assert min_queries(SETTINGS) == 49  # the first n with two cosine terms
    assert min_queries(StatisticsConfig(level=0.95, degrees_scale=0.4, persistence_scale=0.38, alpha=0.05)) == 12


def test_cosine_variance_is_the_mean_square_of_the_low_cosine_terms():
    values = np.random.default_rng(0).random(50)
    n, t = len(values), np.arange(50)
    written_out = [math.sqrt(2 / n) * np.sum(values * np.cos(np.pi * j * (t + 0.5) / n)) for j in (1, 2, 3)]
    assert cosine_variance(values, 3) == pytest.approx(np.mean(np.square(written_out)))
    assert cosine_variance(values + 7.0, 3) == pytest.approx(cosine_variance(values, 3))  # the mean is left out
    with pytest.raises(ValueError, match="50 cosine terms of a series of 50"):
        cosine_variance(values, 50)


def test_cosine_variance_estimates_an_ar1_long_run_variance():
    # AR(1) with coefficient 0.6 and unit innovations: long-run variance 1 / (1 - 0.6)^2 = 6.25
    rng = np.random.default_rng(1)
    noise = rng.standard_normal((400, 3000))
    series = np.zeros_like(noise)
    for i in range(1, 3000):
        series[:, i] = 0.6 * series[:, i - 1] + noise[:, i]
    assert np.mean(cosine_variance(series[:, 1000:], 20)) == pytest.approx(6.25, rel=0.05)


def test_an_interval_of_a_constant_counts_its_stretches_not_its_queries():
    # every query right: no variance to estimate, and no reason to take the 100 as independent
    interval = route_interval(np.ones(100), SETTINGS)
    degrees = cosine_degrees(100, SETTINGS)
    q2 = student.ppf(0.975, degrees) ** 2
    assert interval["effective_queries"] == degrees + 1 and interval["high"] == 1.0
    assert interval["low"] == pytest.approx((degrees + 1) / (degrees + 1 + q2))
    # where series of its kind vary, their runs say how many independent queries it is worth
    assert route_interval(np.ones(100), SETTINGS, runs=Runs(0.0, 4.0))["effective_queries"] == 25
    assert route_interval(np.ones(100), SETTINGS, runs=Runs(0.0, 1.0))["effective_queries"] == 100


def test_runs_of_outcomes_widen_the_interval_beyond_wilsons():
    # 160 queries in runs of 20 (a stretch matched, a stretch missed): 8 independent pieces, not 160
    runs = np.repeat(np.array([1, 0, 1, 1, 0, 1, 0, 1], bool), 20)
    interval = fraction_interval(runs, np.ones(160, bool), SETTINGS)
    route = interval["route"]["high"] - interval["route"]["low"]
    wilson = interval["wilson"]["high"] - interval["wilson"]["low"]
    # the runs also cut the cosine terms (the persistence rule): the t quantile widens it further
    assert route > 2 * wilson and interval["route"]["degrees"] < cosine_degrees(160, SETTINGS)
    # independent queries: the two agree (the route's t quantile a little wider than the normal's)
    independent = np.random.default_rng(0).random(2000) < 0.6
    interval = fraction_interval(independent, np.ones(2000, bool), SETTINGS)
    route = interval["route"]["high"] - interval["route"]["low"]
    wilson = interval["wilson"]["high"] - interval["wilson"]["low"]
    assert route == pytest.approx(wilson, rel=0.25)


def test_a_route_too_short_says_so_instead_of_a_number():
    interval = fraction_interval(np.arange(20) % 3 == 0, np.ones(20, bool), SETTINGS)
    assert interval["route"] == {
        "low": None,
        "high": None,
        "reason": "not enough queries (20 on a route, fewer than 49)",
    }
    assert interval["wilson"]["low"] < 1 / 3 < interval["wilson"]["high"]
    comparison = paired_difference(np.arange(20) % 2 == 0, np.zeros(20, bool), SETTINGS)
    assert comparison["p_value"] is None and comparison["low"] is None and comparison["difference"] == 0.5
    tested = paired_difference(np.arange(100) % 2 == 0, np.zeros(100, bool), SETTINGS)
    judged = with_verdicts([comparison, tested], 0.05)
    assert [row["verdict"] for row in judged] == ["not enough queries", "better"]
    assert judged[0]["p_holm"] is None and judged[1]["p_holm"] == tested["p_value"]  # a family of one tested


def test_recall_counts_only_the_queries_that_have_a_match():
    hits = np.array([1, 0, 1, 1, 0, 0] * 20, bool)
    counted = np.array([1, 1, 1, 1, 0, 0] * 20, bool)
    interval = fraction_interval(hits, counted, SETTINGS)
    assert interval["wilson"]["low"] == pytest.approx(binomtest(60, 80).proportion_ci(method="wilson").low)
    assert interval["route"] == route_interval(hits[counted], SETTINGS)


def test_no_counted_query_has_no_interval():
    assert fraction_interval(np.zeros(6, bool), np.zeros(6, bool), SETTINGS) == {"route": None, "wilson": None}


def test_holm_known_values():
    assert np.allclose(holm([0.01, 0.04, 0.03, 0.005]), [0.03, 0.06, 0.06, 0.02])
    assert np.allclose(holm([0.5, 0.9]), [1.0, 1.0])
    assert holm([]).size == 0


def test_identical_learners_make_no_difference():
    correct = np.random.default_rng(1).random(158) < 0.7
    comparison = paired_difference(correct, correct, SETTINGS)
    assert comparison["difference"] == 0.0
    assert (comparison["low"], comparison["high"]) == (0.0, 0.0)
    assert comparison["p_value"] == 1.0
    [judged] = with_verdicts([comparison], SETTINGS.alpha)
    assert judged["verdict"] == "no difference"


def test_the_paired_test_is_a_t_test_of_the_differences():
    rng = np.random.default_rng(7)
    first, second = rng.random(300) < 0.6, rng.random(300) < 0.5
    comparison = paired_difference(first, second, SETTINGS)
    change = first.astype(float) - second.astype(float)
    degrees = cosine_degrees(300, SETTINGS)
    error = math.sqrt(np.mean(dct(change, type=2, norm="ortho")[1 : degrees + 1] ** 2) / 300)
    assert comparison["degrees"] == degrees
    assert comparison["p_value"] == pytest.approx(2 * student.sf(abs(change.mean()) / error, degrees))
    half = student.ppf(0.975, degrees) * error
    assert (comparison["low"], comparison["high"]) == pytest.approx((change.mean() - half, change.mean() + half))


def test_one_learner_right_on_every_discordant_query_is_significantly_better():
    rng = np.random.default_rng(2)
    second = rng.random(2000) < 0.5
    first = second | (rng.random(2000) < 0.3)  # right wherever second is, and on ~300 more
    comparison = paired_difference(first, second, SETTINGS)
    assert comparison["second_only"] == 0 and comparison["first_only"] > 200
    assert comparison["low"] > 0
    judged = with_verdicts([comparison, paired_difference(second, first, SETTINGS)], 0.05)
    assert [entry["verdict"] for entry in judged] == ["better", "worse"]


def test_one_run_of_wins_is_not_a_difference_along_the_route():
    # 400 queries alike but for one run of 20 the first side alone gets right: McNemar would count
    # 20 independent wins (p ~ 2e-6); along the route it is one stretch
    second = np.random.default_rng(4).random(400) < 0.5
    first = second.copy()
    first[200:220] = True
    second[200:220] = False
    comparison = paired_difference(first, second, SETTINGS)
    assert comparison["first_only"] == 20 and comparison["second_only"] == 0
    assert comparison["p_value"] > 0.05 and comparison["low"] < 0
    [judged] = with_verdicts([comparison], 0.05)
    assert judged["verdict"] == "no difference"


def test_paired_comparison_refuses_different_queries():
    with pytest.raises(ValueError, match="not the same queries"):
        paired_difference(np.ones(5, bool), np.ones(6, bool), SETTINGS)


def test_routes_pooled_keep_their_own_variances():
    rng = np.random.default_rng(8)
    routes = [np.repeat(rng.random(n // 10) < 0.5, 10).astype(float) for n in (400, 200, 600)]
    pooled = mean_variance(np.concatenate(routes), SETTINGS, [400, 200, 600])
    # each route's cosine terms from the routes' persistence, pooled over them
    together = persistence(routes)
    assert together.omega > 0
    parts = [mean_variance(route, SETTINGS, runs=together) for route in routes]
    weights = [400 / 1200, 200 / 1200, 600 / 1200]
    assert pooled.variance == pytest.approx(sum(w * w * part.variance for w, part in zip(weights, parts)))
    squares = sum((w * w * part.variance) ** 2 / part.degrees for w, part in zip(weights, parts))
    assert pooled.degrees == pytest.approx(pooled.variance**2 / squares)  # Satterthwaite
    # the order the routes are joined in changes nothing
    swapped = mean_variance(np.concatenate(routes[::-1]), SETTINGS, [600, 200, 400])
    assert (swapped.variance, swapped.degrees) == pytest.approx((pooled.variance, pooled.degrees))
    # a route too short for its own variance: the pooled one says so
    assert "not enough queries" in mean_variance(np.ones(230), SETTINGS, [200, 30]).reason
    with pytest.raises(ValueError, match="routes of 250 queries for a series of 230"):
        mean_variance(np.ones(230), SETTINGS, [200, 50])


def test_outcomes_round_trip(tmp_path):
    outcomes = QueryOutcomes(
        np.array([3, 4, 9]),
        np.array([True, False, True]),
        np.array([-0.5, -np.inf, -0.25]),
        np.array([True, True, False]),
        np.array([True, False, False]),
        np.array([3, 7, 2]),
        np.array([0.5, np.inf, 0.25]),
    )
    outcomes.to_csv(tmp_path / "pair.csv")
    back = QueryOutcomes.read_csv(tmp_path / "pair.csv")
    for name in ("query_place", "correct", "confidence", "has_match", "hit_at_1", "match_place", "match_distance"):
        assert np.array_equal(getattr(back, name), getattr(outcomes, name)), name
    (tmp_path / "bad.csv").write_text("query_place,correct\n1,1\n")
    with pytest.raises(ValueError, match=r"bad\.csv: per-query outcomes lack column\(s\) confidence"):
        QueryOutcomes.read_csv(tmp_path / "bad.csv")


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
    # every matcher against each one before it, under its metric
    more = comparison_tables(
        ["pca"],
        [
            ("cosine", "single", ""),
            ("cosine", "sequence", "+seq"),
            ("cosine", "delta", "+delta"),
            ("cityblock", "sequence", "@cityblock+seq"),
            ("cityblock", "delta", "@cityblock+delta"),
        ],
    )
    assert {name: rows for name, rows in more.items() if name.startswith("matchers")} == {
        "matchers+seq": [("pca+seq", "pca")],
        "matchers+delta": [("pca+delta", "pca")],
        "matchers+delta vs +seq": [("pca+delta", "pca+seq")],
        "matchers@cityblock+delta vs +seq": [("pca@cityblock+delta", "pca@cityblock+seq")],
    }
    # a run without sequences or extra distances has only its learners' table
    assert list(comparison_tables(["pca", "ica"], variants[:1])) == ["learners"]


def test_pair_comparisons_test_every_row_and_refuse_other_queries():
    rng = np.random.default_rng(6)
    correct = {label: rng.random(60) < 0.6 for label in ("a", "b", "c")}
    tables = {"learners": [("a", "b"), ("a", "c"), ("b", "c")]}
    found = pair_comparisons(lambda label: (np.arange(60), correct[label]), tables, SETTINGS)
    [first, *_] = found["learners"]
    expected = paired_difference(correct["a"], correct["b"], SETTINGS)
    assert {key: first[key] for key in expected} == expected
    assert [row["p_holm"] >= row["p_value"] for row in found["learners"]] == [True] * 3
    shifted = {"a": np.arange(60), "b": np.arange(1, 61), "c": np.arange(60)}
    with pytest.raises(ValueError, match="b: its queries are not those of a"):
        pair_comparisons(lambda label: (shifted[label], correct[label]), tables, SETTINGS)


def test_the_mean_of_one_pair_is_that_pairs_interval():
    correct = np.random.default_rng(3).random(158) < 0.6
    one = fraction_interval(correct, np.ones(158, bool), SETTINGS)
    assert mean_interval([correct], [np.arange(158)], SETTINGS) == pytest.approx(one["route"])


def test_the_mean_over_pairs_of_the_same_places_keeps_their_correlation():
    correct = np.repeat(np.random.default_rng(4).random(16) < 0.5, 10)  # runs of 10 along the route
    places = np.arange(160)
    alone = mean_interval([correct], [places], SETTINGS)
    # the same outcomes in two pairs: their mean is as uncertain as one pair (two pairs taken as
    # independent would give a narrower interval)
    assert mean_interval([correct, correct], [places, places], SETTINGS) == pytest.approx(alone)
    # one pair right exactly where the other is wrong: the mean is one half at every query
    # (a mean without variance counts n over the pairs' runs' inflation, not n)
    half = mean_interval([correct, ~correct], [places, places], SETTINGS)
    inflation = persistence([correct, ~correct]).inflation
    assert half["low"] < 0.5 < half["high"] and half["effective_queries"] == pytest.approx(160 / inflation)


def test_the_mean_over_pairs_of_other_places_is_bounded_by_their_errors():
    rng = np.random.default_rng(9)
    first, second = rng.random(200) < 0.6, rng.random(300) < 0.4
    found = mean_interval([first, second], [np.arange(200), np.arange(300)], SETTINGS)
    errors = [math.sqrt(mean_variance(c.astype(float), SETTINGS).variance) for c in (first, second)]
    degrees = min(cosine_degrees(n, SETTINGS) for n in (200, 300))
    half = student.ppf(0.975, degrees) * np.mean(errors)
    mean = (first.mean() + second.mean()) / 2
    assert (found["low"], found["high"]) == pytest.approx((mean - half, mean + half))


def test_a_mean_over_no_pair_is_refused():
    with pytest.raises(ValueError, match="no season pair"):
        mean_interval([], [], SETTINGS)


def test_a_difference_near_0_or_100_percent_on_a_short_route_says_its_interval_may_be_short():
    rng = np.random.default_rng(10)
    high, middle = rng.random(158) < 0.97, rng.random(158) < 0.6
    assert "may cover less than 95%" in paired_difference(high, middle, SETTINGS)["interval_note"]
    assert "interval_note" not in paired_difference(middle, rng.random(158) < 0.5, SETTINGS)
    long_high, long_middle = rng.random(400) < 0.97, rng.random(400) < 0.6
    assert "interval_note" not in paired_difference(long_high, long_middle, SETTINGS)


def test_the_degrees_rule_is_exact_at_integers():
    # 0.15 * 1000^(2/3) is 15 in exact arithmetic, 14.999... in floats
    assert cosine_degrees(1000, SETTINGS) == 15


def test_persistence_reads_the_runs_of_an_ar_with_a_nugget():
    rng = np.random.default_rng(11)
    phi, a = 0.8, 0.5
    noise = rng.standard_normal((40, 2000))
    ar = np.zeros_like(noise)
    for t in range(1, 2000):
        ar[:, t] = phi * ar[:, t - 1] + math.sqrt(1 - phi * phi) * noise[:, t]
    series = math.sqrt(a) * ar + math.sqrt(1 - a) * rng.standard_normal((40, 2000))
    # r_k = a phi^k: omega = [2 a phi (1 + phi) / (1 - phi)^3] / [1 + 2 a phi / (1 - phi)]
    known = (2 * a * phi * (1 + phi) / (1 - phi) ** 3) / (1 + 2 * a * phi / (1 - phi))
    found = persistence(series)
    assert found.omega == pytest.approx(known, rel=0.15)
    assert found.inflation == pytest.approx(1 + 2 * a * phi / (1 - phi), rel=0.1)
    # independent queries show no dependence, and a constant nothing to estimate it from
    assert persistence(rng.random((6, 158)) < 0.5) == Runs(0.0, 1.0)
    assert persistence([np.ones(158)]) == Runs()


def test_long_runs_cut_the_degrees_and_too_long_ones_are_refused():
    settings = SETTINGS
    assert cosine_degrees(1800, settings, persistence=40.0) < cosine_degrees(1800, settings)
    runs = np.repeat(np.random.default_rng(5).random(4) < 0.5, 40).astype(float)  # 4 runs of 40
    spread = mean_variance(runs, settings)
    assert spread.reason is not None and spread.reason.startswith("runs too long for this many queries")


def test_no_interval_is_narrower_than_wilsons_and_differences_stay_inside_minus_one_one():
    # a series anti-correlated at lag 1 has a long-run variance below the binomial's: n_eff is capped at n
    alternating = np.tile([True, False], 80)
    interval = fraction_interval(alternating, np.ones(160, bool), SETTINGS)
    assert interval["route"]["effective_queries"] <= 160
    assert (
        interval["route"]["low"] <= interval["wilson"]["low"]
        and interval["route"]["high"] >= interval["wilson"]["high"]
    )
    first = np.ones(160, bool)
    second = np.repeat(np.random.default_rng(2).random(16) < 0.1, 10)
    compared = paired_difference(first, second, SETTINGS)
    assert compared["low"] >= -1.0 and compared["high"] <= 1.0


def test_the_mean_over_independent_pairs_is_as_narrow_as_their_trials_allow():
    # each query's share of six pairs correct is the mean of six 0/1 outcomes: six independent pairs
    # inform like 6 n trials, so the cap on the effective trials is 6 n, not n (an interval as wide
    # as one pair's Wilson would cover nearly always)
    rng = np.random.default_rng(0)
    pairs = [rng.random(2000) < 0.5 for _ in range(6)]
    interval = mean_interval(pairs, [np.arange(2000)] * 6, SETTINGS)
    low, high = wilson_interval(1000, 2000, SETTINGS.level)
    assert interval["high"] - interval["low"] < 0.6 * (high - low)  # about 1 / sqrt(6) = 0.41 of it
    assert interval["effective_queries"] <= 6 * 2000
