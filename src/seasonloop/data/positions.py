"""Where each place of a season is, in metres: read from a CSV beside the data, or from the renderer.

A positions CSV holds one row per frame (for a frame folder: in the folder's natural order, or
keyed by a column of file names) or one row per time (for a video: a column of video seconds,
interpolated at each kept sample's time). Its coordinate columns are metres (x, y; or one
column of distance along the route) or degrees (latitude, longitude), converted to Earth-centred
metres (pyproj; degrees_to_metres says why not a map projection) before any interpolation.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from seasonloop.params.checks import check_degree_columns


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


def degrees_to_metres(coordinates: np.ndarray, columns: Sequence[str], source: Path | str) -> np.ndarray:
    """(n, 2) (latitude, longitude) degrees of one season to (n, 3) Earth-centred (geocentric,
    EPSG:4978) metres on the WGS84 ellipsoid, by pyproj. No projection and no zone: the straight
    line between two places is the chord under their geodesic, shorter by (d / R)^2 / 24 of it
    (under 1e-9 for d up to 1 km, R the Earth's radius), anywhere on Earth, across +-180 degrees
    and at the poles alike; every season is converted on its own and compares with every other.
    Places are on the ellipsoid (height 0)."""
    from pyproj import Transformer  # here: only positions in degrees need it (0.3 s import)

    check_degree_columns(columns)
    if (np.abs(coordinates[:, 0]) > 90).any() or (np.abs(coordinates[:, 1]) > 180).any():
        raise ValueError(
            f"{source}: degrees must be (latitude, longitude) within +-90, +-180 "
            "(a first column beyond +-90 is a longitude: are the columns swapped?)"
        )
    to_geocentric = Transformer.from_crs("EPSG:4326", "EPSG:4978", always_xy=True)
    x, y, z = to_geocentric.transform(coordinates[:, 1], coordinates[:, 0], np.zeros(len(coordinates)))
    return np.stack([np.asarray(axis, np.float64) for axis in (x, y, z)], axis=1)


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


def positions_in_names(files: Sequence[Path]) -> np.ndarray:
    """(n, 2) (east, north) UTM metres read from image names as gmberton's VPR datasets write them,
    `@<utm_east>@<utm_north>@...@.jpg`; a name without them is one line naming the file."""
    coordinates = np.empty((len(files), 2))
    for i, file in enumerate(files):
        fields = Path(file).name.split("@")
        try:
            coordinates[i] = float(fields[1]), float(fields[2])
        except (IndexError, ValueError):
            raise ValueError(
                f"{file}: no UTM position in its name (data.position_source: image_names expects "
                "'@<utm_east>@<utm_north>@...')"
            ) from None
    if not np.isfinite(coordinates).all():
        raise ValueError(f"{Path(files[0]).parent}: a UTM position in an image name is not finite")
    return coordinates


@dataclass(frozen=True)
class PositionFiles:
    """Where the seasons' positions are: <folder>/<season>.csv, its coordinate columns and units,
    and its key column (videos: seconds; frames: file names, or None for rows in frame order); or,
    in_names, each frame file's own name (positions_in_names)."""

    folder: Path
    columns: tuple[str, ...]
    units: str
    key: str | None
    in_names: bool = False

    def file(self, season: str) -> Path:
        return Path(self.folder) / f"{season}.csv"


# what the built-in renderer writes beside its videos (seasonloop.data.synthetic.video)
RENDERED = PositionFiles(Path("positions"), ("distance_m",), "metres", "time_s")


def season_positions(
    kind: str, files: PositionFiles, season: str, n_read: int, fps: float, frame_step: int, frame_files: list[Path]
) -> np.ndarray:
    """(n_read, k) metres of the `n_read` places read of one season (before offsets): a video's at
    each kept sample's time, a folder's per kept file (degrees: geocentric, k = 3)."""
    if files.in_names:
        if kind != "frames":
            raise ValueError("data.position_source: image_names needs data.source: frames")
        chosen = positions_in_names(frame_files)[::frame_step]
        if len(chosen) != n_read:
            raise ValueError(f"{Path(frame_files[0]).parent}: {len(chosen)} positions for {n_read} places")
        return chosen
    source = files.file(season)
    coordinates, key = read_table(source, files.columns, files.key)
    if files.units == "degrees":  # to metres before interpolating: degrees jump at +-180
        coordinates = degrees_to_metres(coordinates, files.columns, source)
    if kind == "video":
        if key is None:
            raise ValueError(f"data.position_key: name the column of video seconds in {source}")
        times = np.arange(n_read) * frame_step / float(fps)
        return at_times(coordinates, key.to_numpy(), times, source)
    chosen = for_files(coordinates, key, frame_files, source)[::frame_step]
    if len(chosen) != n_read:
        raise ValueError(f"{source}: {len(chosen)} positions for {n_read} places")
    return chosen
