"""Intervals on a fraction of a pair's queries (fraction correct, recall@1) that respect the route.

The queries of a pair are consecutive places along a route, so their successes come in runs (a
stretch of forest matched, a stretch of snow missed; a sequence matcher's outcome at one query
depends on its neighbours' images): the variance of their mean is the series' long-run variance
(the sum of its autocovariances) over n, larger than the binomial's when runs are long.

The long-run variance is estimated from the series' first ν cosine-transform coefficients, the
equal-weighted cosine (EWC) estimator of Lazarus, Lewis, Stock and Watson ("HAR inference:
recommendations for practice", J. Business & Economic Statistics 36(4), 2018): each coefficient
(scipy.fft.dct, type II, orthonormal, terms 1..ν) carries the series' variance at a low frequency,
and their mean square estimates it with ν degrees of freedom, so a mean divided by its standard
error follows Student's t with ν degrees of freedom. No resampling, no seed, no block length: ν
grows with the route, ν = floor(statistics.degrees_scale * n^(2/3)). LLSW's rule has scale 0.4;
benchmarks/studies/check_calibration.py measured it too liberal at this project's n and dependence, and
the scale in params.yaml is the one that covers 95% there (docs/statistics.md).

The fraction's interval is Wilson's score interval with the route's effective number of queries
(n times the binomial's variance over the long-run one) and the t quantile in place of the
normal's: the score form keeps it inside [0, 1] and its coverage near the ends (fractions near
0 or 1), where the symmetric interval undercovers. Several independent routes joined one after
another (replicate routes pooled) are `segments`: each route's long-run variance is its own,
and their sum, weighted by the routes' shares of the queries, is the pooled mean's, with
Satterthwaite's degrees of freedom: a statement about these routes' queries, not about routes
in general.

Below MIN_DEGREES (a route too short for its own variance) no interval is given: it says "not
enough queries" instead of a number.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from statistics import NormalDist
from typing import Any

import numpy as np

from seasonloop.params.settings import StatisticsConfig

# one cosine term leaves a variance estimate with one degree of freedom: a t_1 (Cauchy) interval
# 12.7 standard errors wide each side at 95%, and no check that the route's spectrum is flat
MIN_DEGREES = 2


def cosine_degrees(n_queries: int, settings: StatisticsConfig) -> int:
    """ν, the cosine terms (degrees of freedom) of a route of n_queries: floor(scale * n^(2/3))."""
    return int(math.floor(settings.degrees_scale * n_queries ** (2.0 / 3.0)))


def min_queries(settings: StatisticsConfig) -> int:
    """The fewest queries a route needs for an interval or a test (MIN_DEGREES cosine terms)."""
    n = 1
    while cosine_degrees(n, settings) < MIN_DEGREES:
        n += 1
    return n


def cosine_variance(values: np.ndarray, degrees: int) -> np.ndarray:
    """The EWC long-run variance of each series along the last axis: the mean square of its
    cosine-transform coefficients 1..degrees (coefficient 0 is the mean, left out, so a constant
    added to a series changes nothing)."""
    from scipy.fft import dct  # ~0.1 s to import; the report stage, which only reads, never needs it

    values = np.asarray(values, np.float64)
    if not 1 <= degrees < values.shape[-1]:
        raise ValueError(f"cosine_variance: {degrees} cosine terms of a series of {values.shape[-1]}")
    coefficients = dct(values, type=2, norm="ortho", axis=-1)[..., 1 : degrees + 1]
    return np.mean(coefficients * coefficients, axis=-1)


@dataclass(frozen=True)
class MeanVariance:
    """The variance of a series' mean (variance, along the route) and its degrees of freedom, or
    why there is none (reason)."""

    variance: float
    degrees: float
    reason: str | None = None


def mean_variance(
    values: np.ndarray, settings: StatisticsConfig, segments: Sequence[int] | None = None
) -> MeanVariance:
    """The variance of values.mean() along the route(s): one route (segments None), or independent
    routes of segments[i] queries one after another (their weighted sum, Satterthwaite's degrees)."""
    values = np.asarray(values, np.float64)
    lengths = [len(values)] if segments is None else [int(length) for length in segments]
    if sum(lengths) != len(values):
        raise ValueError(f"mean_variance: routes of {sum(lengths)} queries for a series of {len(values)}")
    least = min_queries(settings)
    if min(lengths) < least:
        return MeanVariance(math.nan, math.nan, f"not enough queries ({min(lengths)} on a route, fewer than {least})")
    total, parts, ends = len(values), [], np.cumsum(lengths)
    for length, end in zip(lengths, ends):
        route_degrees = cosine_degrees(length, settings)
        route_variance = float(cosine_variance(values[end - length : end], route_degrees)) * length / total**2
        parts.append((route_variance, route_degrees))
    variance = sum(part for part, _ in parts)
    squares = sum(part * part / route_degrees for part, route_degrees in parts)
    # Satterthwaite: one route keeps its own; routes without variance add nothing (none: infinite)
    pooled = float(parts[0][1]) if len(parts) == 1 else (variance * variance / squares if squares > 0 else math.inf)
    return MeanVariance(variance, pooled)


def t_quantile(level: float, degrees: float) -> float:
    """The two-sided `level` quantile of Student's t (the normal's at infinite degrees)."""
    if math.isinf(degrees):
        return NormalDist().inv_cdf(0.5 + level / 2.0)
    from scipy.special import stdtrit  # imported where used: the report stage only reads intervals

    return float(stdtrit(degrees, 0.5 + level / 2.0))


def score_interval(share: float, effective: float, quantile: float) -> tuple[float, float]:
    """Wilson's score interval of a fraction `share` of `effective` independent trials, quantile
    in place of the normal's (exactly 0 or 1 at a bound the data reach: the formula leaves a
    rounding error there)."""
    q2 = quantile * quantile
    centre = share + q2 / (2 * effective)
    spread = quantile * math.sqrt(share * (1 - share) / effective + q2 / (4 * effective * effective))
    scale = 1 + q2 / effective
    low = 0.0 if share == 0 else (centre - spread) / scale
    high = 1.0 if share == 1 else (centre + spread) / scale
    return low, high


def wilson_interval(successes: int, trials: int, level: float) -> tuple[float, float]:
    """The binomial's Wilson score interval (as scipy.stats.binomtest(...).proportion_ci(method=
    "wilson")): every query independent, beside the route's interval for comparison."""
    if trials < 1:
        return math.nan, math.nan
    return score_interval(successes / trials, trials, NormalDist().inv_cdf(0.5 + level / 2.0))


def route_interval(
    values: np.ndarray, settings: StatisticsConfig, segments: Sequence[int] | None = None
) -> dict[str, Any]:
    """{low, high, effective_queries, degrees} of the mean of `values` (each in [0, 1], in route
    order), or {low: None, high: None, reason} when the route is too short. The score interval
    with n_eff = mean (1 - mean) / var(mean): for 0/1 outcomes the binomial's trials that would
    be as informative; a route whose values are all equal has no variance to estimate and counts
    its queries as independent (n_eff = n)."""
    values = np.asarray(values, np.float64)
    spread = mean_variance(values, settings, segments)
    if spread.reason is not None:
        return {"low": None, "high": None, "reason": spread.reason}
    share = float(values.mean())
    binomial = share * (1 - share)
    effective = binomial / spread.variance if binomial > 0 and spread.variance > 0 else float(len(values))
    low, high = score_interval(share, effective, t_quantile(settings.level, spread.degrees))
    return {"low": low, "high": high, "effective_queries": effective, "degrees": spread.degrees}


def counted_segments(counted: np.ndarray, segments: Sequence[int] | None) -> list[int] | None:
    """The routes' lengths once only the counted queries are kept."""
    if segments is None:
        return None
    starts = np.concatenate(([0], np.cumsum(segments)[:-1])).astype(np.int64)
    return [int(n) for n in np.add.reduceat(counted.astype(np.int64), starts)] if len(counted) else []


def fraction_interval(
    successes: np.ndarray, counted: np.ndarray, settings: StatisticsConfig, segments: Sequence[int] | None = None
) -> dict[str, Any]:
    """The route's interval (route_interval) and Wilson's (independent queries) of the fraction of
    the counted queries that succeed (fraction correct: every query counted; recall@1: the queries
    that have a correct place, in route order with the others left out)."""
    successes, counted = np.asarray(successes, bool), np.asarray(counted, bool)
    hits, trials = int((successes & counted).sum()), int(counted.sum())
    if trials == 0:  # e.g. recall@1 of a pair where no query has a correct place (JSON has no NaN)
        return {"route": None, "wilson": None}
    wilson_low, wilson_high = wilson_interval(hits, trials, settings.level)
    return {
        "route": route_interval(successes[counted], settings, counted_segments(counted, segments)),
        "wilson": {"low": wilson_low, "high": wilson_high},
    }
