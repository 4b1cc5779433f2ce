"""Extraction of a route's places, every season into one folder: read each season, check that the
seasons have one length, drop known offsets, measure the alignment, and the record of it all.

The seasons' files are given as data/acquired/sources.json describes them (season -> kind and
path); seasonloop.data.sources reads them, seasonloop.data.alignment measures and applies offsets.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.data.alignment import apply_offsets, check_alignment
from seasonloop.data.sources import check_aligned, pair_season_files, place_description, read_season
from seasonloop.io import load_array, save_array
from seasonloop.params.settings import ExtractConfig


def check_sources(sources: Mapping[str, Any], seasons: Sequence[str], sources_file: Path) -> None:
    """Every season of data.seasons must have been acquired."""
    missing = [season for season in seasons if season not in sources]
    if missing:
        raise ValueError(f"data.seasons: {', '.join(missing)} not in {sources_file}; rerun the acquire stage")


def extract_seasons(
    sources: Mapping[str, Mapping[str, str]],
    seasons: Sequence[str],
    extract: ExtractConfig,
    frame_step: int,
    offsets: Mapping[str, int],
    out: Path,
) -> dict[str, Any]:
    """Write out/<season>.npy, (N, h, w, 3) uint8 BGR at the storage size, one season in memory at a
    time (the full-scale route is ~1 GB a season at 72x128), and return the record of frames.json:
    place count, frames per season, pairing, measured alignment, offsets and what a place is."""
    fps, height, width = float(extract.fps), int(extract.height), int(extract.width)
    kinds = {sources[season]["kind"] for season in seasons}
    files, pairing = pair_season_files(
        {season: (sources[season]["kind"], Path(sources[season]["path"])) for season in seasons}
    )
    print(f"extract_frames: {pairing}")
    counts = {}
    for season in seasons:
        frames = read_season(
            sources[season]["kind"],
            Path(sources[season]["path"]),
            fps,
            height,
            width,
            frame_step=frame_step,
            files=files[season] if files else None,
        )
        counts[season] = len(frames)
        save_array(out / f"{season}.npy", frames)
        del frames
    n_places = check_aligned(
        counts, bool(extract.trim_to_shortest), {season: sources[season]["path"] for season in seasons}
    )
    # known offsets drop a season's first places; every season is then cut to one length
    kept = apply_offsets({season: n_places for season in seasons}, dict(offsets))
    for season in seasons:
        if kept[season] != slice(0, counts[season]):
            save_array(
                out / f"{season}.npy", np.ascontiguousarray(load_array(out / f"{season}.npy", mmap=True)[kept[season]])
            )
    n_places = kept[seasons[0]].stop - kept[seasons[0]].start
    alignment = check_alignment(
        {season: load_array(out / f"{season}.npy", mmap=True) for season in seasons}, int(extract.max_offset)
    )
    return {
        "n_places": n_places,
        "seasons": list(seasons),
        "frames_per_season": counts,
        "frame_step": frame_step,
        "pairing": pairing,
        "alignment": alignment,
        "offsets": dict(offsets),
        "place": place_description(kinds, fps, frame_step),
    }


def preview_grid(
    folder: Path, seasons: Sequence[str], n_places: int, n_shown: int
) -> tuple[list[list[np.ndarray]], list[str]]:
    """(rows of RGB images, row labels): `n_shown` places spread along the route, one column per season."""
    places = np.linspace(0, n_places - 1, n_shown + 2).round().astype(int)[1:-1]
    stored = {season: load_array(folder / f"{season}.npy", mmap=True) for season in seasons}
    grid = [[stored[season][place][..., ::-1] for season in seasons] for place in places]
    return grid, [f"place {p}" for p in places]
