"""Intervals on a fraction of a pair's queries (fraction correct, recall@1) that respect the route.

The queries of a pair are consecutive places along a route, so their successes come in runs (a
stretch of forest matched, a stretch of snow missed; a sequence matcher's outcome at one query
depends on its neighbours' images): an interval that treats them as independent, as the
binomial's, is too narrow. The moving block bootstrap (Kuensch 1989) resamples blocks of
`block_length` consecutive queries, so the runs inside a block stay whole; its percentile interval
is the one the tables use, the Wilson interval of the binomial beside it for comparison.

A resample is a set of blocks (block_resampling), the same for every learner of a pair (they
depend only on the number of queries and the settings), so a paired difference between two
learners is resampled on the same queries (seasonloop.significance.paired). Several independent
routes' queries joined into one (replicate routes) are resampled route by route
(stratified_resampling).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from statistics import NormalDist
from typing import Any

import numpy as np

from seasonloop.params.settings import StatisticsConfig


@dataclass(frozen=True)
class Resampling:
    """Block resamples of a run of queries: starts (resamples, blocks), the first query of each block
    of each resample; lengths (blocks,), each block column's number of queries. A resample's queries
    are its blocks' queries, block after block."""

    starts: np.ndarray
    lengths: np.ndarray

    @property
    def n_queries(self) -> int:
        return int(self.lengths.sum())


def block_resampling(n_queries: int, settings: StatisticsConfig, seed: Sequence[int] | int | None = None) -> Resampling:
    """The moving block bootstrap of one route's queries: ceil(n / length) blocks a resample, each
    first query uniform over the n - length + 1 possible starts, the last block cut so that a resample
    has n queries. A block never wraps around: the route's two ends are not neighbours. Drawn from
    settings.seed, or from `seed` where given (a route among several: stratified_resampling)."""
    if n_queries < 1:
        raise ValueError(f"block_resampling: no query to resample (n_queries {n_queries})")
    length = min(settings.block_length, n_queries)
    blocks = math.ceil(n_queries / length)
    rng = np.random.default_rng(settings.seed if seed is None else seed)
    starts = rng.integers(0, n_queries - length + 1, size=(settings.resamples, blocks), dtype=np.int64)
    lengths = np.full(blocks, length, np.int64)
    lengths[-1] = n_queries - (blocks - 1) * length
    return Resampling(starts, lengths)


def stratified_resampling(routes: Sequence[tuple[int, int]], settings: StatisticsConfig) -> Resampling:
    """Several independent routes' queries one after another, routes[i] = (key, n_queries) in that
    order: each route resampled on its own (its blocks inside it, as many queries as it has), from a
    generator seeded by (settings.seed, key). A route's resamples then depend neither on the order the
    routes are joined in nor on which other routes are there, and no block joins two routes."""
    if not routes:
        raise ValueError("stratified_resampling: no route to resample")
    keys = [key for key, _ in routes]
    if len(set(keys)) != len(keys):
        raise ValueError(f"stratified_resampling: route keys {keys} repeat (each route needs its own generator)")
    strata, offset = [], 0
    for key, n_queries in routes:
        route = block_resampling(n_queries, settings, seed=[settings.seed, key])
        strata.append(Resampling(route.starts + offset, route.lengths))
        offset += n_queries
    return Resampling(
        np.concatenate([stratum.starts for stratum in strata], axis=1),
        np.concatenate([stratum.lengths for stratum in strata]),
    )


def resampled_ratios(numerator: np.ndarray, denominator: np.ndarray, resampling: Resampling) -> np.ndarray:
    """(resamples,) sum(numerator) / sum(denominator) over each resample's queries (NaN where a
    resample holds no denominator). With a denominator of ones, the resampled means."""
    numerator, denominator = np.asarray(numerator, np.float64), np.asarray(denominator, np.float64)
    if len(numerator) != resampling.n_queries:
        raise ValueError(f"resampled_ratios: {len(numerator)} queries, resamples of {resampling.n_queries}")
    ends = resampling.starts + resampling.lengths

    def sums(values: np.ndarray) -> np.ndarray:
        cumulative = np.concatenate(([0.0], np.cumsum(values)))
        return (cumulative[ends] - cumulative[resampling.starts]).sum(axis=1)

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
    successes: np.ndarray, counted: np.ndarray, resampling: Resampling, settings: StatisticsConfig
) -> dict[str, Any]:
    """The block-bootstrap and Wilson intervals of the fraction of the counted queries that succeed
    (fraction correct: every query counted; recall@1: the queries that have a correct place)."""
    successes, counted = np.asarray(successes, bool), np.asarray(counted, bool)
    hits, trials = int((successes & counted).sum()), int(counted.sum())
    if trials == 0:  # e.g. recall@1 of a pair where no query has a correct place (JSON has no NaN)
        return {"block_bootstrap": None, "wilson": None}
    resampled = resampled_ratios(successes & counted, counted, resampling)
    low, high = percentile_interval(resampled, settings.level)
    wilson_low, wilson_high = wilson_interval(hits, trials, settings.level)
    return {"block_bootstrap": {"low": low, "high": high}, "wilson": {"low": wilson_low, "high": wilson_high}}


def block_interval(correct: np.ndarray, settings: StatisticsConfig) -> dict[str, float]:
    """{low, high}: the block-bootstrap interval of the fraction of `correct` queries (in query order),
    as the evaluate stage draws it for a pair of that many queries (an ablation's evaluation)."""
    correct = np.asarray(correct, np.float64)
    resampling = block_resampling(len(correct), settings)
    low, high = percentile_interval(resampled_ratios(correct, np.ones_like(correct), resampling), settings.level)
    return {"low": low, "high": high}
