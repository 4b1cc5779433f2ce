"""Rendering a whole route: one video per season plus the layout and each frame's position
(`render_route`), and a preview grid of a few places in every season (`render_preview`)."""

from __future__ import annotations

import json
import multiprocessing
import os
import sys
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from functools import partial
from pathlib import Path
from typing import NamedTuple

import cv2
import numpy as np
from tqdm import tqdm

from ...params.seasons import SEASONS
from ..layout import RouteLayout
from .difficulty import DEFAULT_DIFFICULTY, RouteDifficulty
from .ride import SeasonRide
from .world import SyntheticRoute


def _check_seasons(seasons: Sequence[str]) -> list[str]:
    """`seasons` as a list; an empty, unknown or repeated season raises ValueError."""
    seasons = list(seasons)
    if not seasons:
        raise ValueError("seasons is empty")
    for season in seasons:
        if season not in SEASONS:
            raise ValueError(f"unknown season {season!r}; expected some of {SEASONS}")
    if len(set(seasons)) != len(seasons):
        raise ValueError(f"seasons contains duplicates: {seasons}")
    return seasons


Frames = Callable[[float, int, int], np.ndarray]  # (season's time, width, height) -> image


def _season_clocks(
    route: SyntheticRoute, seasons: list[str], fps: int, rides: Mapping[str, SeasonRide] | None
) -> dict[str, tuple[int, Frames, np.ndarray]]:
    """Season -> (frames of its video, its frame at its own time, the position of each frame).

    Without rides every season rides the reference (`route.frame`, seconds*fps frames)."""
    clocks: dict[str, tuple[int, Frames, np.ndarray]] = {}
    for season in seasons:
        if not rides:
            n_frames = route.seconds * fps
            times = np.arange(n_frames) / fps
            clocks[season] = (n_frames, partial(route.frame, season), np.asarray(route.position(times)))
            continue
        ride = rides.get(season, SeasonRide())
        if not isinstance(ride, SeasonRide):
            raise ValueError(f"rides.{season}: expected a SeasonRide, got {ride!r}")
        n_frames = route.timeline(season, ride).n_frames(fps)
        positions = np.asarray(route.ride_position(season, ride, np.arange(n_frames) / fps))
        clocks[season] = (n_frames, partial(route.ride_frame, season, ride), positions)
    return clocks


def _write_positions(path: Path, positions: np.ndarray, fps: int) -> None:
    """CSV `time_s,distance_m`: one row per video frame, its time k/fps and exact route position."""
    table = np.column_stack([np.arange(len(positions)) / fps, positions])
    np.savetxt(path, table, fmt=["%.6f", "%.4f"], delimiter=",", header="time_s,distance_m", comments="")


def render_route(
    out_dir: Path,
    seasons: Sequence[str],
    seconds: int,
    fps: int,
    width: int,
    height: int,
    seed: int,
    progress: bool = True,
    difficulty: RouteDifficulty = DEFAULT_DIFFICULTY,
    rides: Mapping[str, SeasonRide] | None = None,
) -> RouteLayout:
    """Write out_dir/<season>.mp4 (frame k at time k/fps), out_dir/positions/<season>.csv (each
    frame's exact distance along the route) and out_dir/layout.json (the reference ride's layout).

    Without `rides` (None or empty) frame k of every season is the same place, seconds*fps frames.
    With `rides` (season -> SeasonRide; seasons not in it ride the reference) each season rides at
    its own pace for its own number of frames, and out_dir/rides.json records each ride with its
    stops and tunnels in its own video seconds. All seasons are rendered side by side so a place's
    geometry is drawn once. On any error the files this call was writing are removed.
    """
    seasons = _check_seasons(seasons)
    if int(fps) != fps or fps < 1:
        raise ValueError(f"fps must be a positive integer, got {fps!r}")
    fps = int(fps)
    unknown = [season for season in rides or {} if season not in seasons]
    if unknown:
        raise ValueError(f"rides: season {unknown[0]!r} is not rendered (seasons: {seasons})")
    route = SyntheticRoute(seconds, seed, difficulty)
    route.frame(seasons[0], 0.0, width, height)  # validates the size before any file is created
    clocks = _season_clocks(route, seasons, fps, rides)  # validates the rides too
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    video_paths = [out_dir / f"{season}.mp4" for season in seasons]
    positions_dir = out_dir / "positions"
    made_positions_dir = not positions_dir.exists()
    written = [*video_paths, out_dir / "layout.json", *(positions_dir / f"{s}.csv" for s in seasons)]
    written += [out_dir / "rides.json"] if rides else []
    try:
        recipe = _RouteRecipe(seconds, seed, difficulty, seasons, fps, rides)
        frames = _rendered_frames(recipe, [clocks[season] for season in seasons], width, height)
        _write_videos(video_paths, frames, max(count for count, _, _ in clocks.values()), fps, width, height, progress)
        positions_dir.mkdir(exist_ok=True)
        for season in seasons:
            _write_positions(positions_dir / f"{season}.csv", clocks[season][2], fps)
        (out_dir / "layout.json").write_text(json.dumps(route.layout.to_json(), indent=1))
        if rides:
            record = {
                season: route.timeline(season, rides.get(season, SeasonRide())).to_json(fps) for season in seasons
            }
            (out_dir / "rides.json").write_text(json.dumps({"fps": fps, "seasons": record}, indent=1))
        else:
            (out_dir / "rides.json").unlink(missing_ok=True)  # an earlier render's would describe other videos
    except BaseException:
        for path in written:
            path.unlink(missing_ok=True)
        if made_positions_dir and positions_dir.is_dir() and not any(positions_dir.iterdir()):
            positions_dir.rmdir()
        raise
    return route.layout


# Frames are rendered in chunks of consecutive video frames, every season of a frame together (the
# seasons share a place's geometry), by worker processes when the render is large enough to pay
# for a worker's start-up (~0.5 s, a few hundred frames' rendering); the videos are written here,
# in order, so the files are the same whatever the number of workers.
_CHUNK_FRAMES = 64
_FRAMES_PER_WORKER = 2000
_worker_clocks: list[tuple[int, Frames, np.ndarray]] = []


class _RouteRecipe(NamedTuple):
    """What a render worker rebuilds its own route and clocks from (render_route's arguments)."""

    seconds: int
    seed: int
    difficulty: RouteDifficulty
    seasons: list[str]
    fps: int
    rides: Mapping[str, SeasonRide] | None


def _render_chunk(
    clocks: list[tuple[int, Frames, np.ndarray]], first: int, stop: int, fps: int, width: int, height: int
) -> list[list[np.ndarray | None]]:
    """Frames first..stop-1 of every clock (None past a clock's last frame)."""
    return [
        [frame(k / fps, width, height) if k < count else None for count, frame, _ in clocks] for k in range(first, stop)
    ]


def _start_worker(recipe: _RouteRecipe) -> None:
    """A render worker's own route and clocks, built from the same arguments as the caller's."""
    clocks = _season_clocks(
        SyntheticRoute(recipe.seconds, recipe.seed, recipe.difficulty), recipe.seasons, recipe.fps, recipe.rides
    )
    _worker_clocks[:] = [clocks[season] for season in recipe.seasons]


def _render_worker_chunk(chunk: tuple[int, int], fps: int, width: int, height: int) -> list[list[np.ndarray | None]]:
    return _render_chunk(_worker_clocks, *chunk, fps, width, height)


def _cores_for_workers() -> int:
    """Cores for render workers: 1 (render here) where spawned children cannot start, i.e. when the
    main script is not a file they can import (`python - < script`); the videos are the same."""
    main_file = getattr(sys.modules["__main__"], "__file__", None)
    if main_file is not None and not os.path.isfile(main_file):
        return 1
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def _rendered_frames(
    recipe: _RouteRecipe, clocks: list[tuple[int, Frames, np.ndarray]], width: int, height: int
) -> Iterator[list[np.ndarray | None]]:
    """Video frame k of every clock, k = 0, 1, ...: rendered here or by worker processes."""
    fps, n_frames = recipe.fps, max(count for count, _, _ in clocks)
    chunks = [(first, min(first + _CHUNK_FRAMES, n_frames)) for first in range(0, n_frames, _CHUNK_FRAMES)]
    workers = min(_cores_for_workers(), sum(count for count, _, _ in clocks) // _FRAMES_PER_WORKER, len(chunks))
    if workers < 2:
        for first, stop in chunks:
            yield from _render_chunk(clocks, first, stop, fps, width, height)
        return
    # spawn, not fork: a forked child of a process whose OpenCV or OpenMP threads are running can
    # hang; a worker that cannot start raises BrokenProcessPool here instead of hanging
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(workers, context, initializer=_start_worker, initargs=(recipe,)) as pool:
        render = partial(_render_worker_chunk, fps=fps, width=width, height=height)
        for chunk in pool.map(render, chunks):
            yield from chunk


def _write_videos(
    paths: list[Path],
    frames: Iterator[list[np.ndarray | None]],
    n_frames: int,
    fps: int,
    width: int,
    height: int,
    progress: bool,
) -> None:
    """One video per path: frame k of each (frames' k-th item, None past its end) at time k/fps."""
    writers: list[cv2.VideoWriter] = []
    try:
        for path in paths:
            writer = cv2.VideoWriter(str(path), cv2.VideoWriter.fourcc(*"mp4v"), float(fps), (int(width), int(height)))
            if not writer.isOpened():
                raise OSError(f"cannot open video writer for {path}")
            writers.append(writer)
        for seasons_frames in tqdm(frames, total=n_frames, desc="render route", unit="frame", disable=not progress):
            for image, writer in zip(seasons_frames, writers):
                if image is not None:
                    writer.write(image)
    finally:
        for writer in writers:
            writer.release()
    # OpenCV's writer does not raise when the disk fills: check what it left
    for path in paths:
        if not path.is_file() or path.stat().st_size == 0:
            raise OSError(f"{path}: the video was not written (is the disk full?)")


def render_preview(
    path: Path,
    seconds: int,
    seed: int,
    times: Sequence[float],
    width: int = 256,
    height: int = 144,
    difficulty: RouteDifficulty = DEFAULT_DIFFICULTY,
) -> None:
    """PNG grid: one row per place (video time), one labelled column per season."""
    times = list(times)
    if not times:
        raise ValueError("times is empty")
    route = SyntheticRoute(seconds, seed, difficulty)
    label_w, header_h, gap = 70, 22, 2
    grid = np.full((header_h + len(times) * (height + gap), label_w + len(SEASONS) * (width + gap), 3), 255, np.uint8)
    font = cv2.FONT_HERSHEY_SIMPLEX
    for col, season in enumerate(SEASONS):
        cv2.putText(grid, season, (label_w + col * (width + gap) + 4, 16), font, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
    for row, t in enumerate(times):
        y = header_h + row * (height + gap)
        cv2.putText(grid, f"t={t:g}s", (4, y + height // 2), font, 0.45, (0, 0, 0), 1, cv2.LINE_AA)
        for col, season in enumerate(SEASONS):
            x = label_w + col * (width + gap)
            grid[y : y + height, x : x + width] = route.frame(season, float(t), width, height)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if not cv2.imwrite(str(path), grid):
        raise OSError(f"cannot write preview PNG {path}")
