"""Intervals on a fraction of a pair's queries (fraction correct, recall@1) that respect the route.

The queries of a pair are consecutive places along a route, so their successes come in runs (a
stretch of forest matched, a stretch of snow missed; a sequence matcher's outcome at one query
depends on its neighbours' images): an interval that treats them as independent, as the
binomial's, is too narrow. The moving block bootstrap (Kuensch 1989) resamples blocks of
`block_length` consecutive queries, so the runs inside a block stay whole; its percentile interval
is the one the tables use, the Wilson interval of the binomial beside it for comparison.

A resample is a set of block starts (block_starts), the same for every learner of a pair (the
starts depend only on the number of queries and the settings), so a paired difference between
two learners is resampled on the same queries (seasonloop.significance.paired).
"""

from __future__ import annotations

import math
from statistics import NormalDist
from typing import Any

import numpy as np

from seasonloop.params.settings import StatisticsConfig


def block_starts(n_queries: int, settings: StatisticsConfig) -> np.ndarray:
    """(resamples, blocks) int64: the first query of each block of each resample, uniform over the
    n - length + 1 possible starts; ceil(n / length) blocks a resample, the last cut so that a
    resample has n queries. A block never wraps around: the route's two ends are not neighbours."""
    if n_queries < 1:
        raise ValueError(f"block_starts: no query to resample (n_queries {n_queries})")
    length = min(settings.block_length, n_queries)
    blocks = math.ceil(n_queries / length)
    rng = np.random.default_rng(settings.seed)
    return rng.integers(0, n_queries - length + 1, size=(settings.resamples, blocks), dtype=np.int64)


def resampled_ratios(
    numerator: np.ndarray, denominator: np.ndarray, starts: np.ndarray, block_length: int
) -> np.ndarray:
    """(resamples,) sum(numerator) / sum(denominator) over each resample's queries (NaN where a
    resample holds no denominator). With a denominator of ones, the resampled means."""
    numerator, denominator = np.asarray(numerator, np.float64), np.asarray(denominator, np.float64)
    n_queries = len(numerator)
    length = min(block_length, n_queries)
    last = n_queries - (starts.shape[1] - 1) * length  # the last block's queries

    def sums(values: np.ndarray) -> np.ndarray:
        cumulative = np.concatenate(([0.0], np.cumsum(values)))
        whole = cumulative[starts[:, :-1] + length] - cumulative[starts[:, :-1]]
        return whole.sum(axis=1) + cumulative[starts[:, -1] + last] - cumulative[starts[:, -1]]

    below = sums(denominator)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(below > 0, sums(numerator) / np.where(below > 0, below, 1.0), np.nan)


def percentile_interval(resampled: np.ndarray, level: float) -> tuple[float, float]:
    """The central `level` interval of the resampled values (NaN resamples left out)."""
    finite = resampled[np.isfinite(resampled)]
    if finite.size == 0:
        return math.nan, math.nan
    tail = (1.0 - level) / 2.0
    low, high = np.quantile(finite, [tail, 1.0 - tail])
    return float(low), float(high)


def wilson_interval(successes: int, trials: int, level: float) -> tuple[float, float]:
    """The binomial's Wilson score interval (as scipy.stats.binomtest(...).proportion_ci(method=
    "wilson"); written out because importing scipy.stats takes ~2 s at every evaluate stage's start)."""
    if trials < 1:
        return math.nan, math.nan
    z = NormalDist().inv_cdf(0.5 + level / 2.0)
    share = successes / trials
    centre = share + z * z / (2 * trials)
    spread = z * math.sqrt(share * (1 - share) / trials + z * z / (4 * trials * trials))
    scale = 1 + z * z / trials
    # at 0 or every success the bound is 0 (1) exactly; the formula leaves a rounding error
    low = 0.0 if successes == 0 else (centre - spread) / scale
    high = 1.0 if successes == trials else (centre + spread) / scale
    return low, high


def fraction_interval(
    successes: np.ndarray, counted: np.ndarray, starts: np.ndarray, settings: StatisticsConfig
) -> dict[str, Any]:
    """The block-bootstrap and Wilson intervals of the fraction of the counted queries that succeed
    (fraction correct: every query counted; recall@1: the queries that have a correct place)."""
    successes, counted = np.asarray(successes, bool), np.asarray(counted, bool)
    hits, trials = int((successes & counted).sum()), int(counted.sum())
    if trials == 0:  # e.g. recall@1 of a pair where no query has a correct place (JSON has no NaN)
        return {"block_bootstrap": None, "wilson": None}
    resampled = resampled_ratios(successes & counted, counted, starts, settings.block_length)
    low, high = percentile_interval(resampled, settings.level)
    wilson_low, wilson_high = wilson_interval(hits, trials, settings.level)
    return {"block_bootstrap": {"low": low, "high": high}, "wilson": {"low": wilson_low, "high": wilson_high}}


def block_interval(correct: np.ndarray, settings: StatisticsConfig) -> dict[str, float]:
    """{low, high}: the block-bootstrap interval of the fraction of `correct` queries (in query order),
    as the evaluate stage draws it for a pair of that many queries (an ablation's evaluation)."""
    correct = np.asarray(correct, np.float64)
    starts = block_starts(len(correct), settings)
    low, high = percentile_interval(
        resampled_ratios(correct, np.ones_like(correct), starts, settings.block_length), settings.level
    )
    return {"low": low, "high": high}
