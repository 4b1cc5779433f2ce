"""Read a route's frames, one array per season, from videos or from folders of images.

Both readers return colour frames (N, height, width, 3) uint8 BGR at a storage size, so the rest of
the pipeline does not care where the frames came from. Frame i of every season is the same place.

Two registries: SOURCES (data.source -> the kind of its files and where they are; "synthetic" is
rendered by the acquire stage) and FRAME_KINDS (a kind in data/acquired/sources.json -> how one
season is read, how places are paired across seasons and what a place is). A new source is one
locating function plus one SOURCES line; a new kind one reader plus one FRAME_KINDS line.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass
import re
from pathlib import Path

import cv2
import numpy as np
from tqdm import tqdm

from seasonloop.settings import DataConfig

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


# ---- data.source: where each season's files are ----------------------------------------------

def _video_files(seasons: Sequence[str], data: DataConfig) -> dict[str, Path]:
    paths = {}
    for season in seasons:
        if season not in data.video_files:
            raise ValueError(f"data.video_files: no file given for season '{season}'")
        paths[season] = Path(data.videos_dir) / data.video_files[season]
        _check_outside_copy(paths[season], "data.videos_dir")
        if not paths[season].is_file():
            raise FileNotFoundError(f"{paths[season]}: video for season '{season}' not found")
    return paths


def _frame_folders(seasons: Sequence[str], data: DataConfig) -> dict[str, Path]:
    paths = {season: Path(data.frames_dir) / season for season in seasons}
    for season, folder in paths.items():
        _check_outside_copy(folder, "data.frames_dir")
        list_frame_files(folder)  # raises, naming the folder, when missing or empty
    return paths


@dataclass(frozen=True)
class Source:
    """One value of data.source: the FRAME_KINDS kind of its files, and how to find them (season ->
    path, checked to exist); None for a source the acquire stage renders itself."""

    kind: str
    locate: Callable[[Sequence[str], DataConfig], dict[str, Path]] | None


# The order is config.SOURCES' (tests/test_config.py keeps them in step).
SOURCES: dict[str, Source] = {
    "synthetic": Source("video", None),  # stages/acquire.py renders it (seasonloop.data.synthetic)
    "videos": Source("video", _video_files),
    "frames": Source("frames", _frame_folders),
}


def get_source(name: str) -> Source:
    """The source registered under data.source `name`."""
    if name not in SOURCES:
        raise ValueError(f"data.source: unknown source '{name}' (known: {', '.join(SOURCES)})")
    return SOURCES[name]


def real_sources(source: str, seasons: Sequence[str], data: DataConfig) -> dict[str, Path]:
    """Where each season's files are for a source read from disk (data.source "videos": a video
    per season, "frames": a frame folder per season), checked to exist."""
    locate = get_source(source).locate
    if locate is None:
        real = ", ".join(name for name, entry in SOURCES.items() if entry.locate is not None)
        raise ValueError(f"data.source: '{source}' is rendered, not read from disk (sources on disk: {real})")
    return locate(seasons, data)


# ---- kinds of files: reading a season, pairing places, describing a place ------------------------

def _read_video(path: Path, fps: float, height: int, width: int, progress: bool, frame_step: int,
                files: Sequence[Path] | None) -> np.ndarray:
    return np.ascontiguousarray(sample_video(path, fps, height, width, progress)[::frame_step])


def _read_frames(path: Path, fps: float, height: int, width: int, progress: bool, frame_step: int,
                 files: Sequence[Path] | None) -> np.ndarray:
    # A frame folder already holds one image per time step (the Nordland PNG release is 1 fps),
    # so fps is not used; only the kept files are read.
    chosen = list(files) if files is not None else list_frame_files(path)
    return read_frame_files(chosen[::frame_step], height, width, progress, desc=f"read {Path(path).name}")


def _video_place(fps: float, frame_step: int) -> str:
    return f"one video frame every {frame_step / fps:g} s (extract.fps {fps:g}, data.frame_step {frame_step})"


def _frame_place(fps: float, frame_step: int) -> str:
    return "one image of each season's folder" if frame_step == 1 else f"every {frame_step}th image of each season's folder"


@dataclass(frozen=True)
class FrameKind:
    """How one kind of season file is read (every frame_step-th place), what a place is, and the
    listing of its files to pair seasons by file name (None: places are paired by time)."""

    read: Callable[[Path, float, int, int, bool, int, Sequence[Path] | None], np.ndarray]
    place: Callable[[float, int], str]
    list_files: Callable[[Path], list[Path]] | None


FRAME_KINDS: dict[str, FrameKind] = {
    "video": FrameKind(_read_video, _video_place, None),
    "frames": FrameKind(_read_frames, _frame_place, list_frame_files),
}


def get_frame_kind(kind: str) -> FrameKind:
    """How files of `kind` (a sources.json kind) are read."""
    if kind not in FRAME_KINDS:
        raise ValueError(f"unknown frame source kind '{kind}' (known: {', '.join(FRAME_KINDS)})")
    return FRAME_KINDS[kind]


def read_season(kind: str, path: Path, fps: float, height: int, width: int, progress: bool = True,
                frame_step: int = 1, files: Sequence[Path] | None = None) -> np.ndarray:
    """Places of one season from a file of FRAME_KINDS `kind` ("video": a video, "frames": a frame
    folder): every `frame_step`-th frame, so a place is one kept frame.

    `fps` applies to videos only; `files` gives a folder's files in place order (pair_season_files),
    else the folder is listed in natural order.
    """
    if frame_step < 1:
        raise ValueError(f"data.frame_step: expected an integer >= 1, got {frame_step!r}")
    return get_frame_kind(kind).read(path, fps, height, width, progress, frame_step, files)


def pair_season_files(sources: Mapping[str, tuple[str, Path]]) -> tuple[dict[str, list[Path]] | None, str]:
    """(season -> files in place order, or None, and a line saying how places are paired) for
    season -> (kind, path): seasons all of one kind that lists files are paired by align_frame_files,
    any others by time."""
    kinds = {kind for kind, _ in sources.values()}
    list_files = get_frame_kind(kinds.pop()).list_files if len(kinds) == 1 else None
    if list_files is None:
        return None, "video samples paired by time"
    return align_frame_files({season: list_files(Path(path)) for season, (_, path) in sources.items()})


def place_description(kinds: Collection[str], fps: float, frame_step: int) -> str:
    """What one place (one row of every season's arrays) is, for the metrics and the report, when
    the seasons' files are of `kinds`."""
    # seasons of different kinds are paired by time, as videos are
    kind = next(iter(kinds)) if len(set(kinds)) == 1 else "video"
    return get_frame_kind(kind).place(fps, frame_step)
