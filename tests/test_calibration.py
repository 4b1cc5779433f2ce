"""The calibration benchmark (benchmarks/studies/check_calibration.py) at a small grid: its simulated routes
have the dependence it is given, and on them the project's intervals and paired test keep their
stated levels where the binomial's do not. The full grid's table: docs/statistics.md."""

from __future__ import annotations

from itertools import combinations

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from benchmarks.studies.check_calibration import (
    INDEPENDENT,
    Dependence,
    binary_correlation,
    coverage_cell,
    fit_dependence,
    learners,
    means_cell,
    power_cell,
    table_cell,
)
from seasonloop.params.settings import StatisticsConfig  # noqa: E402

SETTINGS = StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05)
# about what the benchmark fits to the default run's single-image outcomes (its record says)
SINGLE_LIKE = Dependence(a=0.47, phi=0.77, share=0.38)
REPLICATES = 300  # a rate of 0.95 has a Monte Carlo standard error of 0.013 on 300 routes


def test_binary_correlation_is_the_bivariate_normals():
    p, latent = 0.3, 0.6
    threshold = multivariate_normal([0, 0], [[1, latent], [latent, 1]]).cdf([-0.5244005127080407] * 2)
    assert binary_correlation(latent, p)[0] == pytest.approx((threshold - p * p) / (p * (1 - p)), abs=1e-6)
    assert binary_correlation(0.0, p)[0] == 0.0


def test_fit_dependence_recovers_the_process_it_is_given():
    known = Dependence(a=0.5, phi=0.7, share=0.4)
    rng = np.random.default_rng(0)
    series = [learners(rng, 1, 3000, [0.4], known)[0][0] for _ in range(40)]
    pairs = [(first[0], second[0]) for first, second in (learners(rng, 1, 3000, [0.4, 0.4], known) for _ in range(40))]
    fitted = fit_dependence(series, pairs)["dependence"]
    assert fitted == pytest.approx({"a": 0.5, "phi": 0.7, "share": 0.4}, abs=0.08)
    independent = fit_dependence([rng.random(3000) < 0.4 for _ in range(20)], [])["dependence"]
    assert independent["a"] * independent["phi"] < 0.05 and independent["share"] == 0.0


def test_the_simulated_learners_share_what_they_are_given():
    rng = np.random.default_rng(1)
    outcomes = learners(rng, 400, 500, [0.5, 0.5, 0.5], SINGLE_LIKE)
    between = np.mean([np.corrcoef(a.ravel(), b.ravel())[0, 1] for a, b in combinations(outcomes, 2)])
    assert between == pytest.approx(binary_correlation(SINGLE_LIKE.share, 0.5)[0], abs=0.02)
    assert [o.mean() for o in outcomes] == pytest.approx([0.5] * 3, abs=0.01)


def test_the_interval_covers_what_it_says_where_wilsons_does_not():
    cell = coverage_cell(np.random.default_rng(2), SETTINGS, 158, 0.5, SINGLE_LIKE, REPLICATES)
    assert cell["route"]["rate"] >= 0.91  # 0.95 less three Monte Carlo standard errors
    assert cell["wilson"]["rate"] < 0.85  # the runs along the route are there
    independent = coverage_cell(np.random.default_rng(3), SETTINGS, 158, 0.2, INDEPENDENT, REPLICATES)
    assert independent["route"]["rate"] >= 0.91


def test_equal_learners_are_called_different_about_alpha_of_the_time():
    cell = table_cell(np.random.default_rng(4), SETTINGS, 158, 0.5, SINGLE_LIKE, REPLICATES, size=4)
    assert cell["per_comparison"]["rate"] <= 0.09  # 0.05 plus three standard errors (0.013)
    assert cell["per_table"]["rate"] <= 0.09
    pooled = table_cell(np.random.default_rng(5), SETTINGS, 158, 0.5, SINGLE_LIKE, REPLICATES, size=3, routes=3)
    assert pooled["per_comparison"]["rate"] <= 0.09 and pooled["per_table"]["rate"] <= 0.09


def test_too_short_a_route_is_refused_not_answered():
    cell = coverage_cell(np.random.default_rng(6), SETTINGS, 20, 0.5, SINGLE_LIKE, 20)
    assert cell["route"] == {"rate": None, "replicates": 0, "refused": 20}
    assert cell["wilson"]["replicates"] == 20


def test_power_grows_with_the_queries_pooled():
    one = power_cell(np.random.default_rng(7), SETTINGS, 158, 0.5, 0.10, SINGLE_LIKE, REPLICATES, 2)
    three = power_cell(np.random.default_rng(7), SETTINGS, 158, 0.5, 0.10, SINGLE_LIKE, REPLICATES, 2, routes=3)
    assert three["power"]["rate"] > one["power"]["rate"] + 0.1
    assert one["interval_coverage"]["rate"] >= 0.91 and three["interval_coverage"]["rate"] >= 0.91


def test_the_mean_over_pairs_covers_what_it_says():
    fractions = (0.9, 0.85, 0.3, 0.1)
    cell = means_cell(np.random.default_rng(8), SETTINGS, 158, fractions, SINGLE_LIKE, 0.25, REPLICATES)
    # a few draws show runs too long for 158 queries (the persistence estimated from four pairs)
    assert cell["rate"] >= 0.91 and cell["refused"] <= 0.05 * REPLICATES


def test_the_out_of_sample_models_have_the_dependence_they_name():
    from benchmarks.studies.check_calibration import Blocks, Markov, autocorrelation, matcher_of

    rng = np.random.default_rng(9)
    (chains,) = learners(rng, 40, 2000, [0.3], Markov(0.8))
    assert chains.mean() == pytest.approx(0.3, abs=0.02)
    assert np.mean([autocorrelation(chain, 1) for chain in chains]) == pytest.approx(0.8, abs=0.02)
    assert np.mean([autocorrelation(chain, 3) for chain in chains]) == pytest.approx(0.8**3, abs=0.03)
    first, second = learners(rng, 200, 1000, [0.4, 0.4], Blocks(20, 80, 0.5))
    assert first.mean() == pytest.approx(0.4, abs=0.03)
    # every block is all right or all wrong: a change of outcome only where a block may end, at
    # least 20 queries after the last one of the route's first whole block
    changes = [np.flatnonzero(np.diff(row.astype(np.int8))) for row in first]
    assert min(np.diff(found).min() for found in changes if len(found) > 1) >= 20
    # a pair's learners take the stretch's common outcome half the time each: correlation about 1/4
    between = np.mean([np.corrcoef(a, b)[0, 1] for a, b in zip(first, second)])
    assert between == pytest.approx(0.25, abs=0.06)
    assert [matcher_of(name) for name in ("a-b", "a-b+seq", "a-b@cityblock+delta", "a-b+smoothed")] == [
        "single",
        "+seq",
        "+delta",
        "+smoothed",
    ]


def test_the_smallest_difference_found_needs_every_larger_one_found_too():
    from benchmarks.studies.check_power import smallest_found

    assert smallest_found({"0.050": 0.3, "0.100": 0.85, "0.200": 0.99}) == 0.10
    # a dip above it (noise, or a refused cell) moves it up: found means found from there on
    assert smallest_found({"0.050": 0.81, "0.100": 0.79, "0.200": 0.9}) == 0.20
    assert smallest_found({"0.050": 0.1, "0.100": None}) is None


def test_power_under_holm_is_below_power_alone_and_grows_with_the_gap():
    small = power_cell(np.random.default_rng(12), SETTINGS, 400, 0.5, 0.05, SINGLE_LIKE, 60, 4)
    large = power_cell(np.random.default_rng(12), SETTINGS, 400, 0.5, 0.30, SINGLE_LIKE, 60, 4)
    assert small["power_holm"]["rate"] <= small["power"]["rate"]
    assert large["power_holm"]["rate"] > small["power_holm"]["rate"] and large["power_holm"]["rate"] >= 0.8


def test_the_drift_studys_true_runs_are_the_simulated_outcomes_own():
    # check_drift's ω and inflation come from the latent's correlation: no runs without dependence,
    # and under a drift the measured lag-k correlations of the drawn outcomes are the ones it sums
    from benchmarks.studies.check_drift import true_runs

    assert true_runs(INDEPENDENT, 0.5).omega == 0 and true_runs(INDEPENDENT, 0.5).inflation == 1
    drift = Dependence(a=0.3, phi=float(np.exp(-1 / 100)), share=0.3)
    outcomes = learners(np.random.default_rng(0), 400, 1800, [0.5], drift)[0].astype(float)
    centred = outcomes - outcomes.mean()
    measured = [np.mean(centred[:, :-k] * centred[:, k:]) / np.mean(centred * centred) for k in (1, 50)]
    expected = binary_correlation(0.3 * drift.phi ** np.array([1, 50]), 0.5)
    assert measured == pytest.approx(expected, abs=0.02)
    runs = true_runs(drift, 0.5)
    assert runs.inflation > 30 and 100 < np.sqrt(runs.omega) < 200  # a drift of about 100 queries
