"""Stage evaluate@<method>: match every season pair with one learner's descriptors.

For each pair of evaluate.pairs whose two seasons are in data.seasons, and each matcher of
evaluate.matchers (single-image best match; SeqSLAM-style sequence matching), writes
metrics/eval/<method>/<pair><suffix>.json, plots/pr/<method>/<pair><suffix>.csv (the study's PR
convention) and plots/similarity/<method>/<pair><suffix>.png, where suffix is "" for single-image
matching and "+seq" for sequence matching.
"""

from __future__ import annotations

import argparse
from pathlib import Path


from _common import data_seasons, load_params, param, stage_main, test_places

from seasonloop.config import available_pairs, pair_name
from seasonloop.evaluation import MATCHERS, match_pair
from seasonloop.io import load_array, staged_dir, write_json
from seasonloop.plots import plot_distance_matrix


@stage_main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("method")
    method = parser.parse_args().method
    params = load_params("data.seasons", "evaluate", "sequence")
    evaluate = param(params, "evaluate")
    matchers = list(evaluate["matchers"])
    for matcher in matchers:
        if matcher not in MATCHERS:
            raise ValueError(f"evaluate.matchers: unknown matcher '{matcher}' (known: {', '.join(MATCHERS)})")
    pairs = available_pairs(data_seasons(params), evaluate["pairs"])
    if not pairs:
        raise ValueError("evaluate.pairs: no pair has both of its seasons in data.seasons")
    places = test_places()
    features = Path("data/features") / method
    with staged_dir(Path("metrics/eval") / method) as metrics_dir, \
            staged_dir(Path("plots/pr") / method) as pr_dir, \
            staged_dir(Path("plots/similarity") / method) as similarity_dir:
        for database, query in pairs:
            for matcher in matchers:
                name = pair_name(database, query) + MATCHERS[matcher]
                metrics, pr, distances = match_pair(
                    load_array(features / f"{database}.npy"), load_array(features / f"{query}.npy"),
                    places, places, matcher, evaluate, param(params, "sequence"))
                write_json(metrics_dir / f"{name}.json", metrics)
                pr.to_csv(pr_dir / f"{name}.csv", index=False, float_format="%.6g")
                plot_distance_matrix(distances, f"{method}{MATCHERS[matcher]}: {database} (database) vs {query} (queries)",
                                     similarity_dir / f"{name}.png")


if __name__ == "__main__":
    main()
