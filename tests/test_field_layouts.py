"""End to end: the field's dataset layouts and ground-truth formats as docs/other-datasets.md's
recipes read them, on data the tests make from the synthetic route:

- VPR-Bench: `ref/` and `query/` folders of integer-named images and `ground_truth_new.npy`
  (rows [query index, array of correct reference indices]);
- gmberton's VPR datasets: `database/` and `queries/` folders, each image's UTM position in its
  name (`@<utm_east>@<utm_north>@...@.jpg`), correct within 25 m.
"""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pandas as pd
import pytest

from seasonloop.data.frames import sample_video
from seasonloop.data.synthetic import SeasonRide, render_route
from tools.repository import dvc
from tools.small_runs import DATA_PATH
from workspaces import make_workspace

SECONDS = 240


def rendered(folder: Path, seasons: list[str], rides: dict | None = None) -> dict[str, tuple[list, np.ndarray]]:
    """season -> (its frames at 1 fps, each frame's distance along the route in metres)."""
    render_route(folder, seasons, SECONDS, 1, 128, 72, seed=3, progress=False, rides=rides or {})
    return {
        season: (
            frames := list(sample_video(folder / f"{season}.mp4", 1, 72, 128, progress=False)),
            pd.read_csv(folder / "positions" / f"{season}.csv")["distance_m"].to_numpy()[: len(frames)],
        )
        for season in seasons
    }


def layout_params(traverses: list[str]) -> dict:
    pair = [traverses[0], traverses[1]]
    return {
        **DATA_PATH,
        "data": {"seasons": traverses},
        "train": {"seasons": traverses},
        "evaluate": {"pairs": [pair]},
        "ablation": {**DATA_PATH["ablation"], "pair": pair, "training_seasons": [[traverses[0]]]},
        "report": {"example_pair": pair},
        "cae_widths": {**DATA_PATH["cae_widths"], "pairs": [pair]},
    }


def run_layout(tmp_path: Path, traverses: list[str], data: Path, *settings: str) -> tuple[Path, dict]:
    """`dvc exp run` of the frames in data/<traverse>/ with `settings` in a new workspace; (its
    root, metrics/ground_truth.json)."""
    root = make_workspace(tmp_path / "repo", layout_params(traverses))
    result = dvc(root, "exp", "run", "-S", "data.source=frames", "-S", f"data.frames_dir={data}", *settings)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return root, json.loads((root / "metrics/ground_truth.json").read_text())


def summary_fraction(root: Path, pair: str) -> float:
    return json.loads((root / "metrics/summary.json").read_text())["fraction_correct"]["raw_patchnorm"][pair]


@pytest.mark.e2e
def test_a_vpr_bench_dataset_runs_from_its_own_layout(tmp_path):
    # ref: every winter frame; query: every 2nd summer frame; query i is correct at references
    # 2i-1 .. 2i+1, as VPR-Bench's Nordland writes +-1 frame (there every 10th frame is a query)
    data = tmp_path / "Nordland"
    seasons = rendered(tmp_path / "videos", ["winter", "summer"])
    for name, frames in (("ref", seasons["winter"][0]), ("query", seasons["summer"][0][::2])):
        (data / name).mkdir(parents=True)
        for i, frame in enumerate(frames):
            cv2.imwrite(str(data / name / f"{i:07d}.jpg"), frame)
    n_ref, n_query = len(seasons["winter"][0]), len(seasons["summer"][0][::2])
    rows = np.empty((n_query, 2), dtype=object)
    for i in range(n_query):
        rows[i] = i, np.arange(max(0, 2 * i - 1), min(n_ref, 2 * i + 2))
    np.save(data / "ground_truth_new.npy", rows, allow_pickle=True)
    root, truth = run_layout(
        tmp_path,
        ["ref", "query"],
        data,
        *("-S", "data.ground_truth=vpr_bench", "-S", f"data.ground_truth_dir={data}"),
        *("-S", "sequence.v_min=1.5", "-S", "sequence.v_max=2.5", "-S", "sequence.v_steps=3"),
    )
    assert truth["kind"] == "vpr_bench" and "VPR-Bench" in truth["correct"]
    pair = truth["pairs"]["ref-query"]
    assert pair["n_without_match"] == 0 and 2.0 <= pair["mean_correct_per_query"] <= 3.0
    chance = pair["mean_correct_per_query"] / pair["n_database"]
    assert summary_fraction(root, "ref-query") > 3 * chance
    assert "ref-query" in (root / "plots/report.html").read_text()


@pytest.mark.e2e
def test_a_gmberton_dataset_runs_with_utm_positions_in_its_image_names(tmp_path):
    # database: summer; queries: fall ridden 1.25x faster from 15 s down the line; fake UTM (east
    # along the route, north constant) in the names, as gmberton's Nordland writes them
    data = tmp_path / "nordland" / "images" / "test"
    seasons = rendered(tmp_path / "videos", ["summer", "fall"], {"fall": SeasonRide(speed=1.25, start_s=15.0)})
    for name, season in (("database", "summer"), ("queries", "fall")):
        (data / name).mkdir(parents=True)
        frames, metres = seasons[season]
        for frame, east in zip(frames, metres):
            cv2.imwrite(str(data / name / f"@{500000 + east:.2f}@7000000.00@33@W@{name}.jpg"), frame)
    root, truth = run_layout(
        tmp_path,
        ["database", "queries"],
        data,
        *("-S", "data.ground_truth=positions", "-S", "data.position_source=image_names"),
        *("-S", "evaluate.tolerance_m=25"),
        *("-S", "sequence.v_min=1.0", "-S", "sequence.v_max=1.6", "-S", "sequence.v_steps=7"),
    )
    assert truth["kind"] == "positions" and "25 m" in truth["correct"]
    pair = truth["pairs"]["database-queries"]
    chance = pair["mean_correct_per_query"] / pair["n_database"]
    assert summary_fraction(root, "database-queries") > 3 * chance
    positions = np.load(root / "data/frames/queries_positions.npy")
    assert positions[:, 0].min() >= 500000 and (positions[:, 1] == 7000000).all()
