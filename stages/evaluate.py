"""Stage evaluate@<method>: match every season pair with one learner's descriptors.

For each pair of evaluate.pairs whose two seasons are in data.seasons, each metric (evaluate.metric,
then evaluate.extra_metrics) and each matcher of evaluate.matchers (single-image best match;
SeqSLAM-style sequence matching), writes metrics/eval/<method>/<pair><suffix>.json,
plots/pr/<method>/<pair><suffix>.csv (the study's PR convention) and
plots/similarity/<method>/<pair><suffix>.png, where suffix is "@<metric>" for an extra metric
(nothing for evaluate.metric) followed by "" for single-image matching and "+seq" for sequence
matching (seasonloop.evaluation.result_suffix).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from _common import data_seasons, load_params, stage_main, test_places

from seasonloop.config import available_pairs, pair_name
from seasonloop.evaluation import evaluations, match_distances
from seasonloop.io import load_array, staged_dir, write_json
from seasonloop.matching import distance_matrix
from seasonloop.plots import plot_distance_matrix
from seasonloop.settings import EvaluateConfig, SequenceConfig


@stage_main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("method")
    method = parser.parse_args().method
    params = load_params("data.seasons", "evaluate", "sequence")
    evaluate, sequence = EvaluateConfig.from_params(params), SequenceConfig.from_params(params)
    variants = evaluations(evaluate)
    pairs = available_pairs(data_seasons(params), evaluate.pairs)
    if not pairs:
        raise ValueError("evaluate.pairs: no pair has both of its seasons in data.seasons")
    places = test_places()
    features = Path("data/features") / method
    with staged_dir(Path("metrics/eval") / method) as metrics_dir, \
            staged_dir(Path("plots/pr") / method) as pr_dir, \
            staged_dir(Path("plots/similarity") / method) as similarity_dir:
        for database, query in pairs:
            descriptors = [load_array(features / f"{season}.npy") for season in (database, query)]
            # One distance matrix per metric, shared by its matchers.
            distances = {metric: distance_matrix(*descriptors, metric=metric)
                         for metric in dict.fromkeys(metric for metric, _, _ in variants)}
            for metric, matcher, suffix in variants:
                name = pair_name(database, query) + suffix
                metrics, pr, matched = match_distances(distances[metric], places, places, matcher, evaluate, sequence)
                write_json(metrics_dir / f"{name}.json", metrics)
                pr.to_csv(pr_dir / f"{name}.csv", index=False, float_format="%.6g")
                plot_distance_matrix(matched, f"{method}{suffix}: {database} (database) vs {query} (queries)",
                                     similarity_dir / f"{name}.png")


if __name__ == "__main__":
    main()
