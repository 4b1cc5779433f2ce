"""docs/extending.md's steps, done: each adds what the page says to a copy of the project, in the
files it names and no others, and runs it through `dvc repro` (a learner: tests/test_new_learner.py)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import yaml

from tools.repository import REPO, commit_all, dvc, git, tool_env, write_params
from workspaces import committed_run


def copied_src(folder: Path) -> Path:
    """A copy of the library's source in folder/src, to change as a recipe says."""
    shutil.copytree(REPO / "src", folder / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    return folder / "src"


def run_on_params(src: Path, program: str, change: Callable[[dict[str, Any]], None]) -> subprocess.CompletedProcess:
    """`program` run with the library at `src`, params.yaml with `change` applied on its stdin."""
    params = yaml.safe_load((REPO / "params.yaml").read_text())
    change(params)
    return subprocess.run(
        [sys.executable, "-c", program],
        input=yaml.safe_dump(params),
        env=tool_env(PYTHONPATH=str(src)),
        capture_output=True,
        text=True,
    )


# A matcher the project has never seen: each frame's descriptor beside its successor's (the last
# frame's twice), matched as single images.
PAIRS_FUNCTION = """
def _with_next(descriptors: np.ndarray, places: np.ndarray, sequence: SequenceConfig) -> np.ndarray:
    following = np.concatenate([descriptors[1:], descriptors[-1:]])
    return np.concatenate([descriptors, following], axis=1)


"""
PAIRS_LINE = '    "pairs": Matcher("+pairs", "each frame with the next", _single_image, _with_next),\n'
REGISTRY_COMMENT = "# A new matcher is one function plus one line here"


def add_matcher(root: Path) -> None:
    """docs/extending.md, "A matcher": its function and its line in MATCHER_REGISTRY, and its name in
    evaluate.matchers to run it."""
    module = root / "src/seasonloop/evaluation/matchers.py"
    text = module.read_text()
    assert REGISTRY_COMMENT in text and "MATCHER_REGISTRY: dict[str, Matcher] = {\n" in text
    text = text.replace(REGISTRY_COMMENT, PAIRS_FUNCTION.lstrip("\n") + REGISTRY_COMMENT)
    text = text.replace(
        "MATCHER_REGISTRY: dict[str, Matcher] = {\n", "MATCHER_REGISTRY: dict[str, Matcher] = {\n" + PAIRS_LINE
    )
    module.write_text(text)
    params = yaml.safe_load((root / "params.yaml").read_text())
    params["evaluate"]["matchers"] = [*params["evaluate"]["matchers"], "pairs"]
    (root / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))


@pytest.mark.e2e
def test_a_matcher_added_in_its_module_and_params_runs_through_dvc_repro(tmp_path, small_seed_cache):
    root = committed_run(tmp_path / "workspace", small_seed_cache)
    add_matcher(root)
    changed = git(root, "status", "--porcelain").stdout.split("\n")
    assert sorted(line[3:] for line in changed if line) == ["params.yaml", "src/seasonloop/evaluation/matchers.py"]

    result = dvc(root, "repro")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    # every learner evaluated with it, its rows in the summary and the report beside the others'
    learners = yaml.safe_load((root / "params.yaml").read_text())["learners"]
    summary = yaml.safe_load((root / "metrics/mean_fraction_correct.json").read_text())
    assert {f"{learner}+pairs" for learner in learners} <= set(summary)
    assert all((root / "metrics/eval" / learner / "summer-fall+pairs.json").is_file() for learner in learners)
    assert "each frame with the next" in (root / "plots/report.html").read_text()


def test_a_setting_added_in_params_yaml_and_its_sections_dataclass_is_checked_by_every_stage(tmp_path):
    """docs/extending.md, "A setting": its value in params.yaml and one field with its check in its
    section's dataclass; the whole-file check every stage starts with then requires and checks it."""
    src = copied_src(tmp_path)
    settings = src / "seasonloop/params/settings.py"
    anchor = "    window_at_breaks: str = setting(one_of(*WINDOW_RULES))\n"
    text = settings.read_text()
    assert anchor in text
    settings.write_text(text.replace(anchor, anchor + "    stride: int = setting(integer(1))\n"))
    check = "import sys, yaml; from seasonloop.registries.choices import check_whole; check_whole(yaml.safe_load(sys.stdin))"

    def checked(stride: int | None) -> subprocess.CompletedProcess:
        def change(params: dict[str, Any]) -> None:
            if stride is not None:
                params["sequence"]["stride"] = stride

        return run_on_params(src, check, change)

    assert checked(2).returncode == 0
    assert "sequence.stride" in checked(0).stderr  # its check
    assert "sequence.stride" in checked(None).stderr  # and params.yaml must hold it


# A source the project has never seen: each traverse's frames in an images/ folder of its own
# (dataset/<traverse>/images/*.png), a layout some datasets ship.
NESTED_FUNCTION = """
def _nested_frame_folders(seasons: Sequence[str], data: DataConfig) -> dict[str, Path]:
    paths = {season: Path(data.frames_dir) / season / "images" for season in seasons}
    for folder in paths.values():
        list_frame_files(folder)  # raises, naming the folder, when missing or empty
    return paths


"""
NESTED_LINE = '    "nested_frames": Source("frames", locate=_nested_frame_folders),\n'
SOURCES_OPEN = "SOURCES: dict[str, Source] = {\n"


def add_source(root: Path) -> None:
    """docs/extending.md, "A data source": its locating function and its line in SOURCES."""
    module = root / "src/seasonloop/data/sources.py"
    text = module.read_text()
    anchor = "@dataclass(frozen=True)\nclass Source:"
    assert anchor in text and SOURCES_OPEN in text
    text = text.replace(SOURCES_OPEN, SOURCES_OPEN + NESTED_LINE)
    module.write_text(text.replace(anchor, NESTED_FUNCTION.lstrip("\n") + anchor))


@pytest.mark.e2e
def test_a_data_source_added_in_its_module_runs_through_dvc_repro(tmp_path):
    import cv2

    from seasonloop.data.frames import sample_video
    from seasonloop.data.synthetic import render_route
    from tools.small_runs import DATA_PATH
    from workspaces import make_workspace

    dataset, seasons = tmp_path / "dataset", ["summer", "winter"]
    render_route(tmp_path / "videos", seasons, 240, 1, 128, 72, seed=3, progress=False)
    for season in seasons:
        (dataset / season / "images").mkdir(parents=True)
        for i, frame in enumerate(sample_video(tmp_path / "videos" / f"{season}.mp4", 1, 72, 128, progress=False)):
            cv2.imwrite(str(dataset / season / "images" / f"{i + 1}.png"), frame)
    overrides = {
        **DATA_PATH,
        "data": {"source": "nested_frames", "frames_dir": str(dataset), "seasons": seasons},
        "train": {"seasons": seasons},
        "evaluate": {"pairs": ["winter-summer"]},
        "ablation": {**DATA_PATH["ablation"], "pair": "winter-summer"},
        "report": {"example_pair": "winter-summer"},
        "cae_widths": {**DATA_PATH["cae_widths"], "pairs": ["winter-summer"]},
    }
    root = make_workspace(tmp_path / "repo", {})  # the project as it is; then the source, and params naming it
    add_source(root)
    write_params(root, overrides)
    changed = git(root, "status", "--porcelain").stdout.split("\n")
    assert sorted(line[3:] for line in changed if line) == ["params.yaml", "src/seasonloop/data/sources.py"]
    commit_all(root)
    result = dvc(root, "repro")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    places = yaml.safe_load((root / "metrics/dataset.json").read_text())["seasons"]
    assert set(places) == set(seasons)
    assert (root / "metrics/eval/raw_patchnorm/winter-summer.json").is_file()


# A kind the project has never seen: a query is right only at its own frame (the aligned kind with
# no tolerance, whatever evaluate.tolerance_frames says).
EXACT_CLASS = """
class Exact(Aligned):
    name = "exact"

    def pair_builder(self, seasons, test, counts, evaluate, frames_dir, truth_dir) -> PairBuilder:
        return lambda database, query: aligned_truth(test[database], test[query], 0)

    def describe(self, evaluate: EvaluateConfig) -> str:
        return "the query's own frame index"


"""
KINDS_OPEN = "TRUTH_KINDS: dict[str, TruthKind] = {kind.name: kind for kind in (Aligned(), "


def test_a_ground_truth_kind_added_in_its_module_is_checked_and_builds_its_truth(tmp_path):
    """docs/extending.md, "A ground-truth kind": its class and its entry in TRUTH_KINDS; params.yaml's
    data.ground_truth may then name it, and the pair's truth is the class's."""
    src = copied_src(tmp_path)
    module = src / "seasonloop/data/ground_truth_kinds.py"
    text = module.read_text()
    assert KINDS_OPEN in text
    text = text.replace(
        KINDS_OPEN, EXACT_CLASS.lstrip("\n") + KINDS_OPEN.replace("(Aligned(), ", "(Aligned(), Exact(), ")
    )
    module.write_text(text)
    program = """
import sys, yaml
import numpy as np
from seasonloop.data.ground_truth_kinds import truth_kind
from seasonloop.params.settings import EvaluateConfig
from seasonloop.registries.choices import check_whole

params = yaml.safe_load(sys.stdin)
check_whole(params)
kind = truth_kind(params["data"]["ground_truth"])
test = {"summer": np.array([3, 4, 5]), "winter": np.array([3, 4, 5])}
evaluate = EvaluateConfig.from_params(params)
truth = kind.pair_builder(["summer", "winter"], test, {}, evaluate, None, None)("summer", "winter")
print(kind.describe(evaluate), int(truth.correct.sum()), evaluate.tolerance_frames)
"""

    def run(kind: str) -> subprocess.CompletedProcess:
        def change(params: dict[str, Any]) -> None:
            params["data"]["ground_truth"] = kind
            params["evaluate"]["tolerance_frames"] = 1

        return run_on_params(src, program, change)

    exact, aligned = run("exact"), run("aligned")
    assert exact.returncode == 0 and aligned.returncode == 0, exact.stderr + aligned.stderr
    describe, correct, tolerance = exact.stdout.strip().rsplit(" ", 2)
    # its own rule: 3 test places, each right at its own frame only, where aligned's tolerance of 1
    # also counts each one's neighbours
    assert (describe, correct, tolerance) == ("the query's own frame index", "3", "1")
    assert aligned.stdout.split()[-2] == "7"
    assert "data.ground_truth: unknown value 'exakt'" in run("exakt").stderr
