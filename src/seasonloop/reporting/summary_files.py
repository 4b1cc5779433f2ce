"""The summary's files: the study's tables as markdown and CSV, its comparison figures, and the
long tables `dvc plots show` reads, all from one run's EvaluationResults (seasonloop.reporting.results).

Which folder they go to is the caller's; the file names inside it are fixed here (the report and
dvc.yaml's plots name them).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.evaluation.outcomes import QueryOutcomes
from seasonloop.io import load_array
from seasonloop.params.settings import StatisticsConfig
from seasonloop.plots import plot_pr_curves, plot_similarity_grid
from seasonloop.reporting.dvcplots import pr_long
from seasonloop.reporting.fraction_plots import plot_fraction_correct
from seasonloop.reporting.results import EvaluationResults
from seasonloop.reporting.summary import (
    fraction_correct_table,
    interval_tables,
    markdown_table,
    pr_landmarks,
    pr_landmarks_table,
    side_by_side_markdown,
    study_table,
)
from seasonloop.significance.means import mean_interval


def mean_intervals(
    outcomes_dir: Path,
    learners: Sequence[str],
    variants: Sequence[tuple[str, str, str]],
    pairs: Sequence[str],
    settings: StatisticsConfig,
) -> dict[str, dict[str, float]]:
    """label -> {low, high, ...}: the interval of the fraction correct averaged over `pairs`
    (seasonloop.significance.means), from the evaluate stages' per-query outcomes
    outcomes_dir/<learner>/<pair><suffix>.csv of every learner and (metric, matcher, suffix) of `variants`."""
    intervals = {}
    for _, _, suffix in variants:
        for learner in learners:
            outcomes = [QueryOutcomes.read_csv(outcomes_dir / learner / f"{pair}{suffix}.csv") for pair in pairs]
            intervals[learner + suffix] = mean_interval(
                [o.correct for o in outcomes], [o.query_place for o in outcomes], settings
            )
    return intervals


def summary_record(results: EvaluationResults, mean_interval_of: Mapping[str, Mapping[str, float]]) -> dict[str, Any]:
    """Fraction correct per label and pair with its 95% interval along the route, its mean per label
    with the mean's interval (mean_interval_of[label], as mean_intervals gives it), and the study's
    PR landmarks beside ours."""
    labels, pairs, metrics = results.labels, results.pairs, results.metrics
    return {
        "fraction_correct": {
            label: {pair: metrics[label][pair]["fraction_correct"] for pair in pairs} for label in labels
        },
        "fraction_correct_interval": {
            label: {pair: metrics[label][pair]["intervals"]["fraction_correct"]["route"] for pair in pairs}
            for label in labels
        },
        "mean_fraction_correct": {
            label: float(np.mean([metrics[label][pair]["fraction_correct"] for pair in pairs])) for label in labels
        },
        "mean_fraction_correct_interval": {label: dict(mean_interval_of[label]) for label in labels},
        "pr_landmarks": pr_landmarks(metrics),
    }


def compare_record(results: EvaluationResults) -> dict[str, float]:
    """label -> fraction correct averaged over the run's pairs, under the main distance, single and
    sequence matching: the compact set DVC compares across experiments (one short column per
    learner and matcher in `dvc exp show`; the per-pair values are in metrics/summary.json)."""
    return {
        label: float(np.mean([results.metrics[label][pair]["fraction_correct"] for pair in results.pairs]))
        for label in results.labels
        if results.metric_of[label] == results.main_metric
    }


def write_tables(out: Path, results: EvaluationResults, runtime: Mapping[str, Mapping[str, Any]]) -> None:
    """fraction_correct.md (ours beside the study's numbers) and .csv, pr_landmarks.md, runtime.md."""
    ours = fraction_correct_table(results.metrics, results.pairs)
    study = study_table(results.labels, results.pairs)
    (out / "fraction_correct.md").write_text(
        "Fraction of correct matches (%), ours with its 95% interval along the route in square brackets "
        "(the study's in round brackets where it gives one; [not enough queries]: too few for an interval, "
        "or for the length of the runs of the learner's outcomes, as metrics/eval's reason says)\n\n"
        + side_by_side_markdown(ours, study, interval_tables(results.metrics, results.pairs))
    )
    long = ours.reset_index(names="learner").melt(id_vars="learner", var_name="pair", value_name="fraction_correct")
    long["label"] = long["pair"] + " " + long["learner"]
    long.to_csv(out / "fraction_correct.csv", index=False, float_format="%.3f")
    landmarks = pr_landmarks(results.metrics)
    landmark_cells = pr_landmarks_table(landmarks).map(lambda value: "n/a" if np.isnan(value) else f"{value:.1f}")
    (out / "pr_landmarks.md").write_text(
        "The study's precision-recall landmarks beside ours (%), single-image matching\n\n"
        + markdown_table(landmark_cells.set_index(landmark_cells.index.map(" ".join)), "pair learner landmark")
    )
    runtime_cells = pd.DataFrame(runtime).T.map(
        lambda value: f"{value:.4g}" if isinstance(value, float) else str(value)
    )
    (out / "runtime.md").write_text(
        "Fit time (study Table 6) and feature time per test image (Table 7)\n\n"
        + markdown_table(runtime_cells, "learner")
    )


def write_figures(out: Path, results: EvaluationResults) -> None:
    """fraction_correct.png for the main metric, fraction_correct@<metric>.png for each extra one
    (study Figures 10, 11, 16, 17), and pr_<pair>.png: the main metric's PR curves overlaid."""
    ours = fraction_correct_table(results.metrics, results.pairs)
    study = study_table(results.labels, results.pairs)
    low, high = (bound / 100 for bound in interval_tables(results.metrics, results.pairs))
    for metric in dict.fromkeys(results.metric_of.values()):
        rows = [label for label in results.labels if results.metric_of[label] == metric]
        suffix = "" if metric == results.main_metric else f"@{metric}"
        plot_fraction_correct(
            ours.loc[rows] / 100,
            out / f"fraction_correct{suffix}.png",
            title=f"Fraction of correct matches per pair, {metric} distance",
            reference=study.loc[rows] / 100,
            intervals=(low.loc[rows], high.loc[rows]),
        )
    for pair in results.pairs:
        plot_pr_curves(results.curves[pair], f"Precision-recall, {pair} (database-queries)", out / f"pr_{pair}.png")


def write_dvc_plots(out: Path, results: EvaluationResults, training_curves: pd.DataFrame) -> None:
    """pr/<pair>.csv (every learner's curve, a `learner` column) and training_loss.csv (the loss
    curves only of seasonloop.reporting.dvcplots.training_curves: the learning rate is on another scale).

    One file per pair with every learner, so dvc.yaml names no file that a subset of learners or
    seasons lacks."""
    (out / "pr").mkdir()
    for pair in results.pairs:
        pr_long(results.curves[pair]).to_csv(out / "pr" / f"{pair}.csv", index=False, float_format="%.6g")
    losses = training_curves[training_curves["metric"].str.startswith("loss/")]
    losses.to_csv(out / "training_loss.csv", index=False, float_format="%.6g")


def write_similarity_figure(path: Path, thumbnails: Path, learners: Sequence[str], pairs: Sequence[str]) -> None:
    """One figure of every learner's single-image similarity matrix of every pair under the main
    metric, from the evaluate stages' thumbnails thumbnails/<learner>/<pair>.npy."""
    plot_similarity_grid(
        {learner: {pair: load_array(thumbnails / learner / f"{pair}.npy") for pair in pairs} for learner in learners},
        path,
        "Query x database similarity, single-image matching (true matches on the diagonal)",
    )


def write_summary_files(
    out: Path, results: EvaluationResults, runtime: Mapping[str, Mapping[str, Any]], training_curves: pd.DataFrame
) -> None:
    """Every file of the summary folder `out` (the tables, the figures, the dvc plots tables)."""
    write_tables(out, results, runtime)
    write_figures(out, results)
    write_dvc_plots(out, results, training_curves)
