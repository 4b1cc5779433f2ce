"""Stage preprocess: grayscale, resize to preprocess.height x width, contrast enhancement.

Writes data/preprocessed/<season>.npy (N, 32, 64) uint8 and data/preprocessed/stats.npz with each
frame's brightness and change from the previous frame (before enhancement), used by the split to
find tunnels and station stops.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from _common import data_seasons, load_params, stage_main
from seasonloop.data.preprocess import enhance_image_contrast, frame_statistics, to_gray
from seasonloop.io import load_array, save_array, staged_dir
from seasonloop.params.settings import PreprocessConfig

FRAMES = Path("data/frames")
OUT = Path("data/preprocessed")


@stage_main
def main() -> None:
    params = load_params("data.seasons", "preprocess")
    pre = PreprocessConfig.from_params(params)
    stats = {}
    with staged_dir(OUT) as out:
        for season in data_seasons(params):
            gray = to_gray(load_array(FRAMES / f"{season}.npy", mmap=True), pre.height, pre.width)
            stats[f"{season}_brightness"], stats[f"{season}_change"] = frame_statistics(gray)
            save_array(
                out / f"{season}.npy", enhance_image_contrast(gray, pre.contrast, pre.clahe_clip, pre.clahe_grid)
            )
        np.savez(out / "stats.npz", **stats)


if __name__ == "__main__":
    main()
