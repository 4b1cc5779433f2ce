"""The study's report sections, each built from the pipeline's result data as read from its JSON
files (seasonloop.reporting.results) and the PNG figures the other stages drew.

Knows nothing of DVC or params.yaml: every builder takes plain Python data and PNG paths or bytes
and returns a seasonloop.reporting.html.Section.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.evaluation.matchers import MATCHER_TITLES, MATCHERS
from seasonloop.reporting.html import Block, Image, Png, Section, Table, Text
from seasonloop.reporting.summary import fraction_correct_table, interval_tables, study_table, with_interval

RECALL_COLUMNS = {
    "recall_at_1": "recall@1",
    "recall_at_5": "recall@5",
    "recall_at_10": "recall@10",
    "recall_at_100_precision": "recall at 100% precision",
    "auc_pr": "AUC-PR",
    "auc_pr_vpr_tutorial": "AUC-PR (VPR_Tutorial)",
    "extended_precision": "Extended Precision (VPR-Bench)",
}
DATASET_COLUMNS = {"frames": "places (frames)", "train": "train", "train_augmented": "train, augmented", "test": "test"}
RUNTIME_COLUMNS = {
    "fit_seconds": "fit (s)",
    "n_train_images": "training images",
    "feature_ms_per_image": "features (ms / image)",
    "descriptor_dimension": "descriptor dimension",
    "trained_on": "trained on",
}


TRUTH_COLUMNS = {
    "n_queries": "queries",
    "n_database": "database places",
    "n_without_match": "queries without a correct place",
    "mean_correct_per_query": "correct places per query",
}


def _labelled(frame: pd.DataFrame, columns: Mapping[str, str]) -> pd.DataFrame:
    """The known columns first, in the order of `columns` and renamed by it, then any others."""
    order = [key for key in columns if key in frame] + [key for key in frame if key not in columns]
    return frame[order].rename(columns=columns)


def dataset_section(dataset: Mapping[str, Any], preview: Png, truth: Mapping[str, Any] | None = None) -> Section:
    """Table 3 of the study (places, train, test per season; what the split dropped), which ground
    truth says what is correct (truth: metrics/ground_truth.json) and a preview."""
    seasons = _labelled(pd.DataFrame.from_dict(dataset["seasons"], orient="index"), DATASET_COLUMNS)
    route = pd.DataFrame(
        {
            "places": {
                "dropped from test: tunnels": dataset["dropped_tunnel"],
                "dropped from test: station stops": dataset["dropped_stop"],
                "gap between train and test": dataset["gap"],
            }
        }
    )
    blocks: list[Block] = []
    if "folds" in dataset:
        folds = dataset["folds"]
        tested = ", ".join(f"{season} {count}" for season, count in folds["test"].items())
        blocks.append(
            Text(
                f"Every place tested: {folds['count']} folds along the route (split.folds; docs/pipeline.md, "
                f"'Every place a test place'), test places over all folds: {tested}. Fraction correct, the PR "
                "curves and landmarks, the paired comparisons and the similarity of every pair hold every fold's "
                "queries, each matched against its own fold's test places of the database season; the tables "
                "below, the example matches, the runtimes' fit times, the training-season effect, the CAE widths "
                "and the study's figures are the study's split alone (the last fold)."
            )
        )
    blocks += [Table("Images per season", seasons), Table("Places left out of every season", route)]
    if "detection" in dataset:
        detection = pd.DataFrame.from_dict(dataset["detection"], orient="index")
        blocks.append(
            Table(
                "Tunnel and stop detection against the route's true tunnels and stops", detection, float_format="{:.3f}"
            )
        )
    if truth is not None:
        blocks.append(Text(f"Ground truth ({truth['kind']}): a match is correct when it is {truth['correct']}."))
        # by name: metrics/ground_truth.json is written with sorted keys
        pairs = _labelled(pd.DataFrame.from_dict(truth["pairs"], orient="index"), TRUTH_COLUMNS)
        blocks.append(Table("Ground truth per pair (database-queries)", pairs, float_format="{:.2f}"))
    blocks.append(Image("The same places in every season", preview))
    return Section("Dataset", blocks)


def _beside_study(
    ours: pd.DataFrame, study: pd.DataFrame, intervals: tuple[pd.DataFrame, pd.DataFrame]
) -> pd.DataFrame:
    """Columns (pair, ours) and (pair, study) side by side; a pair the study gives no number for has ours only.
    Ours carries its 95% interval along the route, intervals = (low, high) in %, to whole percent.

    The study's numbers are whole percentages, so they are shown without decimals.
    """
    columns = {}
    low, high = intervals
    for pair in ours.columns:
        columns[(pair, "ours")] = [
            with_interval(value, low.loc[label, pair], high.loc[label, pair]) for label, value in ours[pair].items()
        ]
        if study[pair].notna().any():
            columns[(pair, "study (S)")] = study[pair].map(lambda value: "–" if np.isnan(value) else f"{value:.0f}")
    # the index named: a table the study gives no number for has only lists, which pandas numbers 0, 1, ...
    return pd.DataFrame(columns, index=ours.index)


_FRACTION_CORRECT_INTRO = (
    "Fraction of correct matches: correct best matches / queries, in %, with its 95% interval in "
    "square brackets (allowing for runs of successes along the route: section Paired comparisons). "
    "Pairs are database-queries; "
    "(S) marks the study's numbers, given for single-image matching on three pairs only. "
    "Rows named learner@metric use that distance (evaluate.extra_metrics) instead of the main one "
    "(evaluate.metric). What sequence matching and L1 change, with whether it is significant: "
    "section Paired comparisons. FastICA's unmixing is orthogonal in the whitened space, so under cosine and "
    "Euclidean distances ICA matches exactly like whitened PCA with as many components (pca_whiten): "
    "a gain of ICA over PCA there comes from whitening and keeping the first components, not from "
    "independence. Under L1 (cityblock) the rotation matters, so ica@cityblock against "
    "pca_whiten@cityblock measures what independence adds."
)


def _recall_table(results: Mapping[str, Mapping[str, Mapping[str, float]]], pairs: Sequence[str]) -> pd.DataFrame:
    """Recall metrics in %, one row per (pair, label)."""
    recall = pd.DataFrame.from_dict(
        {
            (pair, label): {
                key: 100 * results[label][pair][key] for key in RECALL_COLUMNS if key in results[label][pair]
            }
            for pair in pairs
            for label in results
        },
        orient="index",
    ).rename(columns=RECALL_COLUMNS)
    recall.index.names = ["pair", "learner"]
    return recall


def fraction_correct_section(
    results: Mapping[str, Mapping[str, Mapping[str, float]]],
    learners: Sequence[str],
    matchers: Sequence[str],
    pairs: Sequence[str],
    figure: Png,
    extra_metrics: Sequence[str] = (),
    extra_figures: Mapping[str, Png] | None = None,
) -> Section:
    """Fraction correct with its interval beside the study's numbers per metric and matcher, recall
    metrics (what sequence matching adds, paired and tested: seasonloop.reporting.comparisons).

    results[label][pair] is the pair's metrics dict (metrics/eval JSON), label = learner + "@<metric>"
    for an extra metric (none for the main one) + MATCHERS[matcher]; extra_figures[metric] is the
    fraction-correct figure of an extra metric.
    """
    for matcher in matchers:
        if matcher not in MATCHERS:
            raise ValueError(f"unknown matcher '{matcher}' (known: {', '.join(MATCHERS)})")
    blocks: list[Block] = [Text(_FRACTION_CORRECT_INTRO)]
    suffixes = {"": "", **{metric: f"@{metric}" for metric in extra_metrics}}
    for metric, metric_suffix in suffixes.items():
        for matcher in matchers:
            labels = [learner + metric_suffix + MATCHERS[matcher] for learner in learners]
            subset = {label: results[label] for label in labels}
            distance = f", {metric} distance" if metric else ""
            blocks.append(
                Table(
                    f"Fraction correct (%), {MATCHER_TITLES[MATCHERS[matcher]]}{distance}",
                    _beside_study(
                        fraction_correct_table(subset, pairs),
                        study_table(labels, pairs),
                        interval_tables(subset, pairs),
                    ),
                )
            )
    blocks.append(
        Table(
            "Recall@N, recall at 100% precision, area under the PR curve and Extended Precision, all in % "
            "(AUC-PR in the study's convention, where recall reaches 100%; AUC-PR (VPR_Tutorial) with recall "
            "= TP / queries, which ends at the fraction correct; Extended Precision as VPR-Bench computes it: "
            "the precision of the most confident matches plus the recall at 100% precision over the correct "
            "matches, halved, so on a few hundred queries it turns on whether the most confident match is right)",
            _recall_table(results, pairs),
        )
    )
    blocks.append(
        Image(
            "Fraction of correct matches per pair; bars: 95% intervals along the route; diamonds: the study's numbers",
            figure,
        )
    )
    for metric, png in (extra_figures or {}).items():
        blocks.append(Image(f"Fraction of correct matches per pair, {metric} distance", png))
    return Section("Fraction correct", blocks)


def pr_section(curves: Mapping[str, Png], landmarks: pd.DataFrame | None = None) -> Section:
    """One PR figure per pair (pair -> PNG), and the study's PR landmarks beside ours
    (seasonloop.reporting.summary.pr_landmarks_table) when given."""
    blocks: list[Block] = [
        Text(
            "Queries sorted by the confidence of their best match; at each distinct confidence the queries "
            "at least that confident are accepted (tied queries together): at full recall, precision equals "
            "the fraction correct."
        )
    ]
    if landmarks is not None:
        blocks.append(Table("The study's precision-recall landmarks beside ours (%), single-image matching", landmarks))
    blocks += [Image(f"Precision-recall, {pair} (database-queries)", png) for pair, png in curves.items()]
    return Section("Precision-recall curves", blocks)


def similarity_section(figure: Png) -> Section:
    """Every learner's similarity matrix of every pair, one figure (the summary stage's)."""
    return Section(
        "Similarity matrices",
        [
            Image(
                "Query x database similarity, single-image matching: one row per learner, one column per "
                "pair (database-queries); each matrix scaled to its own range, true matches on the diagonal",
                figure,
            )
        ],
    )


def runtime_section(runtime: Mapping[str, Mapping[str, float]]) -> Section:
    """Fit time (study Table 6) and feature time per image (Table 7), runtime[learner][key]."""
    table = _labelled(pd.DataFrame.from_dict(runtime, orient="index"), RUNTIME_COLUMNS)
    return Section(
        "Runtimes",
        [Table("Fit time (study Table 6), feature time per test image (Table 7)", table, float_format="{:.4g}")],
    )


def software_section(environments: Mapping[str, Mapping[str, Any]]) -> Section:
    """The library versions and torch threads each learner was fitted with (metrics/fit/<learner>.json's
    environment): one column when every learner shares them, one per learner otherwise."""
    table = pd.DataFrame(
        {learner: {key: str(value) for key, value in env.items()} for learner, env in environments.items()}
    )
    if len(table.columns) > 1 and (table.nunique(axis=1) == 1).all():
        table = table.iloc[:, [0]].set_axis(["every learner"], axis=1)
    table.index.name = "package"
    return Section(
        "Software",
        [
            Text(
                "What the learners were fitted with (requirements.lock pins the same versions for a new "
                "install): another version or thread count can give other floating-point sums."
            ),
            Table("Library versions at fit time", table),
        ],
    )


def parameters_section(params_text: str) -> Section:
    """The parameter file that produced the report, verbatim."""
    return Section(
        "Parameters", [Text("The parameters that produced this report:"), Text(params_text, preformatted=True)]
    )
