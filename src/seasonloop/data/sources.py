"""Read a route's frames, one array per season, from videos or from folders of images.

Both readers return colour frames (N, height, width, 3) uint8 BGR at a storage size, so the rest of
the pipeline does not care where the frames came from. Frame i of every season is the same place.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
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


def list_frame_files(folder: Path) -> list[Path]:
    folder = Path(folder)
    if not folder.is_dir():
        raise FileNotFoundError(f"{folder}: frame folder not found")
    files = sorted(p for p in folder.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
    if not files:
        raise ValueError(f"{folder}: no image files ({', '.join(IMAGE_SUFFIXES)})")
    return files


def read_frame_folder(folder: Path, height: int, width: int, progress: bool = True) -> np.ndarray:
    """Every image of `folder` (sorted by file name), resized to height x width."""
    files = list_frame_files(folder)
    frames = np.empty((len(files), height, width, 3), dtype=np.uint8)
    for i, file in enumerate(tqdm(files, desc=f"read {Path(folder).name}", unit="frame", disable=not progress)):
        image = cv2.imread(str(file), cv2.IMREAD_COLOR)
        if image is None:
            raise ValueError(f"{file}: cannot read image (corrupt or not an image)")
        frames[i] = _resize(image, height, width)
    return frames


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


def real_sources(source: str, seasons: Sequence[str], data_params: Mapping) -> dict[str, Path]:
    """Where each season's video (source "videos") or frame folder ("frames") is, checked to exist."""
    if source == "videos":
        files = data_params.get("video_files") or {}
        paths = {}
        for season in seasons:
            if season not in files:
                raise ValueError(f"data.video_files: no file given for season '{season}'")
            paths[season] = Path(data_params["videos_dir"]) / files[season]
            if not paths[season].is_file():
                raise FileNotFoundError(f"{paths[season]}: video for season '{season}' not found")
        return paths
    if source == "frames":
        paths = {season: Path(data_params["frames_dir"]) / season for season in seasons}
        for season, folder in paths.items():
            list_frame_files(folder)  # raises, naming the folder, when missing or empty
        return paths
    raise ValueError(f"data.source: unknown source '{source}' (known: synthetic, videos, frames)")


def read_season(kind: str, path: Path, fps: float, height: int, width: int, progress: bool = True) -> np.ndarray:
    """Frames of one season from a video (`kind` "video") or a frame folder (`kind` "frames").

    A frame folder already holds one image per time step (the Nordland PNG release is 1 fps), so
    `fps` applies to videos only.
    """
    if kind == "frames":
        return read_frame_folder(path, height, width, progress)
    if kind == "video":
        return sample_video(path, fps, height, width, progress)
    raise ValueError(f"unknown frame source kind '{kind}' (known: video, frames)")
