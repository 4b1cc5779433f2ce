"""Stage summary: the study's tables and comparison figures from every learner's pair metrics.

Rows are labelled <learner><suffix> (seasonloop.evaluation.result_suffix: "pca", "pca+seq",
"pca@cityblock", ...). Writes metrics/summary.json (fraction correct per label and pair, its mean,
and the study's PR landmarks beside ours), metrics/runtime.json (fit seconds, the study's Table 6;
feature milliseconds per image, Table 7), plots/summary/fraction_correct.{md,csv} (ours beside the
study's numbers; the CSV feeds `dvc plots show`), plots/summary/pr_landmarks.md,
plots/summary/runtime.md, and the PNG figures of fraction correct per pair (study Figures 10, 11,
16, 17; fraction_correct.png for evaluate.metric, fraction_correct@<metric>.png for each extra
metric) and overlaid PR curves per pair under evaluate.metric (Figures 9, 14, 15, 17); for
`dvc plots show`, plots/summary/pr/<pair>.csv (every learner's curve under evaluate.metric, a
`learner` column) and plots/summary/training_loss.csv (the dvclive loss curves of the learners
that train in epochs).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from _common import data_seasons, load_params, param, stage_main

from seasonloop.config import available_pairs, pair_name
from seasonloop.dvcplots import pr_long, training_curves
from seasonloop.evaluation import evaluations
from seasonloop.io import read_json, staged_dir, write_json
from seasonloop.plots import plot_fraction_correct, plot_pr_curves
from seasonloop.summary import (
    fraction_correct_table,
    markdown_table,
    pr_landmarks,
    pr_landmarks_table,
    side_by_side_markdown,
    study_table,
)


@stage_main
def main() -> None:
    params = load_params("learners", "data.seasons", "evaluate")
    methods = list(param(params, "learners"))
    evaluate = param(params, "evaluate")
    variants = evaluations(evaluate)
    pairs = [pair_name(a, b) for a, b in available_pairs(data_seasons(params), param(params, "evaluate.pairs"))]
    labels = [method + suffix for _, _, suffix in variants for method in methods]
    metric_of = {method + suffix: metric for metric, _, suffix in variants for method in methods}

    results = {label: {} for label in labels}
    curves = {pair: {} for pair in pairs}  # the PR figures: evaluate.metric's rows only, to stay readable
    for metric, _, suffix in variants:
        for method in methods:
            label = method + suffix
            for pair in pairs:
                name = pair + suffix
                results[label][pair] = read_json(Path("metrics/eval") / method / f"{name}.json")
                if metric == evaluate["metric"]:
                    pr = pd.read_csv(Path("plots/pr") / method / f"{name}.csv")
                    curves[pair][label] = (pr["recall"].to_numpy(), pr["precision"].to_numpy())

    ours = fraction_correct_table(results, pairs)
    study = study_table(labels, pairs)
    landmarks = pr_landmarks(results)
    write_json(Path("metrics/summary.json"), {
        "fraction_correct": {label: {pair: results[label][pair]["fraction_correct"] for pair in pairs} for label in labels},
        "mean_fraction_correct": {label: float(np.mean([results[label][pair]["fraction_correct"] for pair in pairs])) for label in labels},
        "pr_landmarks": landmarks,
    })

    runtime = {}
    for method in methods:
        fit = read_json(Path("metrics/fit") / f"{method}.json")
        per_season = [read_json(Path("metrics/features") / method / f"{season}.json") for season in data_seasons(params)]
        runtime[method] = {
            "fit_seconds": fit["fit_seconds"],
            "n_train_images": fit["n_train_images"],
            "feature_ms_per_image": float(np.mean([s["ms_per_image"] for s in per_season])),
            "descriptor_dimension": per_season[0]["dimension"],
        }
    write_json(Path("metrics/runtime.json"), runtime)

    with staged_dir(Path("plots/summary")) as out:
        (out / "fraction_correct.md").write_text(
            "Fraction of correct matches (%), ours (the study's in brackets where it gives one)\n\n"
            + side_by_side_markdown(ours, study))
        long = ours.reset_index(names="method").melt(id_vars="method", var_name="pair", value_name="fraction_correct")
        long["label"] = long["pair"] + " " + long["method"]
        long.to_csv(out / "fraction_correct.csv", index=False, float_format="%.3f")
        landmark_cells = pr_landmarks_table(landmarks).map(lambda value: "n/a" if np.isnan(value) else f"{value:.1f}")
        (out / "pr_landmarks.md").write_text(
            "The study's precision-recall landmarks beside ours (%), single-image matching\n\n"
            + markdown_table(landmark_cells.set_index(landmark_cells.index.map(" ".join)), "pair method landmark"))
        runtime_cells = pd.DataFrame(runtime).T.map(lambda value: f"{value:.4g}" if isinstance(value, float) else str(value))
        (out / "runtime.md").write_text("Fit time (study Table 6) and feature time per test image (Table 7)\n\n"
                                        + markdown_table(runtime_cells, "method"))
        for metric in dict.fromkeys(metric_of.values()):
            rows = [label for label in labels if metric_of[label] == metric]
            suffix = "" if metric == evaluate["metric"] else f"@{metric}"
            plot_fraction_correct(ours.loc[rows] / 100, out / f"fraction_correct{suffix}.png",
                                  title=f"Fraction of correct matches per pair, {metric} distance",
                                  reference=study.loc[rows] / 100)
        for pair in pairs:
            plot_pr_curves(curves[pair], f"Precision-recall, {pair} (database-queries)", out / f"pr_{pair}.png")
        # `dvc plots show` reads these: one file per pair with every learner, and every learner's
        # training curves, so dvc.yaml names no file that a subset of learners or seasons lacks
        (out / "pr").mkdir()
        for pair in pairs:
            pr_long(curves[pair]).to_csv(out / "pr" / f"{pair}.csv", index=False, float_format="%.6g")
        curves = training_curves(Path("logs"), methods)
        # the losses only (loss/train, loss/validation): the learning rate is on another scale
        curves = curves[curves["metric"].str.startswith("loss/")]
        curves.to_csv(out / "training_loss.csv", index=False, float_format="%.6g")


if __name__ == "__main__":
    main()
