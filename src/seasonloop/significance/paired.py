"""Paired comparisons of two evaluations on the same queries: learner A against learner B on one
pair, a learner single against +seq, cosine against L1.

Each comparison gives the difference in fraction correct with its paired block-bootstrap interval
(the same resampled blocks for both sides: seasonloop.significance.intervals) and McNemar's exact
test on the discordant queries (those one side gets right and the other wrong; under no difference
either side is as likely to be the right one: a two-sided binomial test at 1/2). The p-values of
one table (a family of comparisons) are corrected together by Holm's step-down method.

McNemar's test counts the discordant queries as independent, which along a route they are not, so
its p-value alone is too small; a difference is called significant only when both agree: the
Holm-corrected McNemar p-value is below alpha and the paired block-bootstrap interval excludes 0.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import Resampling, percentile_interval, resampled_ratios

VERDICTS = ("better", "worse", "no difference")


def mcnemar_exact(first_only: int, second_only: int) -> float:
    """Two-sided p-value of McNemar's exact test: first_only of the discordant queries went to the
    first side, second_only to the second (1.0 when none is discordant)."""
    discordant = first_only + second_only
    if discordant == 0:
        return 1.0
    # imported here: scipy.stats takes ~0.5 s to import, and the report stage, which imports this
    # module for the tables, never tests
    from scipy.stats import binomtest

    return float(binomtest(first_only, discordant, 0.5, alternative="two-sided").pvalue)


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
    first: np.ndarray, second: np.ndarray, resampling: Resampling, settings: StatisticsConfig
) -> dict[str, Any]:
    """first's fraction correct minus second's on the same queries (bool arrays in query order),
    its paired block-bootstrap interval, the discordant counts and McNemar's exact p-value."""
    first, second = np.asarray(first, bool), np.asarray(second, bool)
    if first.shape != second.shape:
        raise ValueError(f"paired comparison: {first.shape[0]} queries against {second.shape[0]}: not the same queries")
    change = first.astype(np.float64) - second.astype(np.float64)
    low, high = percentile_interval(resampled_ratios(change, np.ones_like(change), resampling), settings.level)
    first_only, second_only = int((first & ~second).sum()), int((~first & second).sum())
    return {
        "difference": float(change.mean()),
        "low": low,
        "high": high,
        "first_only": first_only,
        "second_only": second_only,
        "p_value": mcnemar_exact(first_only, second_only),
    }


def with_verdicts(comparisons: Sequence[dict[str, Any]], alpha: float) -> list[dict[str, Any]]:
    """The comparisons of one table with p_holm (Holm across the table) and verdict: "better" or
    "worse" (the first side against the second) when p_holm < alpha and the interval excludes 0,
    else "no difference"."""
    adjusted = holm([comparison["p_value"] for comparison in comparisons])
    judged = []
    for comparison, p_holm in zip(comparisons, adjusted):
        verdict = "no difference"
        if p_holm < alpha and comparison["low"] > 0:
            verdict = "better"
        elif p_holm < alpha and comparison["high"] < 0:
            verdict = "worse"
        judged.append({**comparison, "p_holm": float(p_holm), "verdict": verdict})
    return judged
