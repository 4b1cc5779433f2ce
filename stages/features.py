"""Stage features@<method>-<season>: describe every test image of one season with one learner.

Writes data/features/<method>/<season>.npy (N_test, D) float32 and
metrics/features/<method>/<season>.json (feature time per image, the study's Table 7).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from _common import data_seasons, load_params, stage_main, test_images

from seasonloop.io import save_array, write_json
from seasonloop.models.registry import load_learner
from seasonloop.settings import FeaturesConfig


@stage_main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("method")
    parser.add_argument("season")
    args = parser.parse_args()
    params = load_params("data.seasons", "features")
    settings = FeaturesConfig.from_params(params)
    if args.season not in data_seasons(params):
        raise ValueError(f"season '{args.season}' is not in data.seasons")
    learner = load_learner(Path("models") / args.method)
    images = test_images([args.season])[args.season]
    start = time.perf_counter()
    features = learner.describe(images, batch_size=int(settings.batch_size), progress=True)
    seconds = time.perf_counter() - start
    save_array(Path("data/features") / args.method / f"{args.season}.npy", features)
    write_json(Path("metrics/features") / args.method / f"{args.season}.json", {
        "ms_per_image": 1000 * seconds / max(1, len(images)),
        "n_images": len(images),
        "dimension": int(features.shape[1]),
    })


if __name__ == "__main__":
    main()
