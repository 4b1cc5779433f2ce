"""Stage features@<learner>: describe every test image of every season with one learner.

Writes data/features/<learner>/<season>.npy (N_test, D) float32 and
metrics/features/<learner>/<season>.json (feature time per image, the study's Table 7) for each
season of data.seasons. One process per learner, not per learner and season: the model is loaded
once, and a stage's start-up (torch, scikit-learn, DVC) costs seconds on a slow CPU. A learner of
descriptors computed elsewhere (precomputed) looks up the test places' rows of its files instead
of describing images; so this stage depends on precomputed.dir for every learner (rerunning them
when those files change gives identical features, and nothing after them reruns). With
split.folds K > 1 each fold's test images are described by that fold's model, into its fold folder
(seasonloop.data.datasets.fold_dir): every test place once; the times are over every fold.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from _common import data_seasons, load_params, stage_main
from _datasets import SPLIT
from seasonloop.data.datasets import count_folds, fold_dir, read_split, season_part, test_images
from seasonloop.io import read_json, save_array, staged_dir, write_json
from seasonloop.models.core.learner import PlaceRows
from seasonloop.models.core.lookup import load_learner
from seasonloop.params.settings import FeaturesConfig

FRAMES_RECORD = Path("data/frames/frames.json")


def place_rows(season: str, frames: dict, split: dict) -> PlaceRows:
    """The source frames the test places of `season` show: place p is the (offset + p)-th kept
    frame, every frame_step-th frame of the source (of the files data.image_list names, if any)."""
    offset = int(frames["offsets"].get(season, 0))
    rows = (offset + season_part(split, season, "test")) * int(frames["frame_step"])
    if "listed_frames" in frames:
        rows = np.asarray(frames["listed_frames"][season], dtype=np.int64)[rows]
    return PlaceRows(season, rows.astype(np.int64), int(frames["source_frames"][season]))


@stage_main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("learner")
    args = parser.parse_args()
    params = load_params("data.seasons", "features")
    settings = FeaturesConfig.from_params(params)
    seasons = data_seasons(params)
    frames, folds = read_json(FRAMES_RECORD), count_folds(SPLIT)
    seconds = dict.fromkeys(seasons, 0.0)
    n_images = dict.fromkeys(seasons, 0)
    dimension = dict.fromkeys(seasons, 0)
    with (
        staged_dir(Path("data/features") / args.learner) as features_dir,
        staged_dir(Path("metrics/features") / args.learner) as metrics_dir,
    ):
        for fold in range(folds):
            learner = load_learner(fold_dir(Path("models") / args.learner, fold, folds))
            split_dir = fold_dir(SPLIT, fold, folds)
            test, split = test_images(split_dir, seasons), read_split(split_dir)
            out = fold_dir(features_dir, fold, folds)
            out.mkdir(parents=True, exist_ok=True)
            for season in seasons:
                start = time.perf_counter()
                features = learner.describe_places(
                    test[season], place_rows(season, frames, split), batch_size=int(settings.batch_size), progress=True
                )
                seconds[season] += time.perf_counter() - start
                n_images[season] += len(test[season])
                dimension[season] = int(features.shape[1])
                save_array(out / f"{season}.npy", features)
        for season in seasons:
            write_json(
                metrics_dir / f"{season}.json",
                {
                    "ms_per_image": 1000 * seconds[season] / max(1, n_images[season]),
                    "n_images": n_images[season],
                    "dimension": dimension[season],
                },
            )


if __name__ == "__main__":
    main()
