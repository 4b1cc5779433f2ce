"""Extraction of a route's places, every season into one folder: read each season, check that the
seasons have one length, drop known offsets, measure the alignment, and the record of it all.

The seasons' files are given as data/acquired/sources.json describes them (season -> kind and
path); seasonloop.data.sources reads them, seasonloop.data.alignment measures and applies offsets.
"""

from __future__ import annotations

import shutil
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.data.alignment import apply_offsets, check_alignment
from seasonloop.data.frames import keep_listed, list_frame_files, read_image_list, video_sample_count
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
    image_list: Path | None = None,
    stop_threshold: float = 0.0,
) -> dict[str, Any]:
    """Write out/<season>.npy, (N, h, w, 3) uint8 BGR at the storage size, one season in memory at a
    time (the full-scale route is ~1 GB a season at 72x128), and return the record of frames.json:
    place count, frames per season, pairing, measured alignment, offsets and what a place is.

    aligned: frame i of every season is the same place, so the seasons are paired and cut to one
    length and their alignment is measured; otherwise (ground truth from positions or a matrix)
    each season keeps its own frames. positions: where the seasons' positions are; each season's
    kept places' positions (metres) go to out/<season>_positions.npy. image_list: the frame files to
    keep (season_files). stop_threshold: check_alignment's (split.stop_threshold)."""
    fps, height, width = float(extract.fps), int(extract.height), int(extract.width)
    paths = {season: (sources[season]["kind"], Path(sources[season]["path"])) for season in seasons}
    files, pairing, listed_rows = season_files(paths, aligned, image_list)
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
            listing = (files[season] if files else list_frame_files(path)) if kind == "frames" else []
            coordinates[season] = season_positions(kind, positions, season, counts[season], fps, frame_step, listing)
    kept = kept_places(counts, offsets, aligned, bool(extract.trim_to_shortest), sources)
    for season in (season for season in seasons if kept[season] != slice(0, counts[season])):
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
        "source_frames": source_frames,  # before frame_step (rows of descriptors computed elsewhere)
        **({"listed_frames": listed_rows} if listed_rows is not None else {}),
        "frame_step": frame_step,
        "pairing": pairing,
        "alignment": check_alignment(stored, int(extract.max_offset), stop_threshold) if aligned else {},
        "offsets": dict(offsets),
        "place": place_description({kind for kind, _ in paths.values()}, fps, frame_step),
    }


def season_files(
    paths: Mapping[str, tuple[str, Path]], aligned: bool, image_list: Path | None
) -> tuple[dict[str, list[Path]] | None, str, dict[str, list[int]] | None]:
    """(season -> its files in place order, or None for videos and unpaired folders read whole; a
    line saying how places are paired; frames.json's "listed_frames", each kept file's row in its
    folder's full listing (the rows of descriptors computed elsewhere), or None without a list)."""
    files, pairing = pair_season_files(paths) if aligned else (None, "each season its own frames (not aligned)")
    if image_list is None:
        return files, pairing, None
    kept, rows = listed_files(image_list, paths, files)
    return kept, f"{pairing}; {image_list.name} keeps {len(next(iter(kept.values())))} a season", rows


def listed_files(
    image_list: Path, paths: Mapping[str, tuple[str, Path]], files: Mapping[str, list[Path]] | None
) -> tuple[dict[str, list[Path]], dict[str, list[int]]]:
    """(season -> its frame files that `image_list` names, in place order; season -> each kept
    file's row in the folder's natural-order listing)."""
    kinds = sorted({kind for kind, _ in paths.values()} - {"frames"})
    if kinds:
        raise ValueError(f"data.image_list: names frame files, but a season's source is a {kinds[0]}")
    names = read_image_list(image_list)
    kept, rows = {}, {}
    for season, (_, path) in paths.items():
        kept[season] = keep_listed(files[season] if files else list_frame_files(path), names, image_list)
        row_of = {file.name: row for row, file in enumerate(list_frame_files(path))}
        rows[season] = [row_of[file.name] for file in kept[season]]
    return kept, rows


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


def copy_from_dataset(path: Path, out: Path) -> None:
    """A file of the dataset's own (its ground truth) copied into the extraction's output, so that
    the stages after it read it from there, as they read the frames."""
    if not path.is_file():
        raise FileNotFoundError(
            f"{path}: not found (data.frames_dir holds the dataset: its traverses' folders and this file)"
        )
    shutil.copy2(path, out / path.name)
