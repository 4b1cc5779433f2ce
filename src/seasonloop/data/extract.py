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
from seasonloop.data.frames import list_frame_files, video_sample_count
from seasonloop.data.positions import PositionFiles, season_positions
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
    aligned: bool = True,
    positions: PositionFiles | None = None,
) -> dict[str, Any]:
    """Write out/<season>.npy, (N, h, w, 3) uint8 BGR at the storage size, one season in memory at a
    time (the full-scale route is ~1 GB a season at 72x128), and return the record of frames.json:
    place count, frames per season, pairing, measured alignment, offsets and what a place is.

    aligned: frame i of every season is the same place, so the seasons are paired and cut to one
    length and their alignment is measured; otherwise (ground truth from positions or a matrix)
    each season keeps its own frames. positions: where the seasons' positions are; each season's
    kept places' positions (metres) go to out/<season>_positions.npy.
    """
    fps, height, width = float(extract.fps), int(extract.height), int(extract.width)
    kinds = {sources[season]["kind"] for season in seasons}
    paths = {season: (sources[season]["kind"], Path(sources[season]["path"])) for season in seasons}
    files, pairing = pair_season_files(paths) if aligned else (None, "each season its own frames (not aligned)")
    print(f"extract_frames: {pairing}")
    counts, coordinates, source_frames = {}, {}, {}
    for season in seasons:
        kind, path = paths[season]
        source_frames[season] = len(list_frame_files(path)) if kind == "frames" else video_sample_count(path, fps)
        frames = read_season(
            kind, path, fps, height, width, frame_step=frame_step, files=files[season] if files else None
        )
        counts[season] = len(frames)
        save_array(out / f"{season}.npy", frames)
        del frames
        if positions is not None:
            listing = list_frame_files(path) if kind == "frames" else []
            coordinates[season] = season_positions(kind, positions, season, counts[season], fps, frame_step, listing)
    kept = kept_places(counts, offsets, aligned, bool(extract.trim_to_shortest), sources)
    for season in seasons:
        if kept[season] != slice(0, counts[season]):
            save_array(
                out / f"{season}.npy", np.ascontiguousarray(load_array(out / f"{season}.npy", mmap=True)[kept[season]])
            )
    if positions is not None:
        write_positions(out, coordinates, kept)
    places = {season: kept[season].stop - kept[season].start for season in seasons}
    stored = {season: load_array(out / f"{season}.npy", mmap=True) for season in seasons}
    return {
        "n_places": places[seasons[0]] if aligned else None,
        "places_per_season": places,
        "seasons": list(seasons),
        "frames_per_season": counts,
        # frames of each source before data.frame_step (rows of descriptors computed elsewhere)
        "source_frames": source_frames,
        "frame_step": frame_step,
        "pairing": pairing,
        "alignment": check_alignment(stored, int(extract.max_offset)) if aligned else {},
        "offsets": dict(offsets),
        "place": place_description(kinds, fps, frame_step),
    }


def write_positions(out: Path, coordinates: Mapping[str, np.ndarray], kept: Mapping[str, slice]) -> None:
    """out/<season>_positions.npy: the kept places' positions in metres."""
    for season, slice_ in kept.items():
        save_array(out / f"{season}_positions.npy", np.ascontiguousarray(coordinates[season][slice_]))


def kept_places(
    counts: Mapping[str, int],
    offsets: Mapping[str, int],
    aligned: bool,
    trim_to_shortest: bool,
    sources: Mapping[str, Mapping[str, str]],
) -> dict[str, slice]:
    """season -> its places kept: aligned seasons must have one length (or are trimmed to the
    shortest) and are cut to one length after their offsets; others only lose their offsets."""
    if not aligned:
        return {season: own_offset(season, count, offsets.get(season, 0)) for season, count in counts.items()}
    n_places = check_aligned(counts, trim_to_shortest, {season: sources[season]["path"] for season in counts})
    # known offsets drop a season's first places; every season is then cut to one length
    return apply_offsets({season: n_places for season in counts}, dict(offsets))


def own_offset(season: str, count: int, offset: int) -> slice:
    """The places of a season that is not aligned with the others, its first `offset` dropped."""
    if not 0 <= offset < count:
        raise ValueError(f"data.offsets.{season}: {offset} is not in [0, {count})")
    return slice(offset, count)


def preview_grid(
    folder: Path, seasons: Sequence[str], places_per_season: Mapping[str, int], n_shown: int
) -> tuple[list[list[np.ndarray]], list[str]]:
    """(rows of RGB images, row labels): `n_shown` places spread along the first season's route,
    one column per season. Seasons that are not aligned show the place nearest in position
    (<season>_positions.npy), or the same fraction of their frames when there are no positions."""
    first = seasons[0]
    places = np.linspace(0, places_per_season[first] - 1, n_shown + 2).round().astype(int)[1:-1]
    stored = {season: load_array(folder / f"{season}.npy", mmap=True) for season in seasons}
    shown = {}
    for season in seasons:
        if places_per_season[season] == places_per_season[first] and len(set(places_per_season.values())) == 1:
            shown[season] = places
        elif (folder / f"{first}_positions.npy").is_file():
            reference = load_array(folder / f"{first}_positions.npy")[places]
            own = load_array(folder / f"{season}_positions.npy")
            shown[season] = np.linalg.norm(own[None, :, :] - reference[:, None, :], axis=2).argmin(axis=1)
        else:
            shown[season] = (places / max(1, places_per_season[first] - 1) * (places_per_season[season] - 1)).round()
    grid = [[stored[season][int(shown[season][row])][..., ::-1] for season in seasons] for row in range(len(places))]
    return grid, [f"{first} place {p}" if len(set(places_per_season.values())) > 1 else f"place {p}" for p in places]
