"""End to end on a folder of real-like frames: the README's two-season recipe through the report,
then the same data read by a queued experiment (one workspace and one set of frames for both: the
queue's own start-up is most of what the second part costs)."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import pytest

from seasonloop.data.frames import sample_video
from seasonloop.data.synthetic import render_route
from tools.repository import dvc, start_queue
from tools.small_runs import DATA_PATH
from workspaces import make_workspace, repro_with, wait_for_the_queue

SECONDS = 240  # places per season


def write_frame_folders(folder: Path) -> None:
    """Two seasons of PNGs named 1.png ... 240.png (not zero-padded), as Nordland releases name them."""
    videos = folder / "videos"
    render_route(videos, ["summer", "winter"], SECONDS, 1, 128, 72, seed=3, progress=False)
    for season in ("summer", "winter"):
        (folder / season).mkdir(parents=True)
        for i, frame in enumerate(sample_video(videos / f"{season}.mp4", 1, 72, 128, progress=False)):
            cv2.imwrite(str(folder / season / f"{i + 1}.png"), frame)
        # a macOS resource fork, not an image: skipped
        (folder / season / "._1.png").write_bytes(b"\x00\x05\x16\x07")


def readme_recipe(frames: Path) -> list[str]:
    """The README's two-season frames recipe's settings (`dvc exp run -S`), for the folder `frames`."""
    return [
        "data.source=frames",
        f"data.frames_dir={frames}",
        "data.seasons=[summer,winter]",
        "train.seasons=[summer,winter]",
    ]


def as_options(settings: list[str]) -> list[str]:
    """`-S <setting>` for each setting: the arguments of `dvc exp run`."""
    return [part for setting in settings for part in ("-S", setting)]


@pytest.mark.e2e
def test_the_readme_frames_recipe_runs_through_the_report(tmp_path):
    frames = tmp_path / "nordland_png"  # outside the repository: an external dependency
    write_frame_folders(frames)
    # one learner: this test is about the data path (the learners' stages are covered by
    # test_pipeline); two season sets, so that the ablation's filtering shows
    overrides = {
        **DATA_PATH,
        "ablation": {**DATA_PATH["ablation"], "training_seasons": [["summer"], ["summer", "winter"]]},
    }
    root = make_workspace(tmp_path / "repo", overrides)
    # the README's recipe, and nothing else changed
    result = dvc(root, "exp", "run", *as_options(readme_recipe(frames)))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "frames paired by file name" in result.stdout
    # the report, with the CAE width sweep that DATA_PATH skips saying so
    assert "The CAE width sweep was skipped: cae_widths.widths is empty." in (root / "plots/report.html").read_text()
    dataset = json.loads((root / "metrics/dataset.json").read_text())
    assert dataset["seasons"]["winter"]["frames"] == SECONDS and dataset["place"] == "one image of each season's folder"
    ablation = json.loads((root / "metrics/training_seasons.json").read_text())
    assert ablation["pair"] == "winter-summer" and ablation["season_sets"] == ["summer", "summer+winter"]
    assert set(json.loads((root / "metrics/summary.json").read_text())["fraction_correct"]["raw_patchnorm"]) == {
        "winter-summer"
    }
    shown = json.loads(dvc(root, "plots", "show", "--json").stdout)
    assert not shown.get("errors"), shown.get("errors")
    status = dvc(root, "status")
    assert status.returncode == 0 and "up to date" in status.stdout, status.stdout
    # DVC hashes the frames: replacing one in place reruns extraction
    frame = cv2.imread(str(frames / "summer" / "5.png"))
    cv2.imwrite(str(frames / "summer" / "5.png"), 255 - frame)
    changed = json.loads(dvc(root, "status", "--json").stdout)
    assert "extract_frames" in changed, changed
    a_queued_experiment_reads_the_frames_by_absolute_path(root, frames)


def a_queued_experiment_reads_the_frames_by_absolute_path(root: Path, frames: Path) -> None:
    """A queued experiment runs in a copy holding only git-tracked files: real data is given by
    absolute path (README). The frame changed above makes extract_frames read every frame again in
    that copy; the target stops at the split, as the stages after it are the recipe's above."""
    assert dvc(root, "exp", "run", "--queue", "-n", "real", *as_options(readme_recipe(frames)), "split").returncode == 0
    started = start_queue(root)
    assert started.returncode == 0, started.stdout
    status = wait_for_the_queue(root, experiments=1)
    assert "Success" in status and "Failed" not in status, status + dvc(root, "queue", "logs", "real").stdout[-3000:]
    logs = dvc(root, "queue", "logs", "real").stdout
    assert "Running stage 'extract_frames'" in logs and "frames paired by file name" in logs, logs[-3000:]
    shown = dvc(root, "exp", "show", "--json")
    assert shown.returncode == 0 and '"real"' in shown.stdout


# real Nordland frames (summer, winter) beside the repository, as the project's shared folder holds
# them (../shared/real/README.md: source and citation); a fresh clone without them skips the test
REAL_FRAMES = Path(__file__).resolve().parents[2] / "shared" / "real" / "nordland_summer_winter"
# 60 places of the route (every 10th second, names images-NNNNN.png): seconds 5,010 to 5,600, away
# from the first station's standing start
REAL_SECONDS = range(5010, 5610, 10)


@pytest.mark.e2e
@pytest.mark.skipif(not REAL_FRAMES.is_dir(), reason=f"no real Nordland frames at {REAL_FRAMES}")
def test_real_nordland_frames_run_through_the_report(tmp_path):
    frames = tmp_path / "nordland"
    for season in ("summer", "winter"):
        (frames / season).mkdir(parents=True)
        for second in REAL_SECONDS:
            name = f"images-{second:05d}.png"
            (frames / season / name).write_bytes((REAL_FRAMES / season / name).read_bytes())
    # the data path on real images, with the two learners that train fastest
    root = make_workspace(tmp_path / "repo", {**DATA_PATH, "learners": ["raw_patchnorm", "pca"]})
    # the recipe's settings as `dvc exp run` sets them (run as such by the test above)
    result = repro_with(root, *readme_recipe(frames))
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "frames paired by file name (60 names shared by summer, winter)" in result.stdout
    dataset = json.loads((root / "metrics/dataset.json").read_text())
    # the real seasons are aligned by name: the alignment check finds them at offset 0
    assert dataset["alignment"]["summer-winter"]["offset"] == 0, dataset["alignment"]
    evaluation = json.loads((root / "metrics/eval/raw_patchnorm/winter-summer.json").read_text())
    queries = evaluation["n_queries"]
    # far above chance (one correct place among 60), and too few queries for an interval: said so
    assert evaluation["fraction_correct"] > 3 / len(REAL_SECONDS), evaluation["fraction_correct"]
    assert queries < 49 and evaluation["intervals"]["fraction_correct"]["route"]["low"] is None
    comparisons = json.loads((root / "metrics/comparisons.json").read_text())
    rows = comparisons["pairs"]["winter-summer"]["learners"]
    assert [row["verdict"] for row in rows] == ["not enough queries"]
    assert "not enough queries" in (root / "plots/report.html").read_text()
