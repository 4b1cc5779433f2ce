"""End to end: the recipes of docs/other-datasets.md for data that is not Nordland-aligned, as a new
user runs them.

Each test makes its own small data: the synthetic route ridden at a different speed in each season
(so frame i of one season is not frame i of another), written as frame folders with a positions
CSV, a ground-truth matrix, or descriptors computed "elsewhere"; then the recipes' `dvc exp run -S
...` settings, in a fresh copy of the repository (written into params.yaml and reproduced:
workspaces.repro_with).
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

from seasonloop.data.frames import sample_video
from seasonloop.data.synthetic import SeasonRide, render_route
from tools.repository import git
from tools.small_runs import DATA_PATH, TINY
from workspaces import make_workspace, repro_with

SECONDS = 240  # of the reference ride
SEASONS = ["summer", "fall", "winter"]
# fall runs faster and starts 15 s down the line; winter runs slower, stands twice as long and swings
RIDES = {"fall": SeasonRide(speed=1.25, start_s=15.0), "winter": SeasonRide(speed=0.8, stop_scale=2.0, swing=0.2)}
# the sequence matcher must search the speeds the seasons differ by (places per query step)
SEQUENCE = ["sequence.v_min=1.0", "sequence.v_max=1.6", "sequence.v_steps=7"]
BASE = {**DATA_PATH, "data": {"seasons": SEASONS}, "train": {"seasons": SEASONS}}


def write_rides(folder: Path) -> dict[str, np.ndarray]:
    """Frame folders <folder>/<season>/1.png ... (1 fps) of the seasons ridden at their own speeds;
    season -> each frame's distance along the route (m), from the renderer."""
    videos = folder / "videos"
    render_route(videos, SEASONS, SECONDS, 1, 128, 72, seed=3, progress=False, rides=RIDES)
    distances = {}
    for season in SEASONS:
        (folder / season).mkdir(parents=True)
        frames = sample_video(videos / f"{season}.mp4", 1, 72, 128, progress=False)
        for i, frame in enumerate(frames):
            cv2.imwrite(str(folder / season / f"{i + 1}.png"), frame)
        distances[season] = pd.read_csv(videos / "positions" / f"{season}.csv")["distance_m"].to_numpy()[: len(frames)]
    return distances


def stage(root: Path, script: str, *args: str) -> subprocess.CompletedProcess:
    """One stage's script run by hand, as DVC runs it."""
    return subprocess.run([sys.executable, f"stages/{script}", *args], cwd=root, capture_output=True, text=True)


def fraction_correct(root: Path, learner: str, pair: str) -> float:
    return json.loads((root / f"metrics/eval/{learner}/{pair}.json").read_text())["fraction_correct"]


@pytest.mark.e2e
def test_the_synthetic_route_ridden_at_different_speeds_with_positions(tmp_path):
    root = make_workspace(tmp_path / "repo", {**BASE, "synthetic": {**TINY["synthetic"], "seconds": SECONDS}})
    rides = "++synthetic.rides={fall: {speed: 1.25, start_s: 15}, winter: {speed: 0.8, stop_scale: 2, swing: 0.2}}"
    # up to the evaluation: the report of positions on rides like these is read in the test below
    result = repro_with(
        root,
        rides,
        "data.ground_truth=positions",
        "evaluate.tolerance_m=15",
        *SEQUENCE,
        targets=("evaluate@raw_patchnorm",),
    )
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    dataset = json.loads((root / "metrics/dataset.json").read_text())
    frames = {season: dataset["seasons"][season]["frames"] for season in SEASONS}
    assert dataset["ground_truth"] == "positions" and len(set(frames.values())) == 3, frames
    truth = json.loads((root / "metrics/ground_truth.json").read_text())
    assert truth["kind"] == "positions" and "15 m" in truth["correct"]
    # not aligned: frame i of one season is not frame i of another, yet the learners find the
    # places far above chance (a random match is correct for correct places / database places)
    for pair in ("summer-fall", "winter-summer", "winter-fall"):
        chance = truth["pairs"][pair]["mean_correct_per_query"] / truth["pairs"][pair]["n_database"]
        assert fraction_correct(root, "raw_patchnorm", pair) > 3 * chance, (pair, chance)
    # and sequences over the speeds searched lift the pair with signal (summer-fall: 0.50 -> 0.82
    # when written; its winter pairs, 34-59 queries each, did not gain: winter-summer 0.19 -> 0.12)
    assert fraction_correct(root, "raw_patchnorm", "summer-fall+seq") > fraction_correct(
        root, "raw_patchnorm", "summer-fall"
    )


@pytest.mark.e2e
def test_frames_with_positions_precomputed_descriptors_or_a_ground_truth_matrix(tmp_path):
    # one set of frames and one workspace for both kinds of truth (rendering and DVC's start-up are
    # much of what each costs): positions from a csv with descriptors computed elsewhere, then a matrix
    data = tmp_path / "route"  # outside the repository, given by absolute path as the README says
    distances = write_rides(data)
    root = make_workspace(tmp_path / "repo", BASE)
    positions_csv_and_precomputed_descriptors(root, data, distances)
    a_ground_truth_matrix(root, data, distances)


def positions_csv_and_precomputed_descriptors(root: Path, data: Path, distances: dict[str, np.ndarray]) -> None:
    for season, metres in distances.items():
        # latitude/longitude along a meridian, keyed by file name, rows shuffled
        table = pd.DataFrame(
            {"image": [f"{i + 1}.png" for i in range(len(metres))], "lat": 63.0 + metres / 111_195.0, "lon": 10.0}
        )
        (data / "positions").mkdir(exist_ok=True)
        table.sample(frac=1.0, random_state=0).to_csv(data / "positions" / f"{season}.csv", index=False)
        # "descriptors computed elsewhere": a small grey thumbnail of every frame, in frame order
        images = [cv2.imread(str(data / season / f"{i + 1}.png"), cv2.IMREAD_GRAYSCALE) for i in range(len(metres))]
        (data / "descriptors").mkdir(exist_ok=True)
        np.save(data / "descriptors" / f"{season}.npy", np.stack([cv2.resize(im, (16, 8)).ravel() for im in images]))
    result = repro_with(
        root,
        "data.source=frames",
        f"data.frames_dir={data}",
        "data.ground_truth=positions",
        f"data.positions_dir={data / 'positions'}",
        "data.position_columns=[lat,lon]",
        "data.position_units=degrees",
        "data.position_key=image",
        "evaluate.tolerance_m=15",
        "learners=[raw_patchnorm,precomputed]",
        f"precomputed.dir={data / 'descriptors'}",
        *SEQUENCE,
    )
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "each season its own frames" in result.stdout
    summary = json.loads((root / "metrics/summary.json").read_text())
    assert {"precomputed", "precomputed+seq"} <= set(summary["fraction_correct"])
    assert fraction_correct(root, "precomputed", "summer-fall") > 0.2
    assert "precomputed" in (root / "plots/summary/fraction_correct.csv").read_text()
    report = (root / "plots/report.html").read_text()
    assert "precomputed" in report and "Ground truth (positions)" in report
    # descriptors that do not match the frames: one line naming the season and the counts
    kept = (root / "data/features/precomputed/fall.npy").read_bytes()
    np.save(data / "descriptors" / "fall.npy", np.zeros((5, 128)))
    result = stage(root, "features.py", "precomputed")
    assert result.returncode == 1 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "fall.npy: 5 rows of descriptors for the" in result.stderr and "frames of season 'fall'" in result.stderr
    assert (root / "data/features/precomputed/fall.npy").read_bytes() == kept


def a_ground_truth_matrix(root: Path, data: Path, distances: dict[str, np.ndarray]) -> None:
    assert git(root, "checkout", "params.yaml").returncode == 0  # the committed params, not the run's above
    (data / "truth").mkdir()
    for database in SEASONS:
        for query in SEASONS:
            if database != query:
                gap = np.abs(distances[database][:, None] - distances[query][None, :])
                np.savez(data / "truth" / f"{database}-{query}.npz", hard=gap <= 15, soft=gap <= 40)
    settings = ["data.source=frames", f"data.frames_dir={data}", "data.ground_truth=matrix"]
    # up to the evaluation: the report of this workspace's data was read above
    result = repro_with(root, *settings, f"data.ground_truth_dir={data / 'truth'}", targets=("evaluate@raw_patchnorm",))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert json.loads((root / "metrics/ground_truth.json").read_text())["kind"] == "matrix"
    assert fraction_correct(root, "raw_patchnorm", "summer-fall") > 0.3
    # a matrix of the wrong shape: one line naming the file and both shapes, nothing half-written
    kept = (root / "data/split/split.json").read_bytes()
    np.savez(data / "truth" / "summer-fall.npz", hard=np.zeros((3, 3), bool))
    result = stage(root, "split.py")
    assert result.returncode == 1 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "summer-fall.npz: 'hard' has shape (3, 3), expected (database places, query places)" in result.stderr
    assert (root / "data/split/split.json").read_bytes() == kept
