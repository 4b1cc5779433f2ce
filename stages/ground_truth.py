"""Stage ground_truth: which database places are correct for each query, for every season pair.

Writes data/ground_truth/<database>-<query>.npz (seasonloop.data.ground_truth.PairTruth) for
every ordered pair of data.seasons and metrics/ground_truth.json (kind, tolerance, queries without
any correct database place). data.ground_truth says how: aligned frame indices
(evaluate.tolerance_frames), positions (evaluate.tolerance_m) or a matrix given with the data.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, param, stage_main
from _datasets import SPLIT
from seasonloop.data.datasets import read_split
from seasonloop.data.ground_truth import truth_file
from seasonloop.evaluation.pair_truths import each_truth, pair_record, truth_record
from seasonloop.io import staged_dir, write_json
from seasonloop.params.settings import EvaluateConfig

OUT = Path("data/ground_truth")
RECORD = Path("metrics/ground_truth.json")


@stage_main
def main() -> None:
    params = load_params("data.seasons", "data.ground_truth", "data.ground_truth_dir", "evaluate")
    seasons = data_seasons(params)
    kind = param(params, "data.ground_truth")
    evaluate = EvaluateConfig.from_params(params)
    truths = each_truth(
        kind, read_split(SPLIT), seasons, evaluate, Path("data/frames"), Path(param(params, "data.ground_truth_dir"))
    )
    with staged_dir(OUT) as out:
        pairs = {}
        for (database, query), truth in truths:  # one pair in memory at a time
            truth.save(truth_file(out, database, query))
            pairs[database, query] = pair_record(truth)
    record = truth_record(kind, evaluate, pairs)
    for pair, entry in record["pairs"].items():
        if entry["n_without_match"]:
            # counted as the field does (VPR_Tutorial): whatever they match is wrong, and they are
            # not positives of the PR curve
            print(
                f"ground_truth: {pair}: {entry['n_without_match']} of {entry['n_queries']} queries have no "
                f"correct database place ({record['correct']}); they count as wrong matches"
            )
    write_json(RECORD, record)


if __name__ == "__main__":
    main()
