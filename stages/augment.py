"""Stage augment: flips and shifts of the training images; writes the dataset table (study Table 3).

Writes data/augmented/<season>.npy (originals then augmented copies) and metrics/dataset.json.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, stage_main
from _datasets import AUGMENTED, SPLIT
from seasonloop.data.datasets import dataset_record, read_split, write_augmented_sets
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
    with staged_dir(AUGMENTED) as out:
        per_season = write_augmented_sets(SPLIT, out, seasons, config)
    # detection is empty unless the renderer's truth was available
    write_json(DATASET, dataset_record(read_split(SPLIT), per_season, read_json(FRAMES), read_json(DETECTION)))


if __name__ == "__main__":
    main()
