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
error follows Student's t with ν degrees of freedom. No resampling, no seed, no block length.

ν grows with the route and shrinks with the length of its runs: the coefficients' mean square is
the spectrum's mean over frequencies up to ν π / n, close to its value at 0 (what the variance of
the mean needs) only while runs are short against n / ν. LLSW's size-power trade-off gives
ν ∝ (n² / ω)^(1/3), ω = Σ k² γ_k / Σ γ_k the autocovariances' mean squared lag (queries²: long
runs, large ω), so ν = min(floor(degrees_scale n^(2/3)), floor(persistence_scale (n² / ω)^(1/3))).
ω is not known: it is estimated (`persistence`) from the autocorrelations at lags 1-10 pooled
over the series of one kind of statement (a learner's evaluations of one matcher on every season
pair; the comparisons of one table), read through an AR(1) with a nugget (a run's outcomes are
runs of an AR(1) plus independent misses: r_k = c φ^k). A route whose runs leave ν below
MIN_DEGREES has no interval: it says "runs too long for this many queries" rather than a number.
Both scales are params (statistics); benchmarks/studies/check_calibration.py measures the level
they give, on the dependence they were chosen on and on dependence they were not (docs/statistics.md).

The fraction's interval is Wilson's score interval with the route's effective number of queries
(n times the binomial's variance over the long-run one) and the t quantile in place of the
normal's: the score form keeps it inside [0, 1] and its coverage near the ends (fractions near
0 or 1), where the symmetric interval undercovers. Several independent routes joined one after
another (replicate routes pooled) are `segments`: each route's long-run variance is its own,
and their sum, weighted by the routes' shares of the queries, is the pooled mean's, with
Satterthwaite's degrees of freedom: a statement about these routes' queries, not about routes
in general.

Below MIN_DEGREES no interval is given ("not enough queries"). A route whose queries all succeed
(or all fail) has no variance of its own: its effective number of queries is n over the inflation
its kind of series shows (1 + 2 Σ r_k of the fit), or ν + 1 stretches where none of them varies.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from statistics import NormalDist
from typing import Any

import numpy as np

from seasonloop.params.settings import StatisticsConfig

# one cosine term: a t_1 (Cauchy) interval 12.7 standard errors wide at 95%, no check of a flat spectrum
MIN_DEGREES = 2
RUNS_TOO_LONG = "runs too long for this many queries"  # how such a reason begins: tables say which
EXACT = 1e-9  # added before a floor: a product that is an integer in exact arithmetic stays one
PERSISTENCE_LAGS = 10  # the lags the persistence is fitted to, where a run's outcomes still correlate
# one-sided 5%: the lags' correlations must show dependence before it sets ν (`persistence`)
DEPENDENCE_EVIDENCE = 1.645
# φ searched on a grid over (0, 0.999] (ω grows as 1 / (1 - φ)³: a trend, not runs, at φ = 1)
PHI_GRID = np.linspace(0.001, 0.999, 999)


def cosine_degrees(n_queries: int, settings: StatisticsConfig, persistence: float = 0.0) -> int:
    """ν, the cosine terms (degrees of freedom) of a route of n_queries whose autocovariances'
    mean squared lag is `persistence` (ω, queries²; 0: no positive dependence): the smaller of
    floor(degrees_scale n^(2/3)) and floor(persistence_scale (n² / ω)^(1/3)). Exact at integers
    (floor(0.15 * 1000^(2/3)) is 15, which the float product leaves at 14.999...)."""
    nu = math.floor(settings.degrees_scale * n_queries ** (2.0 / 3.0) + EXACT)
    if persistence > 0:
        nu = min(nu, math.floor(settings.persistence_scale * (n_queries**2 / persistence) ** (1.0 / 3.0) + EXACT))
    return int(nu)


def min_queries(settings: StatisticsConfig) -> int:
    """The fewest queries a route needs for an interval or a test (MIN_DEGREES cosine terms) when
    its runs are short (longer runs need more: cosine_degrees)."""
    n = 1
    while cosine_degrees(n, settings) < MIN_DEGREES:
        n += 1
    return n


@dataclass(frozen=True)
class Runs:
    """The runs of one kind of series, from their pooled autocorrelations (`persistence`): omega,
    the autocovariances' mean squared lag (queries²; 0: no dependence shown), and inflation, the
    long-run variance over the variance (1 + 2 Σ r_k; None: no series varied, nothing is known)."""

    omega: float = 0.0
    inflation: float | None = None


def persistence(series: Iterable[np.ndarray]) -> Runs:
    """The Runs of series of one kind from their autocorrelations at lags 1..PERSISTENCE_LAGS pooled
    (autocovariances of the centred series summed, over their variances' sum), read through an
    AR(1) with a nugget, r_k = c φ^k (least squares; φ on a grid, c in closed form): inflation
    1 + 2 c φ / (1 - φ), ω = [2 c φ (1 + φ) / (1 - φ)³] / inflation. No dependence (ω 0, inflation
    1) where the lags' correlations sum to less than DEPENDENCE_EVIDENCE standard errors of
    independent queries' (sqrt(lags / queries)): noise would fit as a slow decay, ω set by chance."""
    lags = np.arange(1, PERSISTENCE_LAGS + 1)
    variance, covariances, queries = 0.0, np.zeros(len(lags)), 0
    for values in series:
        centred = np.asarray(values, np.float64) - np.mean(values)
        if len(centred) <= lags[-1]:
            continue
        variance += float(centred @ centred)
        queries += len(centred)
        covariances += [float(centred[:-lag] @ centred[lag:]) for lag in lags]
    if variance <= 0:
        return Runs()
    correlations = covariances / variance
    if correlations.sum() < DEPENDENCE_EVIDENCE * math.sqrt(len(lags) / queries):
        return Runs(0.0, 1.0)
    powers = PHI_GRID[:, None] ** lags[None, :]  # (grid, lags)
    c = np.clip(powers @ correlations / np.einsum("gl,gl->g", powers, powers), 0.0, 1.0)
    misfit = np.sum((correlations[None, :] - c[:, None] * powers) ** 2, axis=1)
    best = int(np.argmin(misfit))
    phi, c_best = float(PHI_GRID[best]), float(c[best])
    if c_best <= 0:
        return Runs(0.0, 1.0)
    inflation = 1 + 2 * c_best * phi / (1 - phi)
    return Runs((2 * c_best * phi * (1 + phi) / (1 - phi) ** 3) / inflation, inflation)


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
    why there is none (reason); independent: what a series without variance counts as independent
    queries (n over the runs' inflation; the routes' cosine terms plus one each where nothing is
    known of the runs)."""

    variance: float
    degrees: float
    reason: str | None = None
    independent: float = math.nan


def mean_variance(
    values: np.ndarray, settings: StatisticsConfig, segments: Sequence[int] | None = None, runs: Runs | None = None
) -> MeanVariance:
    """The variance of values.mean() along the route(s): one route (segments None), or independent
    routes of segments[i] queries one after another (their weighted sum, Satterthwaite's degrees).
    runs: those of the kind of series these values are (`persistence`, pooled over the statement's
    series); None: estimated from these values alone."""
    values = np.asarray(values, np.float64)
    lengths = [len(values)] if segments is None else [int(length) for length in segments]
    if sum(lengths) != len(values):
        raise ValueError(f"mean_variance: routes of {sum(lengths)} queries for a series of {len(values)}")
    least = min_queries(settings)
    if min(lengths) < least:
        return MeanVariance(math.nan, math.nan, f"not enough queries ({min(lengths)} on a route, fewer than {least})")
    ends = np.cumsum(lengths)
    if runs is None:
        runs = persistence(routes_of(values, segments))
    total, parts = len(values), []
    for length, end in zip(lengths, ends):
        # a route of several needs one cosine term of its own; the routes' sum needs MIN_DEGREES
        route_degrees = cosine_degrees(length, settings, runs.omega)
        if route_degrees < (MIN_DEGREES if len(lengths) == 1 else 1):
            return MeanVariance(math.nan, math.nan, runs_too_long(length, runs.omega))
        route_variance = float(cosine_variance(values[end - length : end], route_degrees)) * length / total**2
        parts.append((route_variance, route_degrees))
    if runs.inflation is None:
        independent = float(sum(route_degrees + 1 for _, route_degrees in parts))
    else:
        independent = total / runs.inflation
    variance = sum(part for part, _ in parts)
    squares = sum(part * part / route_degrees for part, route_degrees in parts)
    # Satterthwaite: one route keeps its own; routes without variance add nothing (none at all: as if
    # every route had the same variance)
    if squares > 0:
        pooled = variance * variance / squares
    else:
        pooled = len(parts) ** 2 / sum(1.0 / route_degrees for _, route_degrees in parts)
    if pooled < MIN_DEGREES:
        return MeanVariance(math.nan, math.nan, runs_too_long(min(lengths), runs.omega))
    return MeanVariance(variance, pooled, independent=independent)


def routes_of(values: np.ndarray, segments: Sequence[int] | None = None) -> list[np.ndarray]:
    """values cut into its independent routes (segments: their lengths; None: one route)."""
    if segments is None:
        return [values]
    return np.split(values, np.cumsum(segments)[:-1])


def runs_too_long(n_queries: int, omega: float) -> str:
    """Why a route of n_queries whose runs have persistence ω has no interval (RUNS_TOO_LONG first)."""
    return (
        f"{RUNS_TOO_LONG}: outcomes correlated over about {math.sqrt(omega):.0f} "
        f"queries leave {n_queries} queries fewer than {MIN_DEGREES} degrees of freedom"
    )


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
    values: np.ndarray,
    settings: StatisticsConfig,
    segments: Sequence[int] | None = None,
    runs: Runs | None = None,
    trials: int = 1,
) -> dict[str, Any]:
    """{low, high, effective_queries, degrees} of the mean of `values` (each the mean of `trials`
    0/1 outcomes, in route order), or {low: None, high: None, reason} when the route is too short
    for its runs. The score interval with n_eff = mean (1 - mean) / var(mean): the binomial's trials
    that would be as informative, at most n trials (never narrower than Wilson's for independent
    outcomes). A route whose values are all equal has no variance of its own to estimate: n_eff is
    n over the runs' inflation, or ν + 1 stretches where none of them varies. runs: as mean_variance."""
    values = np.asarray(values, np.float64)
    spread = mean_variance(values, settings, segments, runs)
    if spread.reason is not None:
        return {"low": None, "high": None, "reason": spread.reason}
    share = float(values.mean())
    binomial = share * (1 - share)
    if binomial > 0 and spread.variance > 0:
        effective = min(binomial / spread.variance, float(len(values) * trials))
    else:
        effective = min(spread.independent, float(len(values)))
    low, high = score_interval(share, effective, t_quantile(settings.level, spread.degrees))
    return {"low": low, "high": high, "effective_queries": effective, "degrees": spread.degrees}


def route_intervals(series: Mapping[str, np.ndarray], settings: StatisticsConfig) -> dict[str, dict[str, Any]]:
    """route_interval of each of several series of one kind (a descriptor's pairs, a learner's
    training-season sets), their runs' persistence pooled."""
    pooled = persistence(series.values())
    return {name: route_interval(values, settings, runs=pooled) for name, values in series.items()}


def counted_segments(counted: np.ndarray, segments: Sequence[int] | None) -> list[int] | None:
    """The routes' lengths once only the counted queries are kept."""
    if segments is None:
        return None
    starts = np.concatenate(([0], np.cumsum(segments)[:-1])).astype(np.int64)
    return [int(n) for n in np.add.reduceat(counted.astype(np.int64), starts)] if len(counted) else []


def fraction_interval(
    successes: np.ndarray,
    counted: np.ndarray,
    settings: StatisticsConfig,
    segments: Sequence[int] | None = None,
    runs: Runs | None = None,
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
        "route": route_interval(successes[counted], settings, counted_segments(counted, segments), runs),
        "wilson": {"low": wilson_low, "high": wilson_high},
    }
