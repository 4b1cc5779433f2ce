"""Every evaluation of one learner: each season pair of the test set under each metric and matcher,
written as metrics JSON, a PR-curve CSV and a thumbnail of the distances matched on (the summary
stage draws the thumbnails of every learner and pair as one figure).

seasonloop.evaluation.matchers defines the evaluations (metric x matcher) and computes one;
this module runs them over the pairs and writes what they give.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from seasonloop.evaluation.blocks import evaluate_in_blocks, pair_distances
from seasonloop.evaluation.ground_truth import PairTruth
from seasonloop.evaluation.matchers import evaluations
from seasonloop.evaluation.pair_truths import truth_file
from seasonloop.io import load_array, save_array, write_json
from seasonloop.params.schema import pair_name
from seasonloop.params.settings import EvaluateConfig, SequenceConfig


def evaluate_learner(
    features: Path,
    pairs: Sequence[tuple[str, str]],
    truths: Path,
    evaluate: EvaluateConfig,
    sequence: SequenceConfig,
    metrics_dir: Path,
    pr_dir: Path,
    similarity_dir: Path,
) -> None:
    """Evaluate the descriptors features/<season>.npy of one learner on `pairs` (database, query)
    against their ground truth truths/<database>-<query>.npz; writes <pair><suffix>.json to
    metrics_dir, .csv to pr_dir and .npy (similarity_thumbnail) to similarity_dir."""
    if not pairs:
        raise ValueError("evaluate.pairs: no pair has both of its seasons in data.seasons")
    variants = evaluations(evaluate)
    for database, query in pairs:
        descriptors = [load_array(features / f"{season}.npy") for season in (database, query)]
        truth = PairTruth.load(truth_file(truths, database, query))
        check_rows(descriptors, truth, features, (database, query))
        for metric in dict.fromkeys(metric for metric, _, _ in variants):
            distance_rows = pair_distances(descriptors[0], descriptors[1], metric)
            for _, matcher, suffix in (variant for variant in variants if variant[0] == metric):
                name = pair_name(database, query) + suffix
                metrics, pr, thumbnail = evaluate_in_blocks(
                    distance_rows, len(descriptors[0]), truth, matcher, evaluate, sequence
                )
                write_json(metrics_dir / f"{name}.json", metrics)
                pr.to_csv(pr_dir / f"{name}.csv", index=False, float_format="%.6g")
                save_array(similarity_dir / f"{name}.npy", thumbnail)


def check_rows(descriptors: Sequence[np.ndarray], truth: PairTruth, features: Path, seasons: Sequence[str]) -> None:
    """One descriptor per test place of each season, or one line saying which file is off."""
    for rows, places, season in zip(descriptors, (truth.database_places, truth.query_places), seasons):
        if len(rows) != len(places):
            raise ValueError(
                f"{features / season}.npy: {len(rows)} descriptors for the {len(places)} test places of {season} "
                "(rerun the features stage)"
            )
