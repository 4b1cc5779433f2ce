"""End to end: `dvc repro` of the whole pipeline on a tiny configuration, in a copy of the repo."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]

# Small enough for CI on 2 cores, large enough that every stage has real work: three seasons
# (so pairs are filtered to the seasons present), every learner, both matchers.
TINY = {
    "data": {"seasons": ["summer", "fall", "winter"]},
    "train": {"seasons": ["summer", "fall", "winter"]},
    "synthetic": {"seconds": 300, "fps": 2, "width": 128, "height": 72},
    "extract": {"height": 36, "width": 64},
    "split": {"section_length": 100, "test_fraction": 0.3, "gap": 3},
    "pca": {"n_discard": 3, "n_keep": 20},
    "pca_whiten": {"n_keep": 16},
    "ica": {"n_components": 16, "max_iter": 200},
    "ica_bovw": {"n_train_patches": 3000, "n_components": 15, "n_words": 20},
    "fae": {"hidden": 32, "epochs": 2},
    "cae": {"channels": [4, 8, 8], "kernels": [5, 3, 3], "epochs": 1, "max_train_images": 64},
    "ablation": {"training_seasons": [["summer"], ["summer", "winter"]], "pair": "summer-fall"},
}


def merge(base: dict, override: dict) -> dict:
    for key, value in override.items():
        base[key] = merge(base[key], value) if isinstance(value, dict) and isinstance(base.get(key), dict) else value
    return base


# What `dvc repro` writes: a developer's checkout may hold them, a fresh clone does not.
PIPELINE_OUTPUTS = ("data/", "models/", "metrics/", "plots/", "logs/", "dvc.lock", "benchmarks/results/")


def source_files() -> list[str]:
    """The repository as a fresh clone would have it, plus uncommitted source changes."""
    listed = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard"],
                            cwd=REPO, check=True, capture_output=True, text=True).stdout.split()
    return [name for name in listed if (REPO / name).is_file() and not name.startswith(PIPELINE_OUTPUTS)]


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    """A fresh git + DVC copy of the repository with the tiny params, after one `dvc repro`."""
    root = tmp_path_factory.mktemp("repo")
    for name in source_files():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(REPO / name, root / name)
    params = merge(yaml.safe_load((root / "params.yaml").read_text()), TINY)
    (root / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))
    for command in (["git", "init", "-q"], ["git", "add", "-A"],
                    ["git", "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "tiny"]):
        subprocess.run(command, cwd=root, check=True)
    result = dvc(root, "repro")
    assert result.returncode == 0, result.stdout + result.stderr
    return root


def dvc(root: Path, *args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    return subprocess.run([str(Path(sys.executable).parent / "dvc"), *args], cwd=root, env=env,
                          capture_output=True, text=True)


@pytest.mark.e2e
def test_repro_writes_every_result(workspace):
    dataset = json.loads((workspace / "metrics/dataset.json").read_text())
    assert dataset["seasons"]["summer"]["frames"] == 300
    assert dataset["dropped_tunnel"] + dataset["dropped_stop"] >= 0
    for name in ("summer", "fall", "winter"):
        assert (workspace / f"data/augmented/{name}.npy").is_file()
        assert (workspace / f"data/split/{name}_test.npy").is_file()
    assert (workspace / "plots/season_preview.png").stat().st_size > 0


@pytest.mark.e2e
def test_learners_metrics_and_plots_exist(workspace):
    learners = ["raw_patchnorm", "pca", "pca_whiten", "ica", "ica_bovw", "fae", "cae"]
    pairs = ["summer-fall", "winter-summer", "winter-fall"]   # the study's pairs among 3 seasons
    suffixes = ("", "+seq", "@cityblock", "@cityblock+seq")  # evaluate.extra_metrics: [cityblock]
    for learner in learners:
        assert (workspace / f"models/{learner}/learner.json").is_file()
        for pair in pairs:
            for suffix in suffixes:
                metrics = json.loads((workspace / f"metrics/eval/{learner}/{pair}{suffix}.json").read_text())
                assert 0 <= metrics["fraction_correct"] <= 1
                assert metrics["precision_at_full_recall"] == pytest.approx(metrics["fraction_correct"])
                assert (workspace / f"plots/pr/{learner}/{pair}{suffix}.csv").is_file()
        assert not list((workspace / f"metrics/eval/{learner}").glob("*spring*"))
    runtime = json.loads((workspace / "metrics/runtime.json").read_text())
    assert set(runtime) == set(learners) and all(r["fit_seconds"] >= 0 for r in runtime.values())
    summary = json.loads((workspace / "metrics/summary.json").read_text())
    assert set(summary["fraction_correct"]) == {learner + suffix for learner in learners for suffix in suffixes}
    assert summary["pr_landmarks"]["summer-fall"]["ica"]["recall_at_100_precision"]["study"] == 0.67
    ablation = json.loads((workspace / "metrics/training_seasons.json").read_text())
    assert set(ablation["fraction_correct"]["pca"]) == {"summer", "summer+winter"}
    for figure in ("fig02_pca_projection", "fig12_patch_ica_filters", "fig13_visual_words",
                   "fig19_autoencoder_descriptors"):
        assert (workspace / f"plots/figures/{figure}.png").stat().st_size > 0
    # fae and cae train in epochs: dvclive logs the loss of each
    assert (workspace / "logs/cae/plots/metrics/train/loss.tsv").is_file()
    shown = dvc(workspace, "plots", "show", "--json")
    assert shown.returncode == 0, shown.stderr
    assert "pr_summer-fall" in json.loads(shown.stdout)["data"]
    # dvc.yaml names the PR files of all six pairs; only those of the absent season may be missing
    errors = json.loads(shown.stdout).get("errors") or []
    assert all("spring" in error.get("source", "") for error in errors), errors
    shown = dvc(workspace, "metrics", "show")
    header = shown.stdout.splitlines()[0].split()
    # one schema: a table of the per-pair metrics, not the union of every JSON file's keys
    assert shown.returncode == 0 and "fraction_correct" in header and len(header) <= 12, header
    report = (workspace / "plots/report.html").read_text()
    assert "data:image/png;base64," in report and "summer-fall" in report
    assert "pca_whiten@cityblock" in report and "precision-recall landmarks" in report


@pytest.mark.e2e
def test_second_repro_does_nothing(workspace):
    status = dvc(workspace, "status")
    assert status.returncode == 0 and "up to date" in status.stdout, status.stdout


@pytest.mark.e2e
def test_a_learner_param_reruns_only_that_learner(workspace):
    params = yaml.safe_load((workspace / "params.yaml").read_text())
    params["pca"]["n_keep"] = 15
    (workspace / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))
    status = dvc(workspace, "status", "--json")
    changed = set(json.loads(status.stdout))
    assert "fit@pca" in changed
    assert not {name for name in changed if "@" in name and "pca" not in name.split("@")[1]}
    assert not changed & {"acquire", "extract_frames", "preprocess", "split", "augment"}
    diff = dvc(workspace, "params", "diff")
    assert "pca.n_keep" in diff.stdout


@pytest.mark.e2e
def test_bad_params_fail_with_one_clear_line(workspace):
    params = yaml.safe_load((workspace / "params.yaml").read_text())
    params["train"]["seasons"] = ["summer", "autumn"]
    (workspace / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))
    result = subprocess.run([sys.executable, "stages/fit.py", "pca"], cwd=workspace, capture_output=True, text=True)
    assert result.returncode == 1
    assert result.stderr.strip() == "error: train.seasons: unknown season 'autumn' (known: summer, fall, winter)"
    result = subprocess.run([sys.executable, "stages/fit.py", "sift"], cwd=workspace, capture_output=True, text=True)
    assert result.returncode == 1 and "unknown method 'sift'" in result.stderr and "Traceback" not in result.stderr


@pytest.mark.e2e
def test_missing_real_videos_fail_cleanly_and_keep_outputs(workspace):
    before = sorted(p.name for p in (workspace / "data/acquired").iterdir())
    params = yaml.safe_load((workspace / "params.yaml").read_text())
    params["data"]["source"] = "videos"
    (workspace / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))
    result = subprocess.run([sys.executable, "stages/acquire.py"], cwd=workspace, capture_output=True, text=True)
    assert result.returncode == 1
    assert result.stderr.strip() == "error: data/nordland/videos/summer.mp4: video for season 'summer' not found"
    # the failed stage leaves neither a half-written folder nor a changed one
    assert sorted(p.name for p in (workspace / "data/acquired").iterdir()) == before
    assert not [p for p in (workspace / "data").iterdir() if p.name.startswith(".acquired")]
