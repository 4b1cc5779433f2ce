"""Stage extract_frames: extract.fps frames a second from every season (every data.frame_step-th
kept: one kept frame is a place), at the storage size. Frame folders are read in natural order and
paired by file name when the seasons share names. Then the seasons' alignment is measured
(seasonloop.alignment): a clear non-zero offset stops the run, and data.offsets shifts a season
by a known one. frames.json records both.

Writes data/frames/<season>.npy (N, h, w, 3) uint8 BGR, data/frames/frames.json and a preview of
the same places in every season (plots/season_preview.png).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from _common import data_seasons, load_params, param, stage_main

from seasonloop.data.sources import check_aligned, pair_season_files, place_description, read_season
from seasonloop.alignment import apply_offsets, check_alignment
from seasonloop.io import load_array, read_json, save_array, staged_dir, write_json
from seasonloop.plots import plot_image_grid
from seasonloop.settings import ExtractConfig

SOURCES = Path("data/acquired/sources.json")
OUT = Path("data/frames")
PREVIEW = Path("plots/season_preview.png")
PREVIEW_PLACES = 6


@stage_main
def main() -> None:
    params = load_params("data.seasons", "data.frame_step", "data.offsets", "extract")
    seasons = data_seasons(params)
    sources = read_json(SOURCES)["seasons"]
    missing = [season for season in seasons if season not in sources]
    if missing:
        raise ValueError(f"data.seasons: {', '.join(missing)} not in {SOURCES}; rerun the acquire stage")
    extract = ExtractConfig.from_params(params)
    fps, height, width = float(extract.fps), int(extract.height), int(extract.width)
    frame_step = int(param(params, "data.frame_step"))
    kinds = {sources[season]["kind"] for season in seasons}
    files, pairing = pair_season_files({season: (sources[season]["kind"], Path(sources[season]["path"])) for season in seasons})
    print(f"extract_frames: {pairing}")
    with staged_dir(OUT) as out:
        counts = {}
        # one season in memory at a time: the full-scale route is ~1 GB a season at 72x128
        for season in seasons:
            frames = read_season(sources[season]["kind"], Path(sources[season]["path"]), fps, height, width,
                                 frame_step=frame_step, files=files[season] if files else None)
            counts[season] = len(frames)
            save_array(out / f"{season}.npy", frames)
            del frames
        n_places = check_aligned(counts, bool(extract.trim_to_shortest),
                                 {season: sources[season]["path"] for season in seasons})
        # known offsets drop a season's first places; every season is then cut to one length
        kept = apply_offsets({season: n_places for season in seasons}, dict(param(params, "data.offsets")))
        for season in seasons:
            if kept[season] != slice(0, counts[season]):
                save_array(out / f"{season}.npy", np.ascontiguousarray(load_array(out / f"{season}.npy", mmap=True)[kept[season]]))
        n_places = kept[seasons[0]].stop - kept[seasons[0]].start
        alignment = check_alignment({season: load_array(out / f"{season}.npy", mmap=True) for season in seasons},
                                    int(extract.max_offset))
        write_json(out / "frames.json", {"n_places": n_places, "seasons": seasons, "frames_per_season": counts,
                                         "frame_step": frame_step, "pairing": pairing, "alignment": alignment,
                                         "offsets": dict(param(params, "data.offsets")),
                                         "place": place_description(kinds, fps, frame_step)})
        places = np.linspace(0, n_places - 1, PREVIEW_PLACES + 2).round().astype(int)[1:-1]
        stored = {season: load_array(out / f"{season}.npy", mmap=True) for season in seasons}
        grid = [[stored[season][place][..., ::-1] for season in seasons] for place in places]
        plot_image_grid(grid, PREVIEW, row_labels=[f"place {p}" for p in places], col_labels=seasons,
                        title="The same places in every season")


if __name__ == "__main__":
    main()
