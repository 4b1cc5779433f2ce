"""One evaluation of a season pair: distances, the matcher, metrics and PR curve.

A learner is evaluated once per (metric, matcher): the metric `evaluate.metric` and every metric
of `evaluate.extra_metrics`, each with every matcher of `evaluate.matchers`. Results carry a
suffix in file names and table labels: "@<metric>" for an extra metric (none for the main one),
then the matcher's ("+seq" for sequence matching), e.g. "pca", "pca+seq", "pca@cityblock+seq".

MATCHER_REGISTRY holds the matchers (name -> suffix and the function that turns descriptor
distances into the distances matched on); MATCHERS is its name -> suffix view. The params are
checked once, by seasonloop.params.schema's schema when EvaluateConfig / SequenceConfig are built: this
module only computes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.evaluation.ground_truth import PairTruth
from seasonloop.evaluation.matching import distance_matrix
from seasonloop.evaluation.metrics import evaluate_truth
from seasonloop.evaluation.sequence import sequence_distances
from seasonloop.params.settings import EvaluateConfig, SequenceConfig

# (distances (N, M), database_places (M,), query_places (N,), sequence) -> the distances to match on
MatchDistances = Callable[[np.ndarray, np.ndarray, np.ndarray, SequenceConfig], np.ndarray]


@dataclass(frozen=True)
class Matcher:
    """One value of evaluate.matchers: the suffix its results carry, and what it matches on."""

    suffix: str
    distances: MatchDistances


def _single_image(
    distances: np.ndarray, database_places: np.ndarray, query_places: np.ndarray, sequence: SequenceConfig
) -> np.ndarray:
    return distances


def _sequence(
    distances: np.ndarray, database_places: np.ndarray, query_places: np.ndarray, sequence: SequenceConfig
) -> np.ndarray:
    # Sequence matching restarts at every break in the place ids (seasonloop.evaluation.sequence).
    return sequence_distances(
        distances,
        length=int(sequence.length),
        v_min=float(sequence.v_min),
        v_max=float(sequence.v_max),
        v_steps=int(sequence.v_steps),
        window=int(sequence.window),
        query_places=query_places,
        database_places=database_places,
        window_at_breaks=sequence.window_at_breaks,
    )


# A new matcher is one function plus one line here; the order is config.MATCHER_NAMES'.
MATCHER_REGISTRY: dict[str, Matcher] = {"single": Matcher("", _single_image), "sequence": Matcher("+seq", _sequence)}
# matcher -> the suffix its results carry in file names and tables ("pca" vs "pca+seq")
MATCHERS: dict[str, str] = {name: matcher.suffix for name, matcher in MATCHER_REGISTRY.items()}


def get_matcher(name: str) -> Matcher:
    """The matcher registered under `name`."""
    if name not in MATCHER_REGISTRY:
        raise ValueError(f"evaluate.matchers: unknown matcher '{name}' (known: {', '.join(MATCHER_REGISTRY)})")
    return MATCHER_REGISTRY[name]


def result_suffix(metric: str, matcher: str, evaluate: EvaluateConfig) -> str:
    """The suffix of one evaluation's results: '@<metric>' for an extra metric, then the matcher's."""
    return ("" if metric == evaluate.metric else f"@{metric}") + get_matcher(matcher).suffix


def evaluations(evaluate: EvaluateConfig) -> list[tuple[str, str, str]]:
    """(metric, matcher, suffix) of every evaluation of a learner on a pair, in table order: the
    main metric's matchers first, then each extra metric's."""
    return [
        (metric, matcher, result_suffix(metric, matcher, evaluate))
        for metric in [evaluate.metric, *evaluate.extra_metrics]
        for matcher in evaluate.matchers
    ]


def match_distances(
    distances: np.ndarray, truth: PairTruth, matcher: str, evaluate: EvaluateConfig, sequence: SequenceConfig
) -> tuple[dict[str, Any], pd.DataFrame, np.ndarray]:
    """(metrics, PR curve, distance matrix used for matching) from one pair's descriptor distances
    and its ground truth (whose place ids tell the sequence matcher where the route breaks).

    evaluate gives the confidence and ratio exclusion; sequence the sequence matcher's settings.
    """
    distances = get_matcher(matcher).distances(distances, truth.database_places, truth.query_places, sequence)
    metrics, pr = evaluate_truth(
        distances, truth, confidence=evaluate.confidence, ratio_exclusion=int(evaluate.ratio_exclusion)
    )
    return metrics, pr, distances


def match_pair(
    database: np.ndarray,
    queries: np.ndarray,
    truth: PairTruth,
    matcher: str,
    evaluate: EvaluateConfig,
    sequence: SequenceConfig,
    metric: str | None = None,
) -> tuple[dict[str, Any], pd.DataFrame, np.ndarray]:
    """(metrics, PR curve, distance matrix used for matching) of one pair with one matcher, under
    `metric` (default evaluate.metric)."""
    distances = distance_matrix(database, queries, metric=evaluate.metric if metric is None else metric)
    return match_distances(distances, truth, matcher, evaluate, sequence)
