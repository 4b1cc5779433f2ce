"""Where each place of a season is, in metres: read from a CSV beside the data, or from the renderer.

A positions CSV holds one row per frame (for a frame folder: in the folder's natural order, or
keyed by a column of file names) or one row per time (for a video: a column of video seconds,
interpolated at each kept sample's time). Its coordinate columns are metres (x, y; or one
column of distance along the route) or degrees (latitude, longitude), converted to metres on a
local plane (equirectangular about the seasons' mean latitude: errors well under a metre over a
few kilometres, which is what a tolerance of metres needs).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

EARTH_RADIUS_M = 6_371_000.0
UNITS = ("metres", "degrees")


def read_table(path: Path, columns: Sequence[str], key: str | None) -> tuple[np.ndarray, pd.Series | None]:
    """(coordinates (n, k) float64, the key column or None) of a positions CSV; a missing file or
    column, or a coordinate that is not a finite number, is one line naming the file."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: positions file not found")
    try:
        table = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as error:
        raise ValueError(f"{path}: cannot read positions CSV ({error})") from None
    wanted = [*columns, *([key] if key else [])]
    missing = [column for column in wanted if column not in table.columns]
    if missing:
        raise ValueError(f"{path}: no column {missing[0]!r} (columns: {', '.join(map(str, table.columns))})")
    coordinates = table[list(columns)].apply(pd.to_numeric, errors="coerce").to_numpy(np.float64)
    bad = ~np.isfinite(coordinates).all(axis=1)
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{path}: {int(bad.sum())} rows with a missing, non-numeric or infinite coordinate "
            f"(first: data row {row + 1}: {table.iloc[row][list(columns)].to_dict()})"
        )
    return coordinates, (table[key] if key else None)


def degrees_to_metres(coordinates: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """season -> (n, 2) (latitude, longitude) degrees, to (north, east) metres on one local plane
    shared by every season (so positions compare across seasons)."""
    every = np.concatenate(list(coordinates.values()))
    if (np.abs(every[:, 0]) > 90).any() or (np.abs(every[:, 1]) > 180).any():
        raise ValueError("data.position_columns: degrees must be (latitude, longitude) within +-90, +-180")
    lat0, lon0 = np.radians(every[:, 0].mean()), np.radians(every[:, 1].mean())
    return {
        season: np.stack(
            [
                EARTH_RADIUS_M * (np.radians(values[:, 0]) - lat0),
                EARTH_RADIUS_M * np.cos(lat0) * (np.radians(values[:, 1]) - lon0),
            ],
            axis=1,
        )
        for season, values in coordinates.items()
    }


def at_times(coordinates: np.ndarray, times: np.ndarray, wanted: np.ndarray, source: Path) -> np.ndarray:
    """Coordinates interpolated at the video times `wanted` (s) from rows at `times`."""
    times = pd.to_numeric(pd.Series(times), errors="coerce").to_numpy(np.float64)
    if not np.isfinite(times).all() or (np.diff(times) <= 0).any():
        raise ValueError(f"{source}: the time column must hold increasing numbers of seconds")
    if len(wanted) and (wanted[0] < times[0] - 1e-6 or wanted[-1] > times[-1] + 1e-6):
        raise ValueError(
            f"{source}: positions cover {times[0]:g}-{times[-1]:g} s, but frames are kept from "
            f"{wanted[0]:g} to {wanted[-1]:g} s"
        )
    return np.stack([np.interp(wanted, times, coordinates[:, k]) for k in range(coordinates.shape[1])], axis=1)


def for_files(coordinates: np.ndarray, names: pd.Series | None, files: Sequence[Path], source: Path) -> np.ndarray:
    """One position per frame file of the folder (all of them, in natural order): by the name
    column, or row i for file i."""
    if names is None:
        if len(coordinates) != len(files):
            raise ValueError(
                f"{source}: {len(coordinates)} positions for {len(files)} frames in {Path(files[0]).parent} "
                "(one row per frame, in the folder's natural order, or name the frames in a column)"
            )
        return coordinates
    row = {str(name): i for i, name in enumerate(names)}
    lacking = [file.name for file in files if file.name not in row]
    if lacking:
        raise ValueError(f"{source}: no position for {len(lacking)} frames (first: {lacking[0]})")
    return coordinates[[row[file.name] for file in files]]


@dataclass(frozen=True)
class PositionFiles:
    """Where the seasons' positions are: <folder>/<season>.csv, its coordinate columns and units,
    and its key column (videos: seconds; frames: file names, or None for rows in frame order)."""

    folder: Path
    columns: tuple[str, ...]
    units: str
    key: str | None

    def file(self, season: str) -> Path:
        return Path(self.folder) / f"{season}.csv"


# what the built-in renderer writes beside its videos (seasonloop.data.synthetic.video)
RENDERED = PositionFiles(Path("positions"), ("distance_m",), "metres", "time_s")


def season_positions(
    kind: str, files: PositionFiles, season: str, n_read: int, fps: float, frame_step: int, frame_files: list[Path]
) -> np.ndarray:
    """(n_read, k) coordinates of the `n_read` places read of one season (before offsets), in the
    CSV's units: a video's at each kept sample's time, a folder's per kept file."""
    source = files.file(season)
    coordinates, key = read_table(source, files.columns, files.key)
    if kind == "video":
        if key is None:
            raise ValueError(f"data.position_key: name the column of video seconds in {source}")
        times = np.arange(n_read) * frame_step / float(fps)
        return at_times(coordinates, key.to_numpy(), times, source)
    chosen = for_files(coordinates, key, frame_files, source)[::frame_step]
    if len(chosen) != n_read:
        raise ValueError(f"{source}: {len(chosen)} positions for {n_read} places")
    return chosen
