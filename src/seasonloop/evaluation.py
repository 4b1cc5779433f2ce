"""One evaluation of a season pair: distances, optional sequence matching, metrics and PR curve.

A learner is evaluated once per (metric, matcher): the metric `evaluate.metric` and every metric
of `evaluate.extra_metrics`, each with every matcher of `evaluate.matchers`. Results carry a
suffix in file names and table labels: "@<metric>" for an extra metric (none for the main one),
then the matcher's ("+seq" for sequence matching), e.g. "pca", "pca+seq", "pca@cityblock+seq".
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.matching import CONFIDENCES, METRICS, distance_matrix
from seasonloop.metrics import evaluate_pair
from seasonloop.sequence import sequence_distances

# matcher -> the suffix its results carry in file names and tables ("pca" vs "pca+seq")
MATCHERS: dict[str, str] = {"single": "", "sequence": "+seq"}


def _check_list(values: Any, key: str, known: tuple[str, ...] | dict[str, str]) -> list[str]:
    if isinstance(values, str) or not isinstance(values, (list, tuple)):
        raise ValueError(f"{key} must be a list, got {values!r}")
    for value in values:
        if value not in known:
            raise ValueError(f"{key}: unknown entry {value!r} (known: {', '.join(known)})")
    if len(set(values)) != len(values):
        raise ValueError(f"{key}: repeated entry in {list(values)}")
    return list(values)


def check_matching(evaluate: Mapping[str, Any]) -> None:
    """Raise a one-line ValueError naming the key for a bad confidence, ratio_exclusion or tolerance."""
    for key in ("confidence", "ratio_exclusion", "tolerance_frames"):
        if key not in evaluate:
            raise ValueError(f"params.yaml: missing key 'evaluate.{key}'")
    if evaluate["confidence"] not in CONFIDENCES:
        raise ValueError(
            f"evaluate.confidence must be one of {', '.join(CONFIDENCES)}, got {evaluate['confidence']!r}")
    for key in ("ratio_exclusion", "tolerance_frames"):
        value = evaluate[key]
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise ValueError(f"evaluate.{key} must be an integer >= 0 (places), got {value!r}")


def result_suffix(metric: str, matcher: str, evaluate: Mapping[str, Any]) -> str:
    """The suffix of one evaluation's results: '@<metric>' for an extra metric, then the matcher's."""
    return ("" if metric == evaluate["metric"] else f"@{metric}") + MATCHERS[matcher]


def evaluations(evaluate: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    """(metric, matcher, suffix) of every evaluation of a learner on a pair, in table order: the
    main metric's matchers first, then each extra metric's. Reads (and checks) evaluate.metric,
    evaluate.extra_metrics and evaluate.matchers only."""
    for key in ("metric", "extra_metrics", "matchers"):
        if key not in evaluate:
            raise ValueError(f"params.yaml: missing key 'evaluate.{key}'")
    if evaluate["metric"] not in METRICS:
        raise ValueError(f"evaluate.metric must be one of {', '.join(METRICS)}, got {evaluate['metric']!r}")
    extra = _check_list(evaluate["extra_metrics"], "evaluate.extra_metrics", METRICS)
    if evaluate["metric"] in extra:
        raise ValueError(f"evaluate.extra_metrics: {evaluate['metric']!r} is already evaluate.metric")
    _check_list(evaluate["matchers"], "evaluate.matchers", MATCHERS)
    return [(metric, matcher, result_suffix(metric, matcher, evaluate))
            for metric in [evaluate["metric"], *evaluate["extra_metrics"]] for matcher in evaluate["matchers"]]


def match_distances(
    distances: np.ndarray,
    database_places: np.ndarray,
    query_places: np.ndarray,
    matcher: str,
    evaluate: Mapping[str, Any],
    sequence: Mapping[str, Any],
) -> tuple[dict[str, Any], pd.DataFrame, np.ndarray]:
    """(metrics, PR curve, distance matrix used for matching) from one pair's descriptor distances.

    Sequence matching restarts at every break in the place ids (seasonloop.sequence).
    """
    check_matching(evaluate)
    if matcher == "sequence":
        distances = sequence_distances(
            distances, length=int(sequence["length"]), v_min=float(sequence["v_min"]),
            v_max=float(sequence["v_max"]), v_steps=int(sequence["v_steps"]), window=int(sequence["window"]),
            query_places=query_places, database_places=database_places)
    elif matcher != "single":
        raise ValueError(f"evaluate.matchers: unknown matcher '{matcher}' (known: {', '.join(MATCHERS)})")
    metrics, pr = evaluate_pair(distances, database_places, query_places,
                                tolerance=int(evaluate["tolerance_frames"]), confidence=evaluate["confidence"],
                                ratio_exclusion=int(evaluate["ratio_exclusion"]))
    return metrics, pr, distances


def match_pair(
    database: np.ndarray,
    queries: np.ndarray,
    database_places: np.ndarray,
    query_places: np.ndarray,
    matcher: str,
    evaluate: Mapping[str, Any],
    sequence: Mapping[str, Any],
    metric: str | None = None,
) -> tuple[dict[str, Any], pd.DataFrame, np.ndarray]:
    """(metrics, PR curve, distance matrix used for matching) of one pair with one matcher, under
    `metric` (default evaluate.metric)."""
    distances = distance_matrix(database, queries, metric=evaluate["metric"] if metric is None else metric)
    return match_distances(distances, database_places, query_places, matcher, evaluate, sequence)
