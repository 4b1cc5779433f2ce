"""Where each place of a season is, in metres: read from a CSV beside the data, or from the renderer.

A positions CSV holds one row per frame (for a frame folder: in the folder's natural order, or
keyed by a column of file names) or one row per time (for a video: a column of video seconds,
interpolated at each kept sample's time). Its coordinate columns are metres (x, y; or one
column of distance along the route) or degrees (latitude, longitude), converted to metres in the
UTM zone of the route (pyproj), the same for every season.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

UNITS = ("metres", "degrees")
LATITUDE_NAMES = ("lat", "latitude")
LONGITUDE_NAMES = ("lon", "lng", "long", "longitude")


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


def utm_zone(latitudes: np.ndarray, longitudes: np.ndarray) -> str:
    """The EPSG code of the UTM zone at the route's mean longitude (north or south by its mean
    latitude): a route of a few hundred km, as Nordland's, stays within 0.05% of true distances."""
    zone = int(np.floor((float(np.mean(longitudes)) + 180.0) / 6.0)) % 60 + 1
    return f"EPSG:{32600 + zone if float(np.mean(latitudes)) >= 0 else 32700 + zone}"


def degrees_to_metres(
    coordinates: Mapping[str, np.ndarray], columns: Sequence[str] = ("lat", "lon")
) -> dict[str, np.ndarray]:
    """season -> (n, 2) (latitude, longitude) degrees, to (north, east) metres in one UTM zone
    shared by every season (utm_zone; pyproj), so positions compare across seasons. Columns
    named as longitude first, or a first column beyond +-90 degrees, are swapped columns: an error."""
    from pyproj import Transformer  # here: only positions in degrees need it (0.3 s import)

    names = [str(name).lower() for name in columns]
    if len(names) == 2 and names[0] in LONGITUDE_NAMES and names[1] in LATITUDE_NAMES:
        raise ValueError(
            f"data.position_columns: {list(columns)} is longitude first; degrees must be [latitude, longitude]"
        )
    every = np.concatenate(list(coordinates.values()))
    if (np.abs(every[:, 0]) > 90).any() or (np.abs(every[:, 1]) > 180).any():
        raise ValueError(
            "data.position_columns: degrees must be (latitude, longitude) within +-90, +-180 "
            "(a first column beyond +-90 is a longitude: are the columns swapped?)"
        )
    to_utm = Transformer.from_crs("EPSG:4326", utm_zone(every[:, 0], every[:, 1]), always_xy=True)
    metres = {}
    for season, values in coordinates.items():
        east, north = to_utm.transform(values[:, 1], values[:, 0])
        metres[season] = np.stack([np.asarray(north, np.float64), np.asarray(east, np.float64)], axis=1)
    return metres


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
    repeated = names.astype(str).value_counts()
    if repeated.iloc[0] > 1:
        raise ValueError(
            f"{source}: image name {repeated.index[0]!r} on {int(repeated.iloc[0])} rows (one row per frame)"
        )
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
