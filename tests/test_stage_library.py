"""The library halves of the extract_frames and evaluate stages, on tiny inputs."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pandas as pd
import pytest
from sequence_settings import sequence_config

from seasonloop.data.extract import check_sources, extract_seasons, preview_grid
from seasonloop.data.ground_truth import aligned_truth
from seasonloop.evaluation.learner_evaluation import evaluate_learner
from seasonloop.params.settings import EvaluateConfig, ExtractConfig, StatisticsConfig

EXTRACT = ExtractConfig(fps=1.0, height=6, width=8, trim_to_shortest=False, max_offset=0)


def frame_folder(folder: Path, n: int, offset: int = 0) -> None:
    folder.mkdir(parents=True)
    rng = np.random.default_rng(0)
    levels = rng.integers(0, 255, size=(n + offset, 12, 16, 3), dtype=np.uint8)
    for i in range(n):
        cv2.imwrite(str(folder / f"{i}.png"), levels[i + offset])


def sources_of(root: Path, seasons) -> dict:
    return {season: {"kind": "frames", "path": str(root / season)} for season in seasons}


def test_extract_seasons_writes_every_season_and_its_record(tmp_path):
    for season in ("summer", "fall"):
        frame_folder(tmp_path / "in" / season, 7)
    out = tmp_path / "out"
    out.mkdir()
    record = extract_seasons(sources_of(tmp_path / "in", ["summer", "fall"]), ["summer", "fall"], EXTRACT, 2, {}, out)
    assert list(record) == [
        "n_places",
        "places_per_season",
        "seasons",
        "frames_per_season",
        "source_frames",
        "frame_step",
        "pairing",
        "alignment",
        "offsets",
        "place",
    ]
    assert record["n_places"] == 4 and record["frames_per_season"] == {"summer": 4, "fall": 4}
    frames = np.load(out / "summer.npy")
    assert frames.shape == (4, 6, 8, 3) and frames.dtype == np.uint8
    json.dumps(record)  # JSON-ready
    grid, labels = preview_grid(out, ["summer", "fall"], record["places_per_season"], 2)
    assert len(grid) == 2 and len(grid[0]) == 2 and labels == ["place 1", "place 2"]
    # BGR on disk, RGB in the preview
    assert np.array_equal(grid[0][0], frames[1][..., ::-1])


def test_extract_seasons_drops_known_offsets_and_rejects_mismatched_lengths(tmp_path):
    frame_folder(tmp_path / "in" / "summer", 6)
    frame_folder(tmp_path / "in" / "fall", 6)
    out = tmp_path / "out"
    out.mkdir()
    record = extract_seasons(
        sources_of(tmp_path / "in", ["summer", "fall"]), ["summer", "fall"], EXTRACT, 1, {"fall": 2}, out
    )
    assert record["n_places"] == 4 and np.load(out / "summer.npy").shape[0] == 4
    frame_folder(tmp_path / "short" / "summer", 6)
    frame_folder(tmp_path / "short" / "fall", 5)
    # the folders share names, so a missing one is named before the lengths are compared
    with pytest.raises(ValueError, match=r"5.png: no frame of that name in fall"):
        extract_seasons(sources_of(tmp_path / "short", ["summer", "fall"]), ["summer", "fall"], EXTRACT, 1, {}, out)


def test_check_sources_names_a_season_that_was_not_acquired():
    with pytest.raises(ValueError, match=r"data.seasons: winter not in sources.json"):
        check_sources({"summer": {}}, ["summer", "winter"], Path("sources.json"))


def test_evaluate_learner_writes_every_pair_metric_and_matcher(tmp_path):
    rng = np.random.default_rng(1)
    features = tmp_path / "features"
    features.mkdir()
    base = rng.normal(size=(15, 5)).astype(np.float32)
    for i, season in enumerate(("summer", "fall")):
        np.save(features / f"{season}.npy", base + 0.01 * i * rng.normal(size=base.shape).astype(np.float32))
    evaluate = EvaluateConfig(
        pairs=("summer-fall",),
        metric="cosine",
        extra_metrics=("cityblock",),
        confidence="distance",
        ratio_exclusion=2,
        tolerance_frames=0,
        tolerance_m=10.0,
        matchers=("single", "sequence"),
    )
    sequence = sequence_config()
    statistics = StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05)
    dirs = [tmp_path / name for name in ("metrics", "pr", "similarity", "outcomes")]
    for folder in dirs:
        folder.mkdir()
    truths = tmp_path / "truths"
    truths.mkdir()
    aligned_truth(np.arange(15), np.arange(15), 0).save(truths / "summer-fall.npz")
    evaluate_learner([features], [("summer", "fall")], [truths], evaluate, sequence, statistics, dirs)
    names = ["summer-fall", "summer-fall+seq", "summer-fall@cityblock", "summer-fall@cityblock+seq"]
    assert sorted(p.stem for p in dirs[0].iterdir()) == sorted(names)
    assert sorted(p.stem for p in dirs[1].iterdir()) == sorted(names)
    assert sorted(p.stem for p in dirs[2].iterdir()) == sorted(names)
    assert sorted(p.stem for p in dirs[3].iterdir()) == sorted(names)
    metrics = json.loads((dirs[0] / "summer-fall.json").read_text())
    assert metrics["fraction_correct"] == 1.0
    # 15 queries: too few for an interval along the route (it says so), Wilson's beside it
    assert metrics["intervals"]["fraction_correct"]["route"]["low"] is None
    assert "not enough queries" in metrics["intervals"]["fraction_correct"]["route"]["reason"]
    assert metrics["intervals"]["recall_at_1"]["wilson"]["high"] == 1.0
    outcomes = pd.read_csv(dirs[3] / "summer-fall+seq.csv")
    assert list(outcomes["query_place"]) == list(range(15))
    assert outcomes["correct"].mean() == json.loads((dirs[0] / "summer-fall+seq.json").read_text())["fraction_correct"]
    thumbnail = np.load(dirs[2] / "summer-fall.npy")
    assert thumbnail.shape == (15, 15) and thumbnail.dtype == np.float16
    assert (np.diagonal(thumbnail) == np.nanmax(thumbnail, axis=1)).all()  # the matches are the most similar
    with pytest.raises(ValueError, match="evaluate.pairs: no pair"):
        evaluate_learner([features], [], [truths], evaluate, sequence, statistics, dirs)
    # descriptors that do not match the test places: one line naming the file
    np.save(features / "fall.npy", base[:14])
    with pytest.raises(ValueError, match=r"fall.npy: 14 descriptors for the 15 test places of fall"):
        evaluate_learner([features], [("summer", "fall")], [truths], evaluate, sequence, statistics, dirs)
