"""Stage extract_frames: extract.fps frames a second from every season (every data.frame_step-th
kept: one kept frame is a place), at the storage size. Frame folders are read in natural order and
paired by file name when the seasons share names. Then the seasons' alignment is measured
(seasonloop.data.alignment): a clear non-zero offset stops the run, and data.offsets shifts a season
by a known one. frames.json records both.

data.image_list (a file in data.frames_dir) keeps the frame files it names only.

Writes data/frames/<season>.npy (N, h, w, 3) uint8 BGR, data/frames/frames.json and a preview of
the same places in every season (plots/season_preview.png). With data.ground_truth positions, also
data/frames/<season>_positions.npy: each place's position in metres (the renderer's exact ones for
the synthetic route, else <data.positions_dir>/<season>.csv); seasons that are not aligned
(ground truth positions or matrix) keep their own frames, lengths and offsets.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, param, stage_main
from seasonloop.data.extract import check_sources, copy_from_dataset, extract_seasons, preview_grid
from seasonloop.data.ground_truth_kinds import truth_kind
from seasonloop.data.positions import RENDERED, PositionFiles
from seasonloop.io import read_json, staged_dir, write_json
from seasonloop.params.settings import DataConfig, ExtractConfig
from seasonloop.plots import plot_image_grid

SOURCES = Path("data/acquired/sources.json")
OUT = Path("data/frames")
PREVIEW = Path("plots/season_preview.png")
PREVIEW_PLACES = 6


@stage_main
def main() -> None:
    params = load_params("data", "extract", "split.stop_threshold")
    seasons = data_seasons(params)
    sources = read_json(SOURCES)["seasons"]
    check_sources(sources, seasons, SOURCES)
    extract, data = ExtractConfig.from_params(params), DataConfig.from_params(params)
    kind = truth_kind(data.ground_truth)
    positions = None
    if kind.reads_positions:
        positions = (
            PositionFiles(SOURCES.parent / RENDERED.folder, RENDERED.columns, RENDERED.units, RENDERED.key)
            if data.source == "synthetic"
            else PositionFiles(
                Path(data.positions_dir),
                data.position_columns,
                data.position_units,
                data.position_key or None,
                in_names=data.position_source == "image_names",
            )
        )
    with staged_dir(OUT) as out:
        record = extract_seasons(
            sources,
            seasons,
            extract,
            int(data.frame_step),
            dict(data.offsets),
            out,
            aligned=kind.aligned,
            positions=positions,
            image_list=Path(data.frames_dir) / data.image_list if data.image_list else None,
            stop_threshold=float(param(params, "split.stop_threshold")),
        )
        record["ground_truth"] = data.ground_truth
        if kind.file_in_dataset:
            copy_from_dataset(Path(data.frames_dir) / kind.file_in_dataset, out)
        write_json(out / "frames.json", record)
        grid, row_labels = preview_grid(out, seasons, record["places_per_season"], PREVIEW_PLACES)
        plot_image_grid(
            grid, PREVIEW, row_labels=row_labels, col_labels=seasons, title="The same places in every season"
        )


if __name__ == "__main__":
    main()
