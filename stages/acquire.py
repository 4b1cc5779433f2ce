"""Stage acquire: render the built-in synthetic route, or point at the real videos / frame folders.

Writes data/acquired/sources.json (season -> what to read) and, for the synthetic route, the
videos and the renderer's true layout (tunnels, stops) beside it.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, stage_main
from seasonloop.data.sources import SOURCES, acquire_sources
from seasonloop.io import staged_dir, write_json
from seasonloop.params.settings import DataConfig, SyntheticConfig

OUT = Path("data/acquired")


@stage_main
def main() -> None:
    params = load_params("data", "synthetic")
    data, synthetic = DataConfig.from_params(params), SyntheticConfig.from_params(params)
    seasons = data_seasons(params)
    with staged_dir(OUT) as out:
        paths = acquire_sources(out, seasons, data, synthetic)
        # a rendered file is named by where it will be: the staged folder is renamed to OUT
        sources = {
            season: {
                "kind": SOURCES[data.source].kind,
                "path": str(OUT / path.relative_to(out) if path.is_relative_to(out) else path),
            }
            for season, path in paths.items()
        }
        write_json(out / "sources.json", {"source": data.source, "seasons": sources})


if __name__ == "__main__":
    main()
