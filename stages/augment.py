"""Stage augment: flips and shifts of the training images; writes the dataset table (study Table 3).

Writes data/augmented/<season>.npy (originals then augmented copies) and metrics/dataset.json;
with split.folds K > 1, each fold's set in its fold folder (seasonloop.data.datasets.fold_dir),
every fold's from the same seeded streams.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, stage_main
from _datasets import AUGMENTED, SPLIT
from seasonloop.data.datasets import (
    count_folds,
    dataset_record,
    fold_counts,
    fold_dirs,
    read_split,
    write_augmented_sets,
)
from seasonloop.io import read_json, staged_dir, write_json
from seasonloop.params.settings import AugmentConfig

DATASET = Path("metrics/dataset.json")
DETECTION = Path("metrics/detection.json")
FRAMES = Path("data/frames/frames.json")


@stage_main
def main() -> None:
    params = load_params("data.seasons", "augment")
    seasons = data_seasons(params)
    config = AugmentConfig.from_params(params)
    folds = count_folds(SPLIT)
    with staged_dir(AUGMENTED) as out:
        per_fold = [
            write_augmented_sets(split, augmented, seasons, config)
            for split, augmented in zip(fold_dirs(SPLIT, folds), fold_dirs(out, folds))
        ]
    # detection is empty unless the renderer's truth was available
    record = dataset_record(read_split(SPLIT), per_fold[-1], read_json(FRAMES), read_json(DETECTION))
    if folds > 1:
        record["folds"] = fold_counts(per_fold)
    write_json(DATASET, record)


if __name__ == "__main__":
    main()
