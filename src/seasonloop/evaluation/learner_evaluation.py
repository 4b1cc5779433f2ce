"""Every evaluation of one learner: each season pair of the test set under each metric and matcher,
written as metrics JSON (with the intervals of fraction correct and recall@1:
seasonloop.significance.intervals), a PR-curve CSV, a thumbnail of the distances matched on (the
summary stage draws the thumbnails of every learner and pair as one figure) and each query's
outcome (seasonloop.evaluation.outcomes: what the paired comparisons between learners read).

seasonloop.evaluation.matchers defines the evaluations (metric x matcher) and computes one;
this module runs them over the pairs and writes what they give.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from tqdm import tqdm

from seasonloop.data.ground_truth import PairTruth, truth_file
from seasonloop.evaluation.blocks import PairEvaluation, evaluate_in_blocks, pair_distances
from seasonloop.evaluation.folds import pooled_evaluation
from seasonloop.evaluation.matchers import evaluations, get_matcher
from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.io import load_array, save_array, write_json
from seasonloop.params.seasons import pair_name
from seasonloop.params.settings import EvaluateConfig, SequenceConfig, StatisticsConfig
from seasonloop.significance.intervals import fraction_interval, persistence


def evaluate_learner(
    features: Sequence[Path],
    pairs: Sequence[tuple[str, str]],
    truths: Sequence[Path],
    evaluate: EvaluateConfig,
    sequence: SequenceConfig,
    statistics: StatisticsConfig,
    out_dirs: Sequence[Path],
    progress: bool = False,
) -> None:
    """Evaluate the descriptors <features>/<season>.npy of one learner on `pairs` (database, query)
    against their ground truth <truths>/<database>-<query>.npz; writes <pair><suffix>.json,
    .csv (PR curve), .npy (similarity_thumbnail) and .csv (outcomes) to out_dirs' four folders
    (metrics, PR curves, thumbnails, outcomes). features and truths hold one folder per fold of the
    split (one: the study's split; several: each fold evaluated on its own and the pair's result
    pooled over them, seasonloop.evaluation.folds). `progress`: a bar over the pairs' distance
    matrices (one per pair, fold, kind of descriptor and metric: what the time goes to)."""
    metrics_dir, pr_dir, similarity_dir, outcomes_dir = out_dirs
    if not pairs:
        raise ValueError("evaluate.pairs: no pair has both of its seasons in data.seasons")
    if len(features) != len(truths):
        raise ValueError(
            f"{features[0]}: descriptors of {len(features)} folds for ground truth of {len(truths)} "
            "(rerun the features stage)"
        )
    groups = distance_groups(evaluations(evaluate))
    per_pair = sum(len(by_metric) for _, by_metric in groups)
    bar = tqdm(
        total=len(pairs) * len(features) * per_pair,
        desc=f"evaluate {features[-1].name}",
        unit="distances",
        disable=not progress,
    )
    # the intervals wait for every pair: a suffix's runs' persistence is pooled over its pairs
    finished: dict[str, dict[str, tuple[dict[str, Any], QueryOutcomes]]] = {}
    for database, query in pairs:
        per_fold: dict[str, list[PairEvaluation]] = {}
        for fold_features, fold_truths in zip(features, truths):
            for suffix, evaluation in pair_evaluations(
                fold_features, fold_truths, (database, query), groups, evaluate, sequence, bar
            ):
                per_fold.setdefault(suffix, []).append(evaluation)
        for suffix, evaluations_of_folds in per_fold.items():
            name = pair_name(database, query) + suffix
            evaluation = pooled_evaluation(evaluations_of_folds, evaluate.confidence)
            evaluation.pr.to_csv(pr_dir / f"{name}.csv", index=False, float_format="%.6g")
            save_array(similarity_dir / f"{name}.npy", evaluation.thumbnail)
            evaluation.outcomes.to_csv(outcomes_dir / f"{name}.csv")
            finished.setdefault(suffix, {})[name] = (evaluation.metrics, evaluation.outcomes)
    bar.close()
    for of_pairs in finished.values():
        intervals = metric_intervals([outcomes for _, outcomes in of_pairs.values()], statistics)
        for (name, (metrics, _)), pair_intervals in zip(of_pairs.items(), intervals):
            write_json(metrics_dir / f"{name}.json", {**metrics, "intervals": pair_intervals})


def pair_evaluations(
    features: Path,
    truths: Path,
    pair: tuple[str, str],
    groups: list[tuple[str, list[tuple[str, list[tuple[str, str]]]]]],
    evaluate: EvaluateConfig,
    sequence: SequenceConfig,
    bar: tqdm,
) -> list[tuple[str, PairEvaluation]]:
    """(suffix, evaluation) of every evaluation of one pair of one fold (its descriptors in
    `features`, its truth in `truths`), grouped as distance_groups says; `bar` advances at each
    distance matrix."""
    database, query = pair
    descriptors = [load_array(features / f"{season}.npy") for season in pair]
    truth = PairTruth.load(truth_file(truths, database, query))
    check_rows(descriptors, truth, features, pair)
    found = []
    for describing, by_metric in groups:
        # each traverse's descriptors as the matchers of this group take them, once for every metric
        taken = get_matcher(describing)
        database_taken = taken.described(descriptors[0], truth.database_places, sequence)
        queries_taken = taken.described(descriptors[1], truth.query_places, sequence)
        for metric, matchers in by_metric:
            distance_rows = pair_distances(database_taken, queries_taken, metric)
            for matcher, suffix in matchers:
                evaluation = evaluate_in_blocks(distance_rows, len(descriptors[0]), truth, matcher, evaluate, sequence)
                found.append((suffix, evaluation))
            bar.update()
    return found


def distance_groups(
    variants: Sequence[tuple[str, str, str]],
) -> list[tuple[str, list[tuple[str, list[tuple[str, str]]]]]]:
    """The evaluations (metric, matcher, suffix) grouped by what they share: the descriptors their
    matchers take (the traverses' own, or one kind of sequence descriptors: one matcher of the group
    names it), then under each metric the distances; the (matcher, suffix) of each in table order.
    Only one group's descriptors and one metric's distances are held at a time."""
    groups: dict[object, tuple[str, dict[str, list[tuple[str, str]]]]] = {}
    for metric, matcher, suffix in variants:
        _, by_metric = groups.setdefault(get_matcher(matcher).describe, (matcher, {}))
        by_metric.setdefault(metric, []).append((matcher, suffix))
    return [(describing, list(by_metric.items())) for describing, by_metric in groups.values()]


def check_rows(descriptors: Sequence[np.ndarray], truth: PairTruth, features: Path, seasons: Sequence[str]) -> None:
    """One descriptor per test place of each season, or one line saying which file is off."""
    for rows, places, season in zip(descriptors, (truth.database_places, truth.query_places), seasons):
        if len(rows) != len(places):
            raise ValueError(
                f"{features / season}.npy: {len(rows)} descriptors for the {len(places)} test places of {season} "
                "(rerun the features stage)"
            )


def metric_intervals(outcomes_of_pairs: Sequence[QueryOutcomes], statistics: StatisticsConfig) -> list[dict[str, Any]]:
    """The intervals of each pair's fraction_correct (every query counted) and recall_at_1 (the
    queries that have a correct place), under the keys of the metrics they belong to: one
    evaluation (learner, matcher, metric) on every pair, the runs' persistence of each metric
    pooled over the pairs (seasonloop.significance.intervals.persistence)."""
    correct = persistence(outcomes.correct for outcomes in outcomes_of_pairs)
    recall = persistence(outcomes.hit_at_1[outcomes.has_match] for outcomes in outcomes_of_pairs)
    return [
        {
            "fraction_correct": fraction_interval(
                outcomes.correct, np.ones_like(outcomes.correct), statistics, runs=correct
            ),
            "recall_at_1": fraction_interval(outcomes.hit_at_1, outcomes.has_match, statistics, runs=recall),
        }
        for outcomes in outcomes_of_pairs
    ]
