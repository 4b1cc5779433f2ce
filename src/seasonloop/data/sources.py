"""Read a route's frames, one array per season, from videos or from folders of images.

Both readers return colour frames (N, height, width, 3) uint8 BGR at a storage size, so the rest of
the pipeline does not care where the frames came from. Frame i of every season is the same place.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
import re
from pathlib import Path

import cv2
import numpy as np
from tqdm import tqdm

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")

# A video whose decoder stops this far short of the frame count in its header is truncated or
# corrupt; a few frames of slack allow for containers whose header count is approximate.
_FRAME_COUNT_SLACK = 0.01


def _resize(frame: np.ndarray, height: int, width: int) -> np.ndarray:
    # INTER_AREA averages source pixels: the right filter for shrinking.
    return cv2.resize(frame, (width, height), interpolation=cv2.INTER_AREA)


def sample_video(
    path: Path, fps: float, height: int, width: int, progress: bool = True
) -> np.ndarray:
    """Frames of the video at `path` sampled `fps` times a second, resized to height x width.

    Sample k is the video frame nearest to time k / fps.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: video not found")
    capture = cv2.VideoCapture(str(path))
    try:
        if not capture.isOpened():
            raise ValueError(f"{path}: cannot open video (unsupported or corrupt file)")
        video_fps = capture.get(cv2.CAP_PROP_FPS)
        n_frames = int(capture.get(cv2.CAP_PROP_FRAME_COUNT))
        if video_fps <= 0 or n_frames <= 0:
            raise ValueError(f"{path}: video reports no frame rate or no frames")
        if fps <= 0 or fps > video_fps:
            raise ValueError(f"extract.fps: {fps} must be in (0, {video_fps}] (the frame rate of {path})")
        step = video_fps / fps
        n_samples = int(np.floor((n_frames - 1) / step + 1e-9)) + 1
        wanted = np.rint(np.arange(n_samples) * step).astype(int)
        samples = np.empty((n_samples, height, width, 3), dtype=np.uint8)
        next_sample, frame_index = 0, 0
        bar = tqdm(total=n_samples, desc=f"extract {path.name}", unit="frame", disable=not progress)
        while next_sample < n_samples:
            # grab() skips decoding the frames we do not keep
            if not capture.grab():
                break
            if frame_index == wanted[next_sample]:
                ok, frame = capture.retrieve()
                if not ok or frame is None:
                    raise ValueError(f"{path}: cannot decode frame {frame_index}")
                samples[next_sample] = _resize(frame, height, width)
                next_sample += 1
                bar.update()
            frame_index += 1
        bar.close()
    finally:
        capture.release()
    if next_sample < n_samples:
        if frame_index < n_frames * (1 - _FRAME_COUNT_SLACK):
            raise ValueError(
                f"{path}: video ends at frame {frame_index} of {n_frames} (truncated or corrupt)"
            )
        samples = samples[:next_sample]
    return samples


def natural_key(name: str) -> tuple:
    """Sort key that orders digit runs by value: 2.png before 10.png (plain sorting scrambles them)."""
    return tuple((0, int(part), part) if part.isdigit() else (1, 0, part.lower())
                 for part in re.split(r"(\d+)", name) if part)


def list_frame_files(folder: Path) -> list[Path]:
    """The image files of `folder` in natural order; hidden files (macOS `._*` and the like) skipped."""
    folder = Path(folder)
    if not folder.is_dir():
        raise FileNotFoundError(f"{folder}: frame folder not found")
    files = sorted((p for p in folder.iterdir()
                    if p.suffix.lower() in IMAGE_SUFFIXES and not p.name.startswith(".") and p.is_file()),
                   key=lambda p: natural_key(p.name))
    if not files:
        raise ValueError(f"{folder}: no image files ({', '.join(IMAGE_SUFFIXES)})")
    return files


def align_frame_files(files: Mapping[str, Sequence[Path]]) -> tuple[dict[str, list[Path]], str]:
    """Pair the seasons' frame files place by place: by name when every folder holds the same
    names, else by natural order. Returns (season -> files, a line saying how they were paired).

    Folders that share some names but not all are an error naming a file one season lacks: one
    missing frame would shift every later place. Different counts are left to check_aligned.
    """
    names = {season: [path.name for path in paths] for season, paths in files.items()}
    sets = {season: set(found) for season, found in names.items()}
    first = next(iter(files))
    if all(found == sets[first] for found in sets.values()):
        order = [path.name for path in files[first]]
        by_name = {season: {path.name: path for path in paths} for season, paths in files.items()}
        return ({season: [by_name[season][name] for name in order] for season in files},
                f"frames paired by file name ({len(order)} names shared by {', '.join(files)})")
    shared = set.intersection(*sets.values())
    if shared:
        for season, found in sets.items():
            for other, other_found in sets.items():
                lacking = sorted(other_found - found, key=natural_key)
                if lacking:
                    raise ValueError(
                        f"{Path(files[other][0]).parent}/{lacking[0]}: no frame of that name in {season} "
                        f"({Path(files[season][0]).parent}); the folders share {len(shared)} names but not all, "
                        "so places cannot be paired")
    return ({season: list(paths) for season, paths in files.items()},
            f"frames paired by position in natural order (the seasons' file names differ)")


def read_frame_files(files: Sequence[Path], height: int, width: int, progress: bool = True, desc: str = "read") -> np.ndarray:
    """The images `files`, in that order, resized to height x width."""
    frames = np.empty((len(files), height, width, 3), dtype=np.uint8)
    for i, file in enumerate(tqdm(files, desc=desc, unit="frame", disable=not progress)):
        image = cv2.imread(str(file), cv2.IMREAD_COLOR)
        if image is None:
            raise ValueError(f"{file}: cannot read image (corrupt or not an image)")
        frames[i] = _resize(image, height, width)
    return frames


def read_frame_folder(folder: Path, height: int, width: int, progress: bool = True) -> np.ndarray:
    """Every image of `folder` (in natural order), resized to height x width."""
    return read_frame_files(list_frame_files(folder), height, width, progress, desc=f"read {Path(folder).name}")


def check_aligned(counts: Mapping[str, int], trim_to_shortest: bool, sources: Mapping[str, Path]) -> int:
    """The common number of places; mismatched season lengths are an error unless trimming."""
    shortest = min(counts.values())
    if len(set(counts.values())) > 1 and not trim_to_shortest:
        detail = ", ".join(f"{season}: {counts[season]} ({sources[season]})" for season in counts)
        raise ValueError(
            f"seasons have different numbers of frames ({detail}); "
            "they must be frame-aligned (set extract.trim_to_shortest: true to cut to the shortest)"
        )
    return shortest


def _in_queued_experiment(cwd: Path) -> bool:
    # `dvc exp run --queue` runs in a copy under .dvc/tmp/exps holding only git-tracked files
    return ".dvc/tmp/exps" in cwd.as_posix()


def _check_outside_copy(path: Path, key: str, cwd: Path | None = None) -> None:
    """A relative data path missing in a queued experiment's copy: say why, in one line."""
    if not path.is_absolute() and not path.exists() and _in_queued_experiment(cwd or Path.cwd()):
        raise FileNotFoundError(
            f"{path}: not in this queued experiment's copy of the repository (it holds only git-tracked "
            f"files); give {key} as an absolute path")


def real_sources(source: str, seasons: Sequence[str], data_params: Mapping) -> dict[str, Path]:
    """Where each season's video (source "videos") or frame folder ("frames") is, checked to exist."""
    if source == "videos":
        files = data_params.get("video_files") or {}
        paths = {}
        for season in seasons:
            if season not in files:
                raise ValueError(f"data.video_files: no file given for season '{season}'")
            paths[season] = Path(data_params["videos_dir"]) / files[season]
            _check_outside_copy(paths[season], "data.videos_dir")
            if not paths[season].is_file():
                raise FileNotFoundError(f"{paths[season]}: video for season '{season}' not found")
        return paths
    if source == "frames":
        paths = {season: Path(data_params["frames_dir"]) / season for season in seasons}
        for season, folder in paths.items():
            _check_outside_copy(folder, "data.frames_dir")
            list_frame_files(folder)  # raises, naming the folder, when missing or empty
        return paths
    raise ValueError(f"data.source: unknown source '{source}' (known: synthetic, videos, frames)")


def read_season(kind: str, path: Path, fps: float, height: int, width: int, progress: bool = True,
                frame_step: int = 1, files: Sequence[Path] | None = None) -> np.ndarray:
    """Places of one season from a video (`kind` "video") or a frame folder (`kind` "frames"):
    every `frame_step`-th frame, so a place is one kept frame.

    A frame folder already holds one image per time step (the Nordland PNG release is 1 fps), so
    `fps` applies to videos only; `files` gives the folder's files in place order (align_frame_files),
    else the folder is listed in natural order.
    """
    if frame_step < 1:
        raise ValueError(f"data.frame_step: expected an integer >= 1, got {frame_step!r}")
    if kind == "frames":
        chosen = list(files) if files is not None else list_frame_files(path)
        return read_frame_files(chosen[::frame_step], height, width, progress, desc=f"read {Path(path).name}")
    if kind == "video":
        return np.ascontiguousarray(sample_video(path, fps, height, width, progress)[::frame_step])
    raise ValueError(f"unknown frame source kind '{kind}' (known: video, frames)")


def place_description(kind: str, fps: float, frame_step: int) -> str:
    """What one place (one row of every season's arrays) is, for the metrics and the report."""
    if kind == "frames":
        return "one image of each season's folder" if frame_step == 1 else f"every {frame_step}th image of each season's folder"
    return f"one video frame every {frame_step / fps:g} s (extract.fps {fps:g}, data.frame_step {frame_step})"
