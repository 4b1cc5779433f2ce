"""End to end: the field's dataset layouts and ground-truth formats as docs/other-datasets.md's
recipes read them, on data the tests make from the synthetic route:

- VPR-Bench: `ref/` and `query/` folders of integer-named images and `ground_truth_new.npy`
  (rows [query index, array of correct reference indices]);
- gmberton's VPR datasets: `database/` and `queries/` folders, each image's UTM position in its
  name (`@<utm_east>@<utm_north>@...@.jpg`), correct within 25 m.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pandas as pd
import pytest

from seasonloop.data.frames import list_frame_files, sample_video
from seasonloop.data.synthetic import SeasonRide, render_route
from seasonloop.models.core.lookup import get_learner
from tools.repository import learner_params
from tools.small_runs import DATA_PATH
from workspaces import make_workspace, repro_with

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


def preset_run(tmp_path: Path, preset: str, data: Path, *settings: str, targets: tuple[str, ...] = ()) -> Path:
    """The layout's documented commands in a new workspace: `python -m seasonloop.preset <preset>`,
    then `dvc exp run -S data.frames_dir=<data>` (and `settings`; as repro_with runs it, up to
    `targets` when given); the workspace's root."""
    root = make_workspace(tmp_path / "repo", DATA_PATH)
    applied = subprocess.run(
        [sys.executable, "-m", "seasonloop.preset", preset], cwd=root, capture_output=True, text=True
    )
    assert applied.returncode == 0, applied.stderr
    result = repro_with(root, f"data.frames_dir={data}", *settings, targets=targets)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return root


def recalls(root: Path, database: str, query: str, correct: np.ndarray) -> dict[str, float]:
    """R@1/5/10 of the patch-normalised image computed here, from the pipeline's preprocessed test
    images and the hard truth `correct` (database images, queries), as VPR_Tutorial's recallAtK:
    queries without a correct reference are left out."""

    def described(traverse: str) -> np.ndarray:
        images = np.load(root / f"data/split/{traverse}_test.npy").astype(np.float32) / np.float32(255)
        n, height, width = images.shape
        patches = images.reshape(n, height // 8, 8, width // 8, 8)
        centred = patches - patches.mean(axis=(2, 4), keepdims=True)
        scale = np.maximum(patches.std(axis=(2, 4), keepdims=True), np.float32(1e-6))
        flat = (centred / scale).reshape(n, -1).astype(np.float64)
        return flat / np.linalg.norm(flat, axis=1, keepdims=True)

    similarity = described(query) @ described(database).T  # cosine: the nearest is the most similar
    ranked = np.argsort(-similarity, axis=1, kind="stable")
    matchable = correct.any(axis=0)
    return {
        f"recall_at_{n}": float(np.mean([correct[ranked[q, :n], q].any() for q in np.flatnonzero(matchable)]))
        for n in (1, 5, 10)
    }


def evaluation(root: Path, learner: str, pair: str) -> dict:
    return json.loads((root / f"metrics/eval/{learner}/{pair}.json").read_text())


@pytest.mark.e2e
def test_a_vpr_bench_dataset_runs_with_one_command_on_every_query(tmp_path):
    # ref: every winter frame; query: every 2nd summer frame, query i at reference 2i; its correct
    # references irregular, as the field's files are: 1 or 3, and none at all for one query (no row)
    data = tmp_path / "Nordland"
    seasons = rendered(tmp_path / "videos", ["winter", "summer"])
    for name, frames in (("ref", seasons["winter"][0]), ("query", seasons["summer"][0][::2])):
        (data / name).mkdir(parents=True)
        for i, frame in enumerate(frames):
            cv2.imwrite(str(data / name / f"{i:07d}.jpg"), frame)
    n_ref, n_query = len(seasons["winter"][0]), len(seasons["summer"][0][::2])
    without = 7
    listed = [i for i in range(n_query) if i != without]
    rows = np.empty((len(listed), 2), dtype=object)
    correct = np.zeros((n_ref, n_query), dtype=bool)
    for row, i in enumerate(listed):
        references = [2 * i] if i % 2 else [2 * i - 1, 2 * i, 2 * i + 1]
        references = [r for r in references if 0 <= r < n_ref]
        rows[row] = i, np.array(references)
        correct[references, i] = True
    np.save(data / "ground_truth_new.npy", rows, allow_pickle=True)

    # (a) the training-free descriptor on every query, R@1/5/10 as VPR-Bench reads them
    root = preset_run(tmp_path, "vpr_bench", data)
    truth = json.loads((root / "metrics/ground_truth.json").read_text())
    assert truth["kind"] == "vpr_bench" and truth["pairs"]["ref-query"]["n_queries"] == n_query
    assert truth["pairs"]["ref-query"]["n_without_match"] == 1
    found = evaluation(root, "raw_patchnorm", "ref-query")
    assert found["n_queries"] == n_query and found["n_database"] == n_ref
    assert {key: found[key] for key in ("recall_at_1", "recall_at_5", "recall_at_10")} == recalls(
        root, "ref", "query", correct
    )
    fit = json.loads((root / "metrics/fit/raw_patchnorm.json").read_text())
    assert fit["trained_on"] == "nothing (training-free)"
    report = (root / "plots/report.html").read_text()
    assert "nothing (training-free)" in report
    assert "it compares training sets" in report and "The CAE width sweep was skipped" in report

    # (b) a learner that learns, trained on the reference traverse only: the queries never seen
    # (up to its evaluation: (c) runs the stages after it)
    result = repro_with(root, "learners=[raw_patchnorm,pca]", targets=("evaluate@pca",))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    fit = json.loads((root / "metrics/fit/pca.json").read_text())
    assert fit["train_seasons"] == ["ref"] and fit["trained_on"].startswith("every place of ref")
    assert evaluation(root, "pca", "ref-query")["n_queries"] == n_query
    # (training on the query traverse is refused: tests/test_protocols.py)

    # (c) fitted elsewhere, as published learners are: learners another run fitted (here on other
    # images of the same size, noise) applied unchanged, nothing fitted on this dataset (up to the
    # evaluation: (a) ran this layout through the report, and the report's "trained on" column of a
    # learner fitted elsewhere is tests/test_report_assembly.py's)
    elsewhere = tmp_path / "fitted_elsewhere"
    images = np.random.default_rng(0).integers(0, 256, (64, 32, 64), dtype=np.uint8)
    for name, params in (("raw_patchnorm", {}), ("pca", {"n_discard": 2, "n_keep": 8})):
        learner = get_learner(name)(learner_params(name, params), seed=0)
        learner.fit(images, progress=False)
        learner.save(elsewhere / name)
    settings = ("train.fitted=elsewhere", f"train.models_dir={elsewhere}", f"data.frames_dir={data}")
    result = repro_with(root, *settings, targets=("evaluate@pca",))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    fit = json.loads((root / "metrics/fit/pca.json").read_text())
    assert fit["trained_on"].startswith("elsewhere: ") and fit["n_train_images"] is None
    assert evaluation(root, "pca", "ref-query")["n_queries"] == n_query


@pytest.mark.e2e
def test_a_gmberton_dataset_runs_with_one_command_on_every_query(tmp_path):
    # database: summer; queries: fall ridden 1.25x faster from 15 s down the line; fake UTM (east
    # along the route, north constant) in the names, as gmberton's Nordland writes them
    data = tmp_path / "nordland" / "images" / "test"
    seasons = rendered(tmp_path / "videos", ["summer", "fall"], {"fall": SeasonRide(speed=1.25, start_s=15.0)})
    for name, season in (("database", "summer"), ("queries", "fall")):
        (data / name).mkdir(parents=True)
        frames, metres = seasons[season]
        for frame, east in zip(frames, metres):
            cv2.imwrite(str(data / name / f"@{500000 + east:.2f}@7000000.00@33@W@{name}.jpg"), frame)
    # up to the evaluation: nothing below reads the stages after it (the VPR-Bench test runs its
    # layout through the report)
    root = preset_run(tmp_path, "gmberton", data, targets=("evaluate@raw_patchnorm",))
    truth = json.loads((root / "metrics/ground_truth.json").read_text())
    assert truth["kind"] == "positions" and "25 m" in truth["correct"]
    positions = np.load(root / "data/frames/queries_positions.npy")
    assert positions[:, 0].min() >= 500000 and (positions[:, 1] == 7000000).all()
    # each image's east as its name gives it, in the order the folder's images are read (a train
    # standing writes one name twice: one image)
    database_metres, query_metres = (
        np.array([float(path.name.split("@")[1]) for path in list_frame_files(data / name)])
        for name in ("database", "queries")
    )
    correct = np.abs(database_metres[:, None] - query_metres[None, :]) <= 25
    found = evaluation(root, "raw_patchnorm", "database-queries")
    assert found["n_queries"] == len(query_metres) and found["n_database"] == len(database_metres)
    assert {key: found[key] for key in ("recall_at_1", "recall_at_5", "recall_at_10")} == recalls(
        root, "database", "queries", correct
    )
