"""Paired comparisons of two evaluations on the same queries: learner A against learner B on one
pair, a learner single against +seq, cosine against L1.

Each comparison is one test on the per-query differences (first correct minus second correct, in
route order): their mean is the difference in fraction correct, its standard error the route's
(seasonloop.significance.intervals: runs of successes and failures allowed for), and the mean over
its standard error follows Student's t with the route's degrees of freedom under no difference.
The interval is the mean plus or minus the t quantile times the standard error; the p-value the
t's two-sided tail. The p-values of one table (a family of comparisons) are corrected together
by Holm's step-down method, and a difference is significant when its Holm p-value is below alpha
(an interval that excludes 0 follows: Holm only raises p-values). The discordant counts (queries
one side gets right and the other wrong) are kept for the reader; McNemar's test on them, which
counts them as independent, is not used: along a route it calls equal learners different 5-10
times as often as it says (benchmarks/studies/check_calibration.py).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import Runs, mean_variance, t_quantile

VERDICTS = ("better", "worse", "no difference", "not enough queries")
# benchmarks/studies/check_calibration.py (docs/statistics.md, table calibration_difference_coverage): the
# difference's interval covers 93-96% except where a side's fraction is near 0 or 1 on a short
# route (down to 83% at 50 queries, 91% at 158); there a comparison says so beside its interval
NEAR_BOUNDARY = 0.1  # a side's fraction below it, or above 1 minus it
NEAR_BOUNDARY_QUERIES = 400  # on fewer queries than this
NEAR_BOUNDARY_NOTE = "interval may cover less than 95%: a side near 0% or 100% on a short route (docs/statistics.md)"


def t_p_value(statistic: float, degrees: float) -> float:
    """Two-sided p-value of a t statistic with `degrees` degrees of freedom."""
    from scipy.special import stdtr  # imported where used: the report stage only reads verdicts

    if math.isinf(degrees):
        return math.erfc(abs(statistic) / math.sqrt(2.0))
    return float(2.0 * stdtr(degrees, -abs(statistic)))


def holm(p_values: Sequence[float]) -> np.ndarray:
    """Holm's step-down adjusted p-values (in the input's order): the k-th smallest times (m - k + 1),
    made non-decreasing in that order and capped at 1."""
    p = np.asarray(p_values, np.float64)
    if p.size == 0:
        return p
    order = np.argsort(p, kind="stable")
    scaled = p[order] * (p.size - np.arange(p.size))
    adjusted = np.empty_like(p)
    adjusted[order] = np.minimum(np.maximum.accumulate(scaled), 1.0)
    return adjusted


def paired_difference(
    first: np.ndarray,
    second: np.ndarray,
    settings: StatisticsConfig,
    segments: Sequence[int] | None = None,
    runs: Runs | None = None,
) -> dict[str, Any]:
    """first's fraction correct minus second's on the same queries (bool arrays in route order;
    segments: the lengths of independent routes joined one after another), its interval (inside
    [-1, 1]), the discordant counts and the p-value (None, with the reason, where a route is too
    short for its runs). runs: those of the differences' kind (the table's, `differences`); None:
    estimated from this one."""
    first, second = np.asarray(first, bool), np.asarray(second, bool)
    if first.shape != second.shape:
        raise ValueError(f"paired comparison: {first.shape[0]} queries against {second.shape[0]}: not the same queries")
    change = differences(first, second)
    difference = float(change.mean())
    counts = {"first_only": int((first & ~second).sum()), "second_only": int((~first & second).sum())}
    spread = mean_variance(change, settings, segments, runs)
    if spread.reason is not None:
        return {"difference": difference, "low": None, "high": None, **counts, "p_value": None, "reason": spread.reason}
    error = math.sqrt(spread.variance)
    half = t_quantile(settings.level, spread.degrees) * error
    if error > 0:
        p_value = t_p_value(difference / error, spread.degrees)
    else:  # every query differs the same way (or none differs): nothing varies along the route
        p_value = 1.0 if difference == 0 else 0.0
    compared: dict[str, Any] = {
        "difference": difference,
        "low": max(difference - half, -1.0),
        "high": min(difference + half, 1.0),
        **counts,
        "degrees": spread.degrees,
        "p_value": p_value,
    }
    shares = (float(first.mean()), float(second.mean()))
    if len(first) < NEAR_BOUNDARY_QUERIES and any(not NEAR_BOUNDARY <= share <= 1 - NEAR_BOUNDARY for share in shares):
        compared["interval_note"] = NEAR_BOUNDARY_NOTE
    return compared


def differences(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """The per-query differences a paired comparison tests (first correct minus second correct)."""
    return np.asarray(first, bool).astype(np.float64) - np.asarray(second, bool).astype(np.float64)


def with_verdicts(comparisons: Sequence[dict[str, Any]], alpha: float) -> list[dict[str, Any]]:
    """The comparisons of one table with p_holm (Holm across the table's tested comparisons) and
    verdict: "better" or "worse" (the first side against the second) when p_holm < alpha, else
    "no difference"; "not enough queries" where no test could be made (it takes no share of alpha)."""
    tested = [i for i, comparison in enumerate(comparisons) if comparison["p_value"] is not None]
    adjusted = dict(zip(tested, holm([comparisons[i]["p_value"] for i in tested])))
    judged = []
    for i, comparison in enumerate(comparisons):
        if i not in adjusted:
            judged.append({**comparison, "p_holm": None, "verdict": "not enough queries"})
            continue
        p_holm = float(adjusted[i])
        verdict = "no difference"
        if p_holm < alpha:
            verdict = "better" if comparison["difference"] > 0 else "worse"
        judged.append({**comparison, "p_holm": p_holm, "verdict": verdict})
    return judged
