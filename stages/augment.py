"""Stage augment: flips and shifts of the training images; writes the dataset table (study Table 3).

Writes data/augmented/<season>.npy (originals then augmented copies) and metrics/dataset.json.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, param, stage_main

from seasonloop.augment import augment_training_set
from seasonloop.io import load_array, read_json, save_array, staged_dir, write_json

SPLIT = Path("data/split")
OUT = Path("data/augmented")
DATASET = Path("metrics/dataset.json")
DETECTION = Path("metrics/detection.json")
FRAMES = Path("data/frames/frames.json")


@stage_main
def main() -> None:
    params = load_params("data.seasons", "augment")
    seasons = data_seasons(params)
    aug = param(params, "augment")
    split = read_json(SPLIT / "split.json")
    per_season = {}
    with staged_dir(OUT) as out:
        for index, season in enumerate(seasons):
            train = load_array(SPLIT / f"{season}_train.npy")
            # a distinct, reproducible stream per season
            augmented = augment_training_set(train, int(aug["copies"]), int(aug["seed"]) + index,
                                             bool(aug["horizontal_flip"]), float(aug["width_shift"]),
                                             float(aug["height_shift"]))
            save_array(out / f"{season}.npy", augmented)
            per_season[season] = {
                "frames": split["n_places"],
                "train": len(split["train"]),
                "train_augmented": len(augmented),
                "test": len(split["test"]),
            }
    detection = read_json(DETECTION)   # empty unless the renderer's truth was available
    frames = read_json(FRAMES)
    write_json(DATASET, {
        "seasons": per_season,
        "total_images": split["n_places"] * len(seasons),
        "total_train": len(split["train"]) * len(seasons),
        "total_test": len(split["test"]) * len(seasons),
        "dropped_tunnel": len(split["dropped_tunnel"]),
        "dropped_stop": len(split["dropped_stop"]),
        "gap": len(split["gap"]),
        # what a place (and so a tolerance of one place) is
        "place": frames["place"],
        "frame_step": frames["frame_step"],
        "pairing": frames["pairing"],
        # the measured offset of each season against the first (seasonloop.alignment)
        "alignment": frames["alignment"],
        "offsets": frames["offsets"],
        **({"detection": detection} if detection else {}),
    })


if __name__ == "__main__":
    main()
