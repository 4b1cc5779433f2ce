"""Read frames from a video or from a folder of images, at a storage size.

Both readers return colour frames (N, height, width, 3) uint8 BGR; folders are listed in natural
order (2.png before 10.png) and paired across seasons by file name when they can be. Which source
a season comes from is seasonloop.data.sources' business.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path, PurePosixPath

import numpy as np

# cv2 and tqdm are imported in the functions that read: every stage's params check imports this
# module (data.source's registry, seasonloop.data.sources), and most stages read no frame

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")

# A video whose decoder stops this far short of the frame count in its header is truncated or
# corrupt; a few frames of slack allow for containers whose header count is approximate.
_FRAME_COUNT_SLACK = 0.01


def _resize(frame: np.ndarray, height: int, width: int) -> np.ndarray:
    import cv2

    # INTER_AREA averages source pixels: the right filter for shrinking.
    return cv2.resize(frame, (width, height), interpolation=cv2.INTER_AREA)


def sample_video(path: Path, fps: float, height: int, width: int, progress: bool = True) -> np.ndarray:
    """Frames of the video at `path` sampled `fps` times a second, resized to height x width.

    Sample k is the video frame nearest to time k / fps.
    """
    import cv2
    from tqdm import tqdm

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
            raise ValueError(f"{path}: video ends at frame {frame_index} of {n_frames} (truncated or corrupt)")
        samples = samples[:next_sample]
    return samples


def video_sample_count(path: Path, fps: float) -> int:
    """How many samples sample_video takes of the video at `path` at `fps` (from its header)."""
    import cv2

    capture = cv2.VideoCapture(str(path))
    try:
        video_fps, n_frames = capture.get(cv2.CAP_PROP_FPS), int(capture.get(cv2.CAP_PROP_FRAME_COUNT))
    finally:
        capture.release()
    if video_fps <= 0 or n_frames <= 0:
        raise ValueError(f"{path}: video reports no frame rate or no frames")
    return int(np.floor((n_frames - 1) / (video_fps / fps) + 1e-9)) + 1


def natural_key(name: str) -> tuple:
    """Sort key that orders digit runs by value: 2.png before 10.png (plain sorting scrambles them)."""
    return tuple(
        (0, int(part), part) if part.isdigit() else (1, 0, part.lower()) for part in re.split(r"(\d+)", name) if part
    )


def list_frame_files(folder: Path) -> list[Path]:
    """The image files of `folder` in natural order; hidden files (macOS `._*` and the like) skipped."""
    folder = Path(folder)
    if not folder.is_dir():
        raise FileNotFoundError(f"{folder}: frame folder not found")
    files = sorted(
        (
            p
            for p in folder.iterdir()
            if p.suffix.lower() in IMAGE_SUFFIXES and not p.name.startswith(".") and p.is_file()
        ),
        key=lambda p: natural_key(p.name),
    )
    if not files:
        raise ValueError(f"{folder}: no image files ({', '.join(IMAGE_SUFFIXES)})")
    return files


def read_image_list(path: Path) -> list[str]:
    """The image names of a list file, one a line (cleanImageNames.txt, Patch-NetVLAD's
    nordland_imageNames_*.txt): each line's file name, its folders ignored; blank lines skipped."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: image list not found (data.image_list)")
    names = [PurePosixPath(line.strip().replace("\\", "/")).name for line in path.read_text().splitlines()]
    names = [name for name in names if name]
    if not names:
        raise ValueError(f"{path}: the image list names no image (data.image_list)")
    return names


def keep_listed(files: Sequence[Path], names: Sequence[str], list_file: Path) -> list[Path]:
    """The files of `files` (one season's, in place order) whose names `names` lists, in that
    order; a listed name the season lacks is an error (it would shift every later place)."""
    listed = set(names)
    kept = [path for path in files if path.name in listed]
    if len(kept) < len(listed):
        lacking = sorted(listed - {path.name for path in kept}, key=natural_key)
        folder = Path(files[0]).parent if files else "the season's folder"
        raise ValueError(f"{list_file}: {len(lacking)} listed images are not in {folder} (first: {lacking[0]})")
    return kept


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
        return (
            {season: [by_name[season][name] for name in order] for season in files},
            f"frames paired by file name ({len(order)} names shared by {', '.join(files)})",
        )
    shared = set.intersection(*sets.values())
    if shared:
        for season, found in sets.items():
            for other, other_found in sets.items():
                lacking = sorted(other_found - found, key=natural_key)
                if lacking:
                    raise ValueError(
                        f"{Path(files[other][0]).parent}/{lacking[0]}: no frame of that name in {season} "
                        f"({Path(files[season][0]).parent}); the folders share {len(shared)} names but not all, "
                        "so places cannot be paired"
                    )
    return (
        {season: list(paths) for season, paths in files.items()},
        "frames paired by position in natural order (the seasons' file names differ)",
    )


def read_frame_files(
    files: Sequence[Path], height: int, width: int, progress: bool = True, desc: str = "read"
) -> np.ndarray:
    """The images `files`, in that order, resized to height x width."""
    import cv2
    from tqdm import tqdm

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
