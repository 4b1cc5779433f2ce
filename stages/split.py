"""Stage split: geographic train/test sections with gaps; tunnels and stops out of the test sets.

Writes data/split/split.json (the place ids of every part), data/split/<season>_{train,test}.npy
and metrics/detection.json: how well tunnel and stop detection matched the renderer's truth when the
data is synthetic (empty otherwise). The scores live outside data/split so that scoring changes do
not invalidate the learners, which depend on data/split.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from _common import data_seasons, load_params, param, stage_main

from seasonloop.data.layout import RouteLayout
from seasonloop.io import load_array, read_json, save_array, staged_dir, write_json
from seasonloop.split import detect_stops, detect_tunnels, make_split

PREPROCESSED = Path("data/preprocessed")
LAYOUT = Path("data/acquired/layout.json")
OUT = Path("data/split")
DETECTION = Path("metrics/detection.json")


def detection_scores(found: np.ndarray, truth: np.ndarray) -> dict[str, float | int]:
    hits = int(np.sum(found & truth))
    return {
        "true": int(truth.sum()),
        "found": int(found.sum()),
        "recall": hits / max(1, int(truth.sum())),
        "precision": hits / max(1, int(found.sum())),
    }


@stage_main
def main() -> None:
    params = load_params("data.source", "data.seasons", "data.frame_step", "extract.fps", "split")
    seasons = data_seasons(params)
    split_params = param(params, "split")
    stats = np.load(PREPROCESSED / "stats.npz")
    tunnel = detect_tunnels({s: stats[f"{s}_brightness"] for s in seasons}, float(split_params["dark_threshold"]))
    stop = detect_stops({s: stats[f"{s}_change"] for s in seasons}, float(split_params["stop_threshold"]))
    n_places = len(tunnel)
    split = make_split(n_places, int(split_params["section_length"]), float(split_params["test_fraction"]),
                       int(split_params["gap"]), tunnel, stop)
    detection = {}
    if param(params, "data.source") == "synthetic" and LAYOUT.is_file():
        # the renderer knows where its tunnels and stops are: score the image-based detection
        layout = RouteLayout.from_json(read_json(LAYOUT))
        # place p is the (p * frame_step)-th sample at extract.fps
        seconds_of_place = (np.arange(n_places) * int(param(params, "data.frame_step"))
                            / float(param(params, "extract.fps"))).astype(int)
        detection = {
            "tunnel": detection_scores(tunnel, layout.in_tunnel()[seconds_of_place]),
            # a still, dark tunnel frame looks like a stop too; the split counts it as a tunnel
            "stop": detection_scores(stop & ~tunnel, layout.stopped()[seconds_of_place]),
        }
    with staged_dir(OUT) as out:
        for season in seasons:
            images = load_array(PREPROCESSED / f"{season}.npy")
            save_array(out / f"{season}_train.npy", images[split.train])
            save_array(out / f"{season}_test.npy", images[split.test])
        write_json(out / "split.json", split.to_json())
    write_json(DETECTION, detection)


if __name__ == "__main__":
    main()
