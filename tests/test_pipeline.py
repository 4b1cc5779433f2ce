"""End to end: `dvc repro` of the whole pipeline on a tiny configuration, in a copy of the repo.

The stages run once per test session in the seed (tests/workspaces.py, the same params); this
module's workspace is a copy of that run, committed, and its tests check what the stages wrote.
"""

from __future__ import annotations

import copy
import json
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from seasonloop.models.core.lookup import get_learner
from tools.repository import dvc
from workspaces import committed_run


@pytest.fixture(scope="module")
def workspace(tmp_path_factory, tiny_seed_cache) -> Path:
    """The seed's TINY run (tools/small_runs.py) in a git + DVC workspace of its own, dvc.lock committed."""
    return committed_run(tmp_path_factory.mktemp("run") / "repo", tiny_seed_cache)


@pytest.mark.e2e
def test_a_fresh_workspace_restores_what_the_run_cache_holds(tiny_seed_cache):
    # the seed's TINY phase ran in a fresh workspace linking SMALL's cache: every stage whose
    # command, deps, params and outputs SMALL's run also had came back from DVC's run cache (a stage
    # with a dep that differs between workspaces, as DVC's .gitignore files once did, would run)
    seed = tiny_seed_cache.parent
    small, tiny = (
        yaml.safe_load((seed / f"repo-{phase}/dvc.lock").read_text())["stages"] for phase in ("small", "tiny")
    )
    shared = {stage for stage, entry in tiny.items() if small.get(stage) == entry}
    assert {"acquire", "split", "fit@pca", "features@pca"} <= shared, sorted(shared)
    said = (seed / "repro-tiny.log").read_text()
    for stage in shared:
        assert f"Stage '{stage}' is cached - skipping run" in said, stage
        assert f"Running stage '{stage}'" not in said, stage


@pytest.fixture(autouse=True)
def restore_params(request):
    """Each test gets the workspace's params.yaml back, whatever the test did or however it failed."""
    if "workspace" not in request.fixturenames:
        yield
        return
    path = request.getfixturevalue("workspace") / "params.yaml"
    saved = path.read_text()
    try:
        yield
    finally:
        path.write_text(saved)


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
    learners = yaml.safe_load((workspace / "params.yaml").read_text())["learners"]
    assert {"raw_patchnorm", "pca", "ica", "fae", "cae"} <= set(learners)  # the study's, at least
    pairs = ["summer-fall", "winter-summer", "winter-fall"]  # the study's pairs among 3 seasons
    # every matcher, under evaluate.metric and evaluate.extra_metrics: [cityblock]
    suffixes = [metric + matcher for metric in ("", "@cityblock") for matcher in ("", "+seq", "+delta", "+smoothed")]
    for learner in learners:
        assert (workspace / f"models/{learner}/learner.json").is_file()
        for pair in pairs:
            for suffix in suffixes:
                metrics = json.loads((workspace / f"metrics/eval/{learner}/{pair}{suffix}.json").read_text())
                assert 0 <= metrics["fraction_correct"] <= 1
                assert metrics["precision_at_full_recall"] == pytest.approx(metrics["fraction_correct"])
                assert 0 <= metrics["extended_precision"] <= 1
                interval = metrics["intervals"]["fraction_correct"]["route"]
                assert interval["low"] is None or interval["low"] <= metrics["fraction_correct"] <= interval["high"]
                assert (workspace / f"plots/pr/{learner}/{pair}{suffix}.csv").is_file()
                assert (workspace / f"data/outcomes/{learner}/{pair}{suffix}.csv").is_file()
        assert not list((workspace / f"metrics/eval/{learner}").glob("*spring*"))
    runtime = json.loads((workspace / "metrics/runtime.json").read_text())
    assert set(runtime) == set(learners) and all(r["fit_seconds"] >= 0 for r in runtime.values())
    summary = json.loads((workspace / "metrics/summary.json").read_text())
    assert set(summary["fraction_correct"]) == {learner + suffix for learner in learners for suffix in suffixes}
    assert summary["pr_landmarks"]["summer-fall"]["ica"]["recall_at_100_precision"]["study"] == 0.67
    ablation = json.loads((workspace / "metrics/training_seasons.json").read_text())
    assert set(ablation["fraction_correct"]["pca"]) == {"summer", "summer+winter"}
    assert set(ablation["intervals"]["pca"]) == {"summer", "summer+winter"}
    # every learner against every other on every pair; each learner's matchers against single images
    # and against each matcher before them; L1 against its reference
    comparisons = json.loads((workspace / "metrics/comparisons.json").read_text())
    assert comparisons["order"]["pairs"] == pairs
    tables = comparisons["pairs"]["summer-fall"]
    matchers = {
        f"matchers{metric}{matcher}{versus}"
        for metric in ("", "@cityblock")
        for matcher, versus in [
            ("+seq", ""),
            ("+delta", ""),
            ("+delta", " vs +seq"),
            ("+smoothed", ""),
            ("+smoothed", " vs +seq"),
            ("+smoothed", " vs +delta"),
        ]
    }
    distances = {f"distances@cityblock{matcher}" for matcher in ("", "+seq", "+delta", "+smoothed")}
    assert set(tables) == {f"learners{suffix}" for suffix in suffixes} | matchers | distances
    n = len(learners)
    assert len(tables["learners"]) == n * (n - 1) // 2 and len(tables["matchers+delta vs +seq"]) == n
    for figure in (
        "fig02_pca_projection",
        "fig12_patch_ica_filters",
        "fig12b_global_ica_basis",
        "fig13_visual_words",
        "fig19_autoencoder_descriptors",
    ):
        assert (workspace / f"plots/figures/{figure}.png").stat().st_size > 0
    # fae and cae train in epochs: dvclive logs the training and validation loss of each, and the
    # fit metrics say how training ended
    for name, epochs in (("fae", 2), ("cae", 1)):
        for curve in ("train", "validation"):
            assert (
                len((workspace / f"logs/{name}/plots/metrics/loss/{curve}.tsv").read_text().splitlines()) == epochs + 1
            )
        info = json.loads((workspace / f"metrics/fit/{name}.json").read_text())["info"]
        assert info["stop_reason"] == "max_epochs" and info["converged"] is False and info["epochs_run"] == epochs
    training = json.loads((workspace / "metrics/network_training.json").read_text())  # every learner trained in epochs
    assert set(training) == {name for name in learners if get_learner(name).trains_in_epochs} >= {"fae", "cae"}
    assert training["cae"]["epochs_run"] == 1
    assert (workspace / "plots/figures/fig19b_autoencoder_reconstructions.png").is_file()
    sweep = json.loads((workspace / "metrics/cae_widths.json").read_text())
    assert sweep["pairs"] == ["summer-fall", "winter-summer"]  # spring-fall has no spring here
    assert {label: (row["channels"], row["reused"]) for label, row in sweep["widths"].items()} == {
        "1/32": ([3, 8, 12], True),
        "1/16": ([6, 16, 24], False),
    }
    assert sweep["widths"]["1/32"]["best_validation_loss"] == training["cae"]["best_validation_loss"]
    assert (workspace / "plots/cae_widths.md").read_text().count("\n| 1/") == 2
    shown = dvc(workspace, "plots", "show", "--json")
    assert shown.returncode == 0, shown.stderr
    plots = json.loads(shown.stdout)
    # one PR plot per pair present, every learner in it; no file of an absent season is named
    assert {"plots/summary/pr/summer-fall.csv", "training_loss"} <= set(plots["data"])
    assert not [name for name in plots["data"] if "spring" in name]
    assert not plots.get("errors"), plots.get("errors")
    shown = dvc(workspace, "metrics", "show")
    header = shown.stdout.splitlines()[0].split()
    # the one declared metrics file: fraction correct per learner and matcher, averaged over the
    # pairs, one short column each for `dvc exp show`; not the union of every per-pair file's keys
    assert shown.returncode == 0 and header[1:] == sorted(
        f"{learner}{matcher}" for learner in learners for matcher in ("", "+seq", "+delta", "+smoothed")
    ), header
    # the per-pair files are still there for `dvc metrics show <path>`
    detail = dvc(workspace, "metrics", "show", "metrics/eval/pca")
    assert detail.returncode == 0 and "recall_at_100_precision" in detail.stdout.splitlines()[0]
    report = (workspace / "plots/report.html").read_text()
    assert "data:image/png;base64," in report and "summer-fall" in report
    assert "pca_whiten@cityblock" in report and "precision-recall landmarks" in report
    assert "CAE width sweep" in report
    assert "Paired comparisons" in report and "summer-fall: learner against learner" in report


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
def test_editing_one_learner_module_reruns_only_that_learner(workspace):
    # the registry imports a learner's module on demand, and its stages depend on that module only
    # (and models/core): its fit, its features and, for a learner of ablation.learners, its part of
    # the training-season ablation; and the figures stage, which asks every learner of the run
    # which figures its model draws; nothing else
    changed = {}
    for learner in ("pca_whiten", "fae", "pca"):
        module = workspace / "src/seasonloop/models" / f"{learner}.py"
        saved = module.read_text()
        try:
            module.write_text(saved + "# an edit\n")
            changed[learner] = set(json.loads(dvc(workspace, "status", "--json").stdout))
        finally:
            module.write_text(saved)
    assert changed["pca_whiten"] == {"fit@pca_whiten", "features@pca_whiten", "figures"}
    assert changed["fae"] == {"fit@fae", "features@fae", "figures"}
    # pca is in ablation.learners
    assert changed["pca"] == {"fit@pca", "features@pca", "training_seasons_fit@pca", "figures"}
    assert set(json.loads(dvc(workspace, "status", "--json").stdout)) == set()


@pytest.mark.e2e
def test_bad_params_fail_with_one_clear_line(workspace):
    base = yaml.safe_load((workspace / "params.yaml").read_text())

    def run_with(change, *command):
        params = copy.deepcopy(base)
        change(params)
        (workspace / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))
        return subprocess.run([sys.executable, *command], cwd=workspace, capture_output=True, text=True)

    result = run_with(lambda p: p["train"].update(seasons=["summer", "autumn"]), "stages/fit.py", "pca")
    assert result.returncode == 1
    assert (
        result.stderr.strip() == "error: train.seasons: unknown traverse 'autumn' (data.seasons: summer, fall, winter)"
    )
    result = run_with(lambda p: None, "stages/fit.py", "sift")
    assert result.returncode == 1 and "unknown learner 'sift'" in result.stderr and "Traceback" not in result.stderr
    # typos and out-of-range values outside the learner sections, caught before any work
    result = run_with(lambda p: p["split"].update(tets_fraction=0.2), "stages/split.py")
    assert result.returncode == 1 and result.stderr.strip().startswith("error: split.tets_fraction: unknown key")
    # a typo in a section the stage does not read stops it too: the whole file is checked first
    result = run_with(lambda p: p["evaluate"].update(metirc="cosine"), "stages/acquire.py")
    assert result.returncode == 1 and result.stderr.strip().startswith("error: evaluate.metirc: unknown key")
    result = run_with(lambda p: p["split"].update(test_fraction=0.9), "stages/split.py")
    assert result.returncode == 1 and result.stderr.strip().startswith(
        "error: split.test_fraction: expected a number in"
    )
    # the ablation rejects a bad evaluate.metric before its first fit
    result = run_with(lambda p: p["evaluate"].update(metric="manhattan"), "stages/training_seasons_fit.py", "ica")
    assert result.returncode == 1 and "FastICA" not in result.stderr
    assert (
        result.stderr.strip()
        == "error: evaluate.metric: unknown value 'manhattan' (known: cosine, euclidean, cityblock)"
    )


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
