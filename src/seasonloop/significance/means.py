"""The interval of a fraction correct averaged over a run's season pairs.

Each pair's fraction is resampled as its own interval is (seasonloop.significance.intervals: the
moving block bootstrap over its queries in route order) and a resample's mean is the mean of the
pairs' resampled fractions. The blocks depend only on a pair's number of queries and the
settings, so pairs with as many queries get the same blocks: on a frame-aligned route, where every
pair's queries are the same test places in the same order, a resample draws the same stretches of
route in every pair. A place that is hard in every pair (a tunnel mouth, a snowed-over cutting) is
then drawn or left out in all of them together, the correlation across pairs that the mean's
interval has to keep; resampling each pair on its own would average it away and make it too narrow.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from seasonloop.params.settings import StatisticsConfig
from seasonloop.significance.intervals import block_resampling, percentile_interval, resampled_ratios


def mean_interval(correct_by_pair: Sequence[np.ndarray], settings: StatisticsConfig) -> dict[str, float]:
    """{low, high}: the block-bootstrap interval of the mean over pairs of each pair's fraction of
    correct queries (correct_by_pair: one bool array per pair, in its query order)."""
    if not correct_by_pair:
        raise ValueError("mean_interval: no season pair to average over")
    resampled = []
    for correct in correct_by_pair:
        correct = np.asarray(correct, np.float64)
        resampling = block_resampling(len(correct), settings)
        resampled.append(resampled_ratios(correct, np.ones_like(correct), resampling))
    low, high = percentile_interval(np.mean(resampled, axis=0), settings.level)
    return {"low": low, "high": high}
