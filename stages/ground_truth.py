"""Stage ground_truth: which database places are correct for each query, for every season pair.

Writes data/ground_truth/<database>-<query>.npz (seasonloop.data.ground_truth.PairTruth) for
every ordered pair of data.seasons and metrics/ground_truth.json (kind, tolerance, queries without
any correct database place). data.ground_truth says how: aligned frame indices
(evaluate.tolerance_frames), positions (evaluate.tolerance_m) or a matrix given with the data.
With split.folds K > 1, each fold's truths (its queries against its own test places of the
database season) in its fold folder (seasonloop.data.datasets.fold_dir), and the record over all.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, param, stage_main
from _datasets import SPLIT
from seasonloop.data.datasets import count_folds, fold_dir, read_split
from seasonloop.data.ground_truth import truth_file
from seasonloop.evaluation.pair_ground_truth import each_truth, pair_record, pooled_pair_record, truth_record
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
    folds = count_folds(SPLIT)
    per_fold: dict[tuple[str, str], list[dict]] = {}
    with staged_dir(OUT) as out:
        for fold in range(folds):
            folder = fold_dir(out, fold, folds)
            folder.mkdir(parents=True, exist_ok=True)
            split = read_split(fold_dir(SPLIT, fold, folds))
            truths = each_truth(
                kind, split, seasons, evaluate, Path("data/frames"), Path(param(params, "data.ground_truth_dir"))
            )
            for (database, query), truth in truths:  # one pair in memory at a time
                truth.save(truth_file(folder, database, query))
                per_fold.setdefault((database, query), []).append(pair_record(truth))
    pairs = {pair: entries[0] if folds == 1 else pooled_pair_record(entries) for pair, entries in per_fold.items()}
    record = {**truth_record(kind, evaluate, pairs), **({"folds": folds} if folds > 1 else {})}
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
