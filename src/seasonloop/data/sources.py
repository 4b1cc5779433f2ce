"""Where a route's frames come from, and how one season of them is read (seasonloop.data.frames reads).

Every reader returns colour frames (N, height, width, 3) uint8 BGR at a storage size, so the rest
of the pipeline does not care where the frames came from. Frame i of every season is the same place.

Two registries: SOURCES (data.source -> the kind of its files and where they are, or how they are
rendered: "synthetic", the built-in route) and FRAME_KINDS (a kind in data/acquired/sources.json -> how one
season is read, how places are paired across seasons and what a place is). A new source is one
locating (or rendering) function plus one SOURCES line; a new kind one reader plus one FRAME_KINDS line.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from seasonloop.data.frames import align_frame_files, list_frame_files, read_frame_files, sample_video
from seasonloop.params.settings import DataConfig, SyntheticConfig


def check_aligned(counts: Mapping[str, int], trim_to_shortest: bool, sources: Mapping[str, Path | str]) -> int:
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
            f"files); give {key} as an absolute path"
        )


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


def _render_synthetic(
    out: Path, seasons: Sequence[str], data: DataConfig, synthetic: SyntheticConfig
) -> dict[str, Path]:
    # here: every stage's params check imports this module (its SOURCES), and only acquire renders
    from seasonloop.data.synthetic import RouteDifficulty, SeasonRide, render_route

    # the difficulty knobs are keys of the synthetic section with RouteDifficulty's field names
    difficulty = RouteDifficulty(**{knob: getattr(synthetic, knob) for knob in RouteDifficulty.knobs()})
    # seasons without a ride ride the reference; rides of seasons not rendered are not used
    rides = {season: SeasonRide(**synthetic.rides[season]) for season in seasons if season in synthetic.rides}
    render_route(
        out,
        seasons,
        synthetic.seconds,
        synthetic.fps,
        synthetic.width,
        synthetic.height,
        synthetic.seed,
        difficulty=difficulty,
        rides=rides or None,  # {}: today's aligned data, no rides.json
    )
    return {season: out / f"{season}.mp4" for season in seasons}


def _frame_folders(seasons: Sequence[str], data: DataConfig) -> dict[str, Path]:
    paths = {season: Path(data.frames_dir) / season for season in seasons}
    for folder in paths.values():
        _check_outside_copy(folder, "data.frames_dir")
        list_frame_files(folder)  # raises, naming the folder, when missing or empty
    return paths


@dataclass(frozen=True)
class Source:
    """One value of data.source: the FRAME_KINDS kind of its files, and how to find them (season ->
    path, checked to exist) or, for a rendered source, how to render them (into a folder, returning
    season -> path)."""

    kind: str
    locate: Callable[[Sequence[str], DataConfig], dict[str, Path]] | None = None
    render: Callable[[Path, Sequence[str], DataConfig, SyntheticConfig], dict[str, Path]] | None = None


# data.source is checked against these names (seasonloop.registries)
SOURCES: dict[str, Source] = {
    "synthetic": Source("video", render=_render_synthetic),  # seasonloop.data.synthetic
    "videos": Source("video", locate=_video_files),
    "frames": Source("frames", locate=_frame_folders),
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


def acquire_sources(out: Path, seasons: Sequence[str], data: DataConfig, synthetic: SyntheticConfig) -> dict[str, Path]:
    """Season -> the file(s) to read for data.source: rendered into `out` (the built-in route), or
    found on disk and checked to exist."""
    source = get_source(data.source)
    if source.render is not None:
        return source.render(Path(out), seasons, data, synthetic)
    return real_sources(data.source, seasons, data)


# ---- kinds of files: reading a season, pairing places, describing a place ------------------------


def _read_video(
    path: Path, fps: float, height: int, width: int, progress: bool, frame_step: int, files: Sequence[Path] | None
) -> np.ndarray:
    return np.ascontiguousarray(sample_video(path, fps, height, width, progress)[::frame_step])


def _read_frames(
    path: Path, fps: float, height: int, width: int, progress: bool, frame_step: int, files: Sequence[Path] | None
) -> np.ndarray:
    # A frame folder already holds one image per time step (the Nordland PNG release is 1 fps),
    # so fps is not used; only the kept files are read.
    chosen = list(files) if files is not None else list_frame_files(path)
    return read_frame_files(chosen[::frame_step], height, width, progress, desc=f"read {Path(path).name}")


def _video_place(fps: float, frame_step: int) -> str:
    return f"one video frame every {frame_step / fps:g} s (extract.fps {fps:g}, data.frame_step {frame_step})"


def _frame_place(fps: float, frame_step: int) -> str:
    return (
        "one image of each season's folder"
        if frame_step == 1
        else f"every {frame_step}th image of each season's folder"
    )


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


def read_season(
    kind: str,
    path: Path,
    fps: float,
    height: int,
    width: int,
    progress: bool = True,
    frame_step: int = 1,
    files: Sequence[Path] | None = None,
) -> np.ndarray:
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
