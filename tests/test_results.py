"""Tests for seasonloop.reporting.results: the other stages' result files read back in table order."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from seasonloop.io import write_json
from seasonloop.models.core.lookup import get_learner, load_fitted_elsewhere
from seasonloop.reporting.results import (
    load_autoencoder_descriptors,
    load_dataset,
    load_evaluations,
    load_runtime,
    load_runtime_record,
    load_training_seasons,
    network_training,
    ordered,
)
from tools.repository import learner_params

LEARNERS = ["pca", "ica"]
PAIRS = ["summer-fall", "winter-fall"]
# (metric, matcher, suffix) as seasonloop.evaluation.matchers.evaluations gives them
VARIANTS = [("cosine", "single", ""), ("cosine", "sequence", "+seq"), ("cityblock", "single", "@cityblock")]


def fake_intervals(fraction: float) -> dict:
    """An evaluate stage's intervals around `fraction` (fake numbers, each bound in [0, 1])."""
    bounds = {"low": max(0.0, fraction - 0.05), "high": min(1.0, fraction + 0.05)}
    interval = {"route": bounds, "wilson": bounds}
    return {"fraction_correct": interval, "recall_at_1": interval}


def write_evaluations(eval_dir, pr_dir) -> None:
    """metrics/eval- and plots/pr-like folders: fraction correct encodes (learner, pair, variant)."""
    for v, (_, _, suffix) in enumerate(VARIANTS):
        for m, learner in enumerate(LEARNERS):
            for p, pair in enumerate(PAIRS):
                write_json(
                    eval_dir / learner / f"{pair}{suffix}.json",
                    {
                        "fraction_correct": (100 * m + 10 * p + v) / 1000,
                        "recall_at_100_precision": 0.5,
                        "precision_at_full_recall": 0.25,
                        "intervals": fake_intervals((100 * m + 10 * p + v) / 1000),
                    },
                )
                (pr_dir / learner).mkdir(parents=True, exist_ok=True)
                pd.DataFrame({"recall": [0.0, 0.5 + v / 10], "precision": [1.0, m / 2]}).to_csv(
                    pr_dir / learner / f"{pair}{suffix}.csv", index=False
                )


@pytest.fixture
def result_dirs(tmp_path):
    eval_dir, pr_dir = tmp_path / "eval", tmp_path / "pr"
    write_evaluations(eval_dir, pr_dir)
    return eval_dir, pr_dir


def test_load_evaluations_in_table_order(result_dirs):
    eval_dir, pr_dir = result_dirs
    results = load_evaluations(eval_dir, LEARNERS, PAIRS, VARIANTS, "cosine", pr_dir=pr_dir)
    # evaluations' order first, then the learners'
    assert results.labels == ["pca", "ica", "pca+seq", "ica+seq", "pca@cityblock", "ica@cityblock"]
    assert results.pairs == PAIRS and all(list(by_pair) == PAIRS for by_pair in results.metrics.values())
    assert results.metrics["ica@cityblock"]["winter-fall"]["fraction_correct"] == pytest.approx(0.112)
    assert results.metric_of == {
        "pca": "cosine",
        "ica": "cosine",
        "pca+seq": "cosine",
        "ica+seq": "cosine",
        "pca@cityblock": "cityblock",
        "ica@cityblock": "cityblock",
    }
    # curves: the main metric's labels only, per pair
    assert list(results.curves) == PAIRS
    assert list(results.curves["summer-fall"]) == ["pca", "ica", "pca+seq", "ica+seq"]
    recall, precision = results.curves["winter-fall"]["ica+seq"]
    np.testing.assert_allclose(recall, [0.0, 0.6])
    np.testing.assert_allclose(precision, [1.0, 0.5])


def test_load_evaluations_refuses_metrics_without_intervals(result_dirs):
    eval_dir, _ = result_dirs
    stale = eval_dir / "ica" / "winter-fall+seq.json"
    stale.write_text('{"fraction_correct": 0.5}')
    with pytest.raises(ValueError, match=r"ica/winter-fall\+seq.json: no intervals \(rerun the evaluate stage\)"):
        load_evaluations(eval_dir, LEARNERS, PAIRS, VARIANTS, "cosine")


def test_load_evaluations_without_curves_reads_no_pr_file(result_dirs):
    eval_dir, _ = result_dirs
    results = load_evaluations(eval_dir, LEARNERS, PAIRS, VARIANTS, "cosine")
    assert results.curves == {} and len(results.labels) == 6


def test_load_evaluations_names_a_missing_file(result_dirs):
    eval_dir, _ = result_dirs
    with pytest.raises(OSError, match="spring-fall"):
        load_evaluations(eval_dir, LEARNERS, ["spring-fall"], VARIANTS, "cosine")


def test_load_runtime(tmp_path):
    for learner, seconds in (("pca", 1.5), ("ica", 20)):
        fit = {"fit_seconds": seconds, "n_train_images": 100, "trained_on": "the training places of summer"}
        write_json(tmp_path / "fit" / f"{learner}.json", fit)
        for season, ms in (("summer", 1.0), ("fall", 2.0)):
            write_json(tmp_path / "features" / learner / f"{season}.json", {"ms_per_image": ms, "dimension": 16})
    runtime = load_runtime(tmp_path / "fit", tmp_path / "features", ["ica", "pca"], ["summer", "fall"])
    assert list(runtime) == ["ica", "pca"]
    assert runtime["pca"] == {
        "fit_seconds": 1.5,
        "n_train_images": 100,
        "feature_ms_per_image": 1.5,
        "descriptor_dimension": 16,
        "trained_on": "the training places of summer",
    }
    assert list(runtime["ica"]) == [
        "fit_seconds",
        "n_train_images",
        "feature_ms_per_image",
        "descriptor_dimension",
        "trained_on",
    ]


def test_ordered_names_what_is_missing():
    assert list(ordered({"b": 1, "a": 2}, ["a", "b"], "x.json")) == ["a", "b"]
    with pytest.raises(ValueError, match=r"x\.json: no entry for c"):
        ordered({"a": 1}, ["a", "c"], "x.json")


def test_records_in_the_run_order(tmp_path):
    write_json(tmp_path / "dataset.json", {"seasons": {"summer": {"frames": 1}, "fall": {"frames": 1}}, "gap": 3})
    assert list(load_dataset(tmp_path / "dataset.json", ["summer", "fall"])["seasons"]) == ["summer", "fall"]
    write_json(tmp_path / "runtime.json", {"ica": {}, "pca": {}})
    assert list(load_runtime_record(tmp_path / "runtime.json", ["pca", "ica"])) == ["pca", "ica"]
    write_json(
        tmp_path / "training.json",
        {
            "pair": "summer-fall",
            "season_sets": ["summer", "summer+winter"],
            "fraction_correct": {
                "ica": {"summer": 0.1, "summer+winter": 0.2},
                "pca": {"summer+winter": 0.4, "summer": 0.3},
            },
        },
    )
    training = load_training_seasons(tmp_path / "training.json", ["pca", "ica"])
    assert list(training["fraction_correct"]) == ["pca", "ica"]
    assert list(training["fraction_correct"]["pca"]) == ["summer", "summer+winter"]
    write_json(tmp_path / "skipped.json", {"skipped": "skipped: one season"})
    assert load_training_seasons(tmp_path / "skipped.json", ["pca"]) == {"skipped": "skipped: one season"}
    write_json(tmp_path / "ae.json", {"fae": {"code": {}}, "cae": {"code": {}}})
    assert list(load_autoencoder_descriptors(tmp_path / "ae.json", ["pca", "fae", "cae"])) == ["fae", "cae"]
    assert load_autoencoder_descriptors(tmp_path / "ae.json", ["pca"]) == {}


def test_a_network_fitted_elsewhere_has_its_models_training_facts_and_no_times_of_this_run(tmp_path):
    # train.fitted: elsewhere takes another run's model (load_fitted_elsewhere): how its training
    # ended is the model's, its seconds and threads were that run's
    images = np.random.default_rng(0).integers(0, 256, (24, 8, 16), dtype=np.uint8)
    learner = get_learner("fae")(learner_params("fae", get_learner("fae").TINY_RUN), seed=0)
    learner.fit(images, progress=False)
    learner.save(tmp_path / "models" / "fae")
    _, info = load_fitted_elsewhere(tmp_path / "models", "fae", (8, 16))
    write_json(tmp_path / "fit" / "fae.json", {"info": info})
    training = network_training(tmp_path / "fit", ["fae"])["fae"]
    assert training["training_seconds"] is None and training["torch_threads"] is None
    assert training["epochs_run"] == learner.fit_info["epochs_run"] and training["converged"] is not None
    with pytest.raises(ValueError, match=r"models/fae: fitted on 8x16 images, this run's are 32x64"):
        load_fitted_elsewhere(tmp_path / "models", "fae", (32, 64))
    (tmp_path / "models" / "fae").rename(tmp_path / "models" / "cae")
    with pytest.raises(ValueError, match=r"models/cae: holds a 'fae' learner, not 'cae'"):
        load_fitted_elsewhere(tmp_path / "models", "cae", (8, 16))
