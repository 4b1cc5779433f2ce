"""The interval of a fraction correct averaged over a run's season pairs.

On a frame-aligned route every pair's queries are the same test places in the same order, and a
place that is hard in every pair (a tunnel mouth, a snowed-over cutting) fails in all of them
together: the mean over pairs is then the mean of one series, each query's fraction of pairs
correct, and its interval is that series' route interval (seasonloop.significance.intervals),
which keeps the correlation across pairs. Pairs whose queries differ have no such series; their
mean's standard error is at most the mean of their standard errors (whatever the correlation
between pairs), the bound the interval uses there, with the fewest degrees of freedom of any pair.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import mean_variance, persistence, route_interval, t_quantile


def mean_interval(
    correct_by_pair: Sequence[np.ndarray], places_by_pair: Sequence[np.ndarray], settings: StatisticsConfig
) -> dict[str, Any]:
    """{low, high, ...} of the mean over pairs of each pair's fraction of correct queries
    (correct_by_pair: one bool array per pair in its query order; places_by_pair: its query
    places), or {low: None, high: None, reason} where a pair has too few queries."""
    if not correct_by_pair:
        raise ValueError("mean_interval: no season pair to average over")
    first = np.asarray(places_by_pair[0])
    # the pairs' outcomes are one kind of series: their runs' persistence is pooled
    pooled = persistence(np.asarray(correct, np.float64) for correct in correct_by_pair)
    if all(np.array_equal(first, places) for places in places_by_pair[1:]):
        mean = np.mean([np.asarray(c, np.float64) for c in correct_by_pair], axis=0)
        # each value the mean of one 0/1 outcome a pair: independent pairs would be n x pairs trials
        return route_interval(mean, settings, runs=pooled, trials=len(correct_by_pair))
    spreads = [mean_variance(np.asarray(correct, np.float64), settings, runs=pooled) for correct in correct_by_pair]
    reasons = [spread.reason for spread in spreads if spread.reason is not None]
    if reasons:
        return {"low": None, "high": None, "reason": reasons[0]}
    mean = float(np.mean([np.mean(correct) for correct in correct_by_pair]))
    error = float(np.mean([math.sqrt(spread.variance) for spread in spreads]))
    degrees = min(spread.degrees for spread in spreads)
    half = t_quantile(settings.level, degrees) * error
    return {"low": max(0.0, mean - half), "high": min(1.0, mean + half), "degrees": degrees}
