"""Rendering a whole route: one video per season plus the layout (`render_route`), and a
preview grid of a few places in every season (`render_preview`)."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np
from tqdm import tqdm

from ...params.seasons import SEASONS
from ..layout import RouteLayout
from .difficulty import DEFAULT_DIFFICULTY, RouteDifficulty
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
) -> RouteLayout:
    """Write out_dir/<season>.mp4 (seconds*fps frames, frame k at time k/fps) and out_dir/layout.json.

    All seasons are rendered side by side so each place's geometry is drawn once. On any error the
    files this call was writing are removed. `difficulty`: see `RouteDifficulty`.
    """
    seasons = _check_seasons(seasons)
    if int(fps) != fps or fps < 1:
        raise ValueError(f"fps must be a positive integer, got {fps!r}")
    route = SyntheticRoute(seconds, seed, difficulty)
    route.frame(seasons[0], 0.0, width, height)  # validates the size before any file is created
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    video_paths = [out_dir / f"{season}.mp4" for season in seasons]
    layout_path = out_dir / "layout.json"
    writers: list[cv2.VideoWriter] = []
    try:
        for path in video_paths:
            writer = cv2.VideoWriter(str(path), cv2.VideoWriter.fourcc(*"mp4v"), float(fps), (int(width), int(height)))
            if not writer.isOpened():
                raise OSError(f"cannot open video writer for {path}")
            writers.append(writer)
        n_frames = route.seconds * int(fps)
        for k in tqdm(range(n_frames), desc="render route", unit="frame", disable=not progress):
            t = k / fps
            for season, writer in zip(seasons, writers):
                writer.write(route.frame(season, t, width, height))
        for writer in writers:
            writer.release()
        writers.clear()
        # OpenCV's writer does not raise when the disk fills: check what it left
        for path in video_paths:
            if not path.is_file() or path.stat().st_size == 0:
                raise OSError(f"{path}: the video was not written (is the disk full?)")
        layout_path.write_text(json.dumps(route.layout.to_json(), indent=1))
    except BaseException:
        for writer in writers:
            writer.release()
        for path in [*video_paths, layout_path]:
            path.unlink(missing_ok=True)
        raise
    return route.layout


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
