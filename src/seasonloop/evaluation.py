"""One evaluation of a season pair: distances, optional sequence matching, metrics and PR curve."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.matching import distance_matrix
from seasonloop.metrics import evaluate_pair
from seasonloop.sequence import sequence_distances

# matcher -> the suffix its results carry in file names and tables ("pca" vs "pca+seq")
MATCHERS: dict[str, str] = {"single": "", "sequence": "+seq"}


def match_pair(
    database: np.ndarray,
    queries: np.ndarray,
    database_places: np.ndarray,
    query_places: np.ndarray,
    matcher: str,
    evaluate: Mapping[str, Any],
    sequence: Mapping[str, Any],
) -> tuple[dict[str, Any], pd.DataFrame, np.ndarray]:
    """(metrics, PR curve, distance matrix used for matching) of one pair with one matcher."""
    distances = distance_matrix(database, queries, metric=evaluate["metric"])
    if matcher == "sequence":
        distances = sequence_distances(
            distances, length=int(sequence["length"]), v_min=float(sequence["v_min"]),
            v_max=float(sequence["v_max"]), v_steps=int(sequence["v_steps"]), window=int(sequence["window"]))
    elif matcher != "single":
        raise ValueError(f"evaluate.matchers: unknown matcher '{matcher}' (known: {', '.join(MATCHERS)})")
    metrics, pr = evaluate_pair(distances, database_places, query_places,
                                tolerance=int(evaluate["tolerance_frames"]), confidence=evaluate["confidence"])
    return metrics, pr, distances
