"""Loading the results the other stages wrote: per-pair evaluation metrics and PR curves, fit and
feature timings, and the JSON records the report shows, each in the order its tables list it.

The layout read here is the evaluate, fit and features stages' (metrics/eval/<learner>/<pair><suffix>.json,
plots/pr/<learner>/<pair><suffix>.csv, <fit>/<learner>.json, <features>/<learner>/<season>.json);
callers pass the folders. Rows are labelled <learner><suffix> (seasonloop.evaluation.matchers.result_suffix).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.io import read_json

Curve = tuple[np.ndarray, np.ndarray]  # (recall, precision)


@dataclass(frozen=True)
class EvaluationResults:
    """Every evaluation of a run, in table order (evaluations' order, then the learners').

    metrics[label][pair] is the pair's metrics JSON; metric_of[label] the distance it used;
    curves[pair][label] = (recall, precision) for the main metric's labels only (the PR figures
    show those, to stay readable), empty when the curves were not loaded.
    """

    pairs: list[str]
    metrics: dict[str, dict[str, dict[str, Any]]]
    metric_of: dict[str, str]
    main_metric: str
    curves: dict[str, dict[str, Curve]]

    @property
    def labels(self) -> list[str]:
        return list(self.metrics)


def load_evaluations(
    eval_dir: Path,
    learners: Sequence[str],
    pairs: Sequence[str],
    variants: Sequence[tuple[str, str, str]],
    main_metric: str,
    pr_dir: Path | None = None,
) -> EvaluationResults:
    """The metrics of every learner, pair and (metric, matcher, suffix) of `variants`
    (seasonloop.evaluation.matchers.evaluations), and the main metric's PR curves when `pr_dir` is given."""
    metrics: dict[str, dict[str, dict[str, Any]]] = {}
    metric_of: dict[str, str] = {}
    curves: dict[str, dict[str, Curve]] = {pair: {} for pair in pairs} if pr_dir is not None else {}
    for metric, _, suffix in variants:
        for learner in learners:
            label = learner + suffix
            metric_of[label] = metric
            metrics[label] = {}
            for pair in pairs:
                name = pair + suffix
                metrics[label][pair] = read_json(eval_dir / learner / f"{name}.json")
                if "intervals" not in metrics[label][pair]:
                    raise ValueError(f"{eval_dir / learner / name}.json: no intervals (rerun the evaluate stage)")
                if pr_dir is not None and metric == main_metric:
                    pr = pd.read_csv(pr_dir / learner / f"{name}.csv")
                    curves[pair][label] = (pr["recall"].to_numpy(), pr["precision"].to_numpy())
    return EvaluationResults(list(pairs), metrics, metric_of, main_metric, curves)


def load_runtime(
    fit_dir: Path, features_dir: Path, learners: Sequence[str], seasons: Sequence[str]
) -> dict[str, dict[str, Any]]:
    """learner -> fit seconds and training images (study Table 6), feature milliseconds per image
    averaged over `seasons` (Table 7), the descriptor dimension and what it was trained on."""
    runtime = {}
    for learner in learners:
        fit = read_json(fit_dir / f"{learner}.json")
        per_season = [read_json(features_dir / learner / f"{season}.json") for season in seasons]
        runtime[learner] = {
            "fit_seconds": fit["fit_seconds"],
            "n_train_images": fit["n_train_images"],
            "feature_ms_per_image": float(np.mean([s["ms_per_image"] for s in per_season])),
            "descriptor_dimension": per_season[0]["dimension"],
            "trained_on": fit["trained_on"],
        }
    return runtime


# what the network training record keeps of each network's fit record
TRAINING_RECORD = (
    "stop_reason",
    "converged",
    "epochs_run",
    "best_epoch",
    "best_validation_loss",
    "final_train_loss",
    "n_train_images",
    "n_validation_images",
    "images_seen",
    "training_seconds",
    "precision",
    "torch_threads",
)


def network_training(fit_dir: Path, learners: Sequence[str]) -> dict[str, dict[str, Any]]:
    """learner -> how its training ended, for the learners of `learners` that train in epochs, from
    the fit stage's records fit_dir/<learner>.json (the model's facts and the run's: time, threads)."""
    training = {}
    for learner in learners:
        info = read_json(fit_dir / f"{learner}.json")["info"]
        if "epochs_run" in info:
            training[learner] = {key: info[key] for key in TRAINING_RECORD}
    return training


def ordered(mapping: Mapping[str, Any], keys: Sequence[str], source: str) -> dict[str, Any]:
    """mapping's entries in the order of keys (the JSON files store their keys sorted)."""
    missing = [key for key in keys if key not in mapping]
    if missing:
        raise ValueError(f"{source}: no entry for {', '.join(missing)} (rerun the stage that writes it)")
    return {key: mapping[key] for key in keys}


def load_dataset(path: Path, seasons: Sequence[str]) -> dict[str, Any]:
    """The dataset record (seasonloop.data.datasets.dataset_record) with its seasons in `seasons`' order."""
    dataset = read_json(path)
    dataset["seasons"] = ordered(dataset["seasons"], seasons, str(path))
    return dataset


def load_runtime_record(path: Path, learners: Sequence[str]) -> dict[str, Any]:
    """The runtime record (load_runtime, as the summary stage wrote it) in `learners`' order."""
    return ordered(read_json(path), learners, str(path))


def load_training_seasons(path: Path, learners: Sequence[str]) -> dict[str, Any]:
    """The training-season record with its learners in `learners`' order and each learner's season
    lists in the order the ablation ran them; a skipped ablation's record as it is."""
    training = read_json(path)
    if "skipped" not in training:
        series = training["fraction_correct"]
        ordered(series, learners, str(path))  # every learner's main-distance series is there
        # each learner's series: its main distance's, then "<learner>@<metric>" of the extra ones
        names = [name for learner in learners for name in sorted(series) if name.partition("@")[0] == learner]
        training["fraction_correct"] = {
            name: ordered(series[name], training["season_sets"], str(path)) for name in names
        }
    return training


def load_autoencoder_descriptors(path: Path, learners: Sequence[str]) -> dict[str, Any]:
    """The auto-encoder descriptor record, its learners in `learners`' order (those it holds)."""
    autoencoders = read_json(path)
    return ordered(autoencoders, [learner for learner in learners if learner in autoencoders], str(path))
