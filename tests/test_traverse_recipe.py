"""End to end with traverses named as the field's datasets name them (Gardens Point's day_left,
day_right, night_right, and a RobotCar-like date with hyphens), through the report."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import pytest

from seasonloop.data.frames import sample_video
from seasonloop.data.synthetic import render_route
from tools.repository import dvc
from tools.small_runs import DATA_PATH
from workspaces import make_workspace

SECONDS = 240
DATE = "2014-12-09-13-21-02"
# the synthetic route's seasons, rendered, then stored under the names a dataset would use
NAMES = {"summer": "day_left", "fall": "day_right", "winter": "night_right", "spring": DATE}


def write_traverses(folder: Path) -> None:
    videos = folder / "videos"
    render_route(videos, list(NAMES), SECONDS, 1, 128, 72, seed=3, progress=False)
    for season, name in NAMES.items():
        (folder / name).mkdir(parents=True)
        for i, frame in enumerate(sample_video(videos / f"{season}.mp4", 1, 72, 128, progress=False)):
            cv2.imwrite(str(folder / name / f"{i + 1}.png"), frame)


@pytest.mark.e2e
def test_traverses_named_like_gardens_point_and_a_date_run_through_the_report(tmp_path):
    frames = tmp_path / "dataset"
    write_traverses(frames)
    names = list(NAMES.values())
    date_pair = f"day_right-{DATE}"  # one string: split where both halves are traverses
    overrides = {
        **DATA_PATH,
        "data": {"source": "frames", "frames_dir": str(frames), "seasons": names},
        "train": {"seasons": ["day_left", "day_right"]},
        "evaluate": {"pairs": [["day_left", "night_right"], date_pair]},
        "ablation": {
            **DATA_PATH["ablation"],
            "pair": ["day_left", "night_right"],
            "training_seasons": [["day_left"], ["day_left", "day_right"]],
        },
        "report": {"example_pair": ["day_left", "night_right"]},
        "cae_widths": {**DATA_PATH["cae_widths"], "pairs": [["day_left", "night_right"]]},
    }
    root = make_workspace(tmp_path / "repo", overrides)
    result = dvc(root, "repro")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    pairs = {"day_left-night_right", date_pair}
    evaluated = {path.stem for path in (root / "metrics/eval/raw_patchnorm").glob("*.json")}
    assert pairs <= evaluated and all(name.split("@")[0].split("+")[0] in pairs for name in evaluated)
    assert set(json.loads((root / "metrics/summary.json").read_text())["fraction_correct"]["raw_patchnorm"]) == pairs
    assert set(json.loads((root / "metrics/dataset.json").read_text())["seasons"]) == set(names)
    ablation = json.loads((root / "metrics/training_seasons.json").read_text())
    assert ablation["pair"] == "day_left-night_right" and ablation["season_sets"] == ["day_left", "day_left+day_right"]
    report = (root / "plots/report.html").read_text()
    for name in [*names, date_pair]:
        assert name in report, name
