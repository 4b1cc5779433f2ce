"""Stage summary: the study's tables and comparison figures from every learner's pair metrics.

Writes metrics/mean_fraction_correct.json, {label: fraction correct averaged over the pairs} for
every learner and matcher under evaluate.metric: the only file dvc.yaml declares as metrics, so
that `dvc exp show` and `dvc metrics diff` compare a compact, stable set in short columns ("pca",
"pca+seq"); metrics/summary.json holds the same per pair and metrics/eval/ every metric of every
pair (`dvc metrics show metrics/summary.json`, `dvc metrics show metrics/eval/pca`).

Each fraction correct in metrics/summary.json carries its 95% interval along the route: a pair's
from its evaluate stage, the mean over the pairs' from the per-query outcomes (data/outcomes/,
seasonloop.significance.means; statistics section). metrics/mean_fraction_correct.json keeps the
point values alone: DVC shows each key as a column, and three per label would bury the comparison.

Rows are labelled <learner><suffix> (seasonloop.evaluation.matchers.result_suffix: "pca", "pca+seq",
"pca@cityblock", ...). Writes metrics/summary.json (fraction correct per label and pair, its mean,
and the study's PR landmarks beside ours), metrics/runtime.json (fit seconds, the study's Table 6;
feature milliseconds per image, Table 7), plots/summary/fraction_correct.{md,csv} (ours beside the
study's numbers; the CSV feeds `dvc plots show`), plots/summary/pr_landmarks.md,
plots/summary/runtime.md, and the PNG figures of fraction correct per pair (study Figures 10, 11,
16, 17; fraction_correct.png for evaluate.metric, fraction_correct@<metric>.png for each extra
metric), overlaid PR curves per pair under evaluate.metric (Figures 9, 14, 15, 17) and
similarity.png (every learner's similarity matrix of every pair, single images, evaluate.metric,
from the evaluate stages' thumbnails in plots/similarity/); for
`dvc plots show`, plots/summary/pr/<pair>.csv (every learner's curve under evaluate.metric, a
`learner` column) and plots/summary/training_loss.csv (the dvclive loss curves of the learners
that train in epochs); metrics/network_training.json (how each of those learners' training
ended, with its time, from metrics/fit/). What each file holds: seasonloop.reporting.summary_files.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, param, stage_main
from seasonloop.evaluation.matchers import evaluations
from seasonloop.io import staged_dir, write_json
from seasonloop.params.seasons import available_pairs, pair_name
from seasonloop.params.settings import EvaluateConfig, StatisticsConfig
from seasonloop.reporting.dvcplots import training_curves
from seasonloop.reporting.results import load_evaluations, load_runtime, network_training
from seasonloop.reporting.summary_files import (
    compare_record,
    mean_intervals,
    summary_record,
    write_similarity_figure,
    write_summary_files,
)

# the metrics DVC compares across experiments (dvc.yaml declares only these)
COMPARE = Path("metrics/mean_fraction_correct.json")


@stage_main
def main() -> None:
    params = load_params("learners", "data.seasons", "evaluate", "statistics")
    learners = list(param(params, "learners"))
    seasons = data_seasons(params)
    evaluate = EvaluateConfig.from_params(params)
    pairs = [pair_name(a, b) for a, b in available_pairs(seasons, evaluate.pairs)]
    results = load_evaluations(
        Path("metrics/eval"), learners, pairs, evaluations(evaluate), evaluate.metric, pr_dir=Path("plots/pr")
    )
    runtime = load_runtime(Path("metrics/fit"), Path("metrics/features"), learners, seasons)
    intervals = mean_intervals(
        Path("data/outcomes"), learners, evaluations(evaluate), pairs, StatisticsConfig.from_params(params)
    )
    write_json(Path("metrics/summary.json"), summary_record(results, intervals))
    write_json(COMPARE, compare_record(results))
    write_json(Path("metrics/runtime.json"), runtime)
    write_json(Path("metrics/network_training.json"), network_training(Path("metrics/fit"), learners))
    with staged_dir(Path("plots/summary")) as out:
        write_summary_files(out, results, runtime, training_curves(Path("logs"), learners))
        write_similarity_figure(out / "similarity.png", Path("plots/similarity"), learners, pairs)


if __name__ == "__main__":
    main()
