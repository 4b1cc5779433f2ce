"""Stage acquire: render the built-in synthetic route, or point at the real videos / frame folders.

Writes data/acquired/sources.json (season -> what to read) and, for the synthetic route, the
videos and the renderer's true layout (tunnels, stops) beside it.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, param, stage_main

from seasonloop.data.sources import SOURCES, real_sources
from seasonloop.data.synthetic import RouteDifficulty, render_route
from seasonloop.io import staged_dir, write_json
from seasonloop.settings import DataConfig, SyntheticConfig

OUT = Path("data/acquired")


@stage_main
def main() -> None:
    params = load_params("data", "synthetic")
    source = param(params, "data.source")
    seasons = data_seasons(params)
    with staged_dir(OUT) as out:
        if source == "synthetic":
            syn = SyntheticConfig.from_params(params)
            # the difficulty knobs are keys of the synthetic section with RouteDifficulty's field names
            difficulty = RouteDifficulty(**{knob: getattr(syn, knob) for knob in RouteDifficulty.knobs()})
            render_route(out, seasons, syn.seconds, syn.fps, syn.width, syn.height, syn.seed, difficulty=difficulty)
            # paths relative to the repository root: the staged folder is renamed to OUT
            sources = {season: {"kind": "video", "path": str(OUT / f"{season}.mp4")} for season in seasons}
        else:
            paths = real_sources(source, seasons, DataConfig.from_params(params))
            sources = {season: {"kind": SOURCES[source].kind, "path": str(path)} for season, path in paths.items()}
        write_json(out / "sources.json", {"source": source, "seasons": sources})


if __name__ == "__main__":
    main()
