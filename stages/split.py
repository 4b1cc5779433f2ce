"""Stage split: geographic train/test sections with gaps; tunnels and stops out of the test sets.

Writes data/split/split.json (the place ids of every part), data/split/<season>_{train,test}.npy
and metrics/detection.json: how well tunnel and stop detection matched the renderer's truth when the
data is synthetic and aligned (empty otherwise). The scores live outside data/split so that scoring
changes do not invalidate the learners, which depend on data/split. Seasons that are not aligned
(data.ground_truth positions, matrix or vpr_bench) are split along the first season's places
(seasonloop.data.season_split), each season with its own parts. With split.folds K > 1 the folder
holds every fold (seasonloop.data.datasets.fold_dir): the study's split where it always is, the
other folds in data/split/folds/<k>/.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from _common import data_seasons, load_params, param, stage_main
from _datasets import SPLIT
from seasonloop.data.datasets import fold_dir
from seasonloop.data.ground_truth_kinds import truth_kind
from seasonloop.data.layout import RouteLayout
from seasonloop.data.season_split import split_seasons
from seasonloop.data.split import detection_record, place_seconds, split_route, write_split_sets
from seasonloop.io import read_json, staged_dir, write_json
from seasonloop.params.settings import SplitConfig

PREPROCESSED = Path("data/preprocessed")
FRAMES = Path("data/frames")
LAYOUT = Path("data/acquired/layout.json")
DETECTION = Path("metrics/detection.json")


@stage_main
def main() -> None:
    params = load_params(
        "data.source",
        "data.seasons",
        "data.frame_step",
        "data.ground_truth",
        "data.ground_truth_dir",
        "extract.fps",
        "evaluate.tolerance_m",
        "split",
    )
    seasons = data_seasons(params)
    stats = np.load(PREPROCESSED / "stats.npz")
    config = SplitConfig.from_params(params)
    kind = truth_kind(param(params, "data.ground_truth"))
    detection = {}
    folds = int(config.folds)
    splits: list[Any]  # each fold's Split (aligned seasons) or SeasonSplits
    if kind.aligned:
        splits = [split_route(stats, seasons, config, fold)[0] for fold in range(folds - 1)]
        split, tunnel, stop = split_route(stats, seasons, config)
        splits.append(split)
        if param(params, "data.source") == "synthetic" and LAYOUT.is_file():
            # the renderer knows where its tunnels and stops are: score the image-based detection
            layout = RouteLayout.from_json(read_json(LAYOUT))
            seconds = place_seconds(
                split.n_places, int(param(params, "data.frame_step")), float(param(params, "extract.fps"))
            )
            detection = detection_record(tunnel, stop, layout.in_tunnel(), layout.stopped(), seconds)
    else:
        counts = {season: len(stats[f"{season}_brightness"]) for season in seasons}
        truth_dir = Path(param(params, "data.ground_truth_dir"))
        mapped = kind.reference_places(seasons, counts, FRAMES, truth_dir, float(param(params, "evaluate.tolerance_m")))
        splits = [split_seasons(stats, seasons, config, mapped, fold) for fold in range(folds)]
    with staged_dir(SPLIT) as out:
        for fold, split in enumerate(splits):
            folder = fold_dir(out, fold, folds)
            folder.mkdir(parents=True, exist_ok=True)
            write_split_sets(PREPROCESSED, folder, seasons, split)
    write_json(DETECTION, detection)


if __name__ == "__main__":
    main()
