"""Stage features@<method>: describe every test image of every season with one learner.

Writes data/features/<method>/<season>.npy (N_test, D) float32 and
metrics/features/<method>/<season>.json (feature time per image, the study's Table 7) for each
season of data.seasons. One process per learner, not per learner and season: the model is loaded
once, and a stage's start-up (torch, scikit-learn, DVC) costs seconds on a slow CPU.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from _common import data_seasons, load_params, stage_main
from _datasets import test_images
from seasonloop.io import save_array, staged_dir, write_json
from seasonloop.models.registry import load_learner
from seasonloop.params.settings import FeaturesConfig


@stage_main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("method")
    args = parser.parse_args()
    params = load_params("data.seasons", "features")
    settings = FeaturesConfig.from_params(params)
    seasons = data_seasons(params)
    learner = load_learner(Path("models") / args.method)
    test = test_images(seasons)
    with (
        staged_dir(Path("data/features") / args.method) as features_dir,
        staged_dir(Path("metrics/features") / args.method) as metrics_dir,
    ):
        for season in seasons:
            start = time.perf_counter()
            features = learner.describe(test[season], batch_size=int(settings.batch_size), progress=True)
            seconds = time.perf_counter() - start
            save_array(features_dir / f"{season}.npy", features)
            write_json(
                metrics_dir / f"{season}.json",
                {
                    "ms_per_image": 1000 * seconds / max(1, len(test[season])),
                    "n_images": len(test[season]),
                    "dimension": int(features.shape[1]),
                },
            )


if __name__ == "__main__":
    main()
