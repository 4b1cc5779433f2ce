"""Stage evaluate@<learner>: match every season pair with one learner's descriptors.

For each pair of evaluate.pairs whose two seasons are in data.seasons, each metric (evaluate.metric,
then evaluate.extra_metrics) and each matcher of evaluate.matchers (single-image best match;
SeqSLAM-style sequence matching), writes metrics/eval/<learner>/<pair><suffix>.json,
plots/pr/<learner>/<pair><suffix>.csv (the study's PR convention) and
plots/similarity/<learner>/<pair><suffix>.npy (a thumbnail of the similarity matched on, for the
summary's figure of every learner and pair) and data/outcomes/<learner>/<pair><suffix>.csv (each
query's outcome, for the compare stage's paired tests), where suffix is "@<metric>" for an extra metric
(nothing for evaluate.metric) followed by "" for single-image matching and "+seq" for sequence
matching (seasonloop.evaluation.matchers.result_suffix). With split.folds K > 1 each fold is
evaluated on its own (its queries against its database places) and each file holds every fold's
queries (seasonloop.evaluation.folds).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from _common import data_seasons, load_params, stage_main
from seasonloop.data.datasets import count_folds, fold_dirs
from seasonloop.evaluation.learner_evaluation import evaluate_learner
from seasonloop.io import staged_dir
from seasonloop.params.seasons import available_pairs
from seasonloop.params.settings import EvaluateConfig, SequenceConfig, StatisticsConfig


@stage_main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("learner")
    learner = parser.parse_args().learner
    params = load_params("data.seasons", "evaluate", "sequence", "statistics")
    evaluate, sequence = EvaluateConfig.from_params(params), SequenceConfig.from_params(params)
    pairs = available_pairs(data_seasons(params), evaluate.pairs)
    truths = Path("data/ground_truth")
    folds = count_folds(truths)
    with (
        staged_dir(Path("metrics/eval") / learner) as metrics_dir,
        staged_dir(Path("plots/pr") / learner) as pr_dir,
        staged_dir(Path("plots/similarity") / learner) as similarity_dir,
        staged_dir(Path("data/outcomes") / learner) as outcomes_dir,
    ):
        evaluate_learner(
            fold_dirs(Path("data/features") / learner, folds),
            pairs,
            fold_dirs(truths, folds),
            evaluate,
            sequence,
            StatisticsConfig.from_params(params),
            (metrics_dir, pr_dir, similarity_dir, outcomes_dir),
            progress=True,
        )


if __name__ == "__main__":
    main()
