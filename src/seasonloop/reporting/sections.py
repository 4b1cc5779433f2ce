"""The study's report sections, each built from the pipeline's result data as read from its JSON
files (seasonloop.reporting.results) and the PNG figures the other stages drew.

Knows nothing of DVC or params.yaml: every builder takes plain Python data and PNG paths or bytes
and returns a seasonloop.reporting.html.Section.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from seasonloop.evaluation.matchers import MATCHERS
from seasonloop.reporting.html import Block, Image, Png, Section, Table, Text, Thumbnails
from seasonloop.reporting.summary import fraction_correct_table, study_table

MATCHER_NAMES = {"single": "single-image matching", "sequence": "sequence matching (SeqSLAM)"}
RECALL_COLUMNS = {
    "recall_at_1": "recall@1",
    "recall_at_5": "recall@5",
    "recall_at_10": "recall@10",
    "recall_at_100_precision": "recall at 100% precision",
    "auc_pr": "AUC-PR",
    "auc_pr_vpr_tutorial": "AUC-PR (VPR_Tutorial)",
}
DATASET_COLUMNS = {"frames": "places (frames)", "train": "train", "train_augmented": "train, augmented", "test": "test"}
RUNTIME_COLUMNS = {
    "fit_seconds": "fit (s)",
    "n_train_images": "training images",
    "feature_ms_per_image": "features (ms / image)",
    "descriptor_dimension": "descriptor dimension",
}


def _labelled(frame: pd.DataFrame, columns: Mapping[str, str]) -> pd.DataFrame:
    """The known columns first, in the order of `columns` and renamed by it, then any others."""
    order = [key for key in columns if key in frame] + [key for key in frame if key not in columns]
    return frame[order].rename(columns=columns)


def dataset_section(dataset: Mapping[str, Any], preview: Png) -> Section:
    """Table 3 of the study (places, train, test per season; what the split dropped) and a preview."""
    seasons = _labelled(pd.DataFrame.from_dict(dataset["seasons"], orient="index"), DATASET_COLUMNS)
    route = pd.DataFrame({"places": {
        "dropped from test: tunnels": dataset["dropped_tunnel"],
        "dropped from test: station stops": dataset["dropped_stop"],
        "gap between train and test": dataset["gap"],
    }})
    blocks: list[Block] = [Table("Images per season", seasons), Table("Places left out of every season", route)]
    if "detection" in dataset:
        detection = pd.DataFrame.from_dict(dataset["detection"], orient="index")
        blocks.append(Table("Tunnel and stop detection against the route's true tunnels and stops", detection,
                            float_format="{:.3f}"))
    blocks.append(Image("The same places in every season", preview))
    return Section("Dataset", blocks)


def _beside_study(ours: pd.DataFrame, study: pd.DataFrame) -> pd.DataFrame:
    """Columns (pair, ours) and (pair, study) side by side; a pair the study gives no number for has ours only.

    The study's numbers are whole percentages, so they are shown without decimals.
    """
    columns = {}
    for pair in ours.columns:
        columns[(pair, "ours")] = ours[pair]
        if study[pair].notna().any():
            columns[(pair, "study (S)")] = study[pair].map(lambda value: "–" if np.isnan(value) else f"{value:.0f}")
    return pd.DataFrame(columns)


def fraction_correct_section(
    results: Mapping[str, Mapping[str, Mapping[str, float]]],
    methods: Sequence[str],
    matchers: Sequence[str],
    pairs: Sequence[str],
    figure: Png,
    extra_metrics: Sequence[str] = (),
    extra_figures: Mapping[str, Png] | None = None,
) -> Section:
    """Fraction correct beside the study's numbers per metric and matcher, the gain of sequence
    matching, recall metrics.

    results[label][pair] is the pair's metrics dict (metrics/eval JSON), label = method + "@<metric>"
    for an extra metric (none for the main one) + MATCHERS[matcher]; extra_figures[metric] is the
    fraction-correct figure of an extra metric.
    """
    for matcher in matchers:
        if matcher not in MATCHERS:
            raise ValueError(f"unknown matcher '{matcher}' (known: {', '.join(MATCHERS)})")
    blocks: list[Block] = [Text(
        "Fraction of correct matches: correct best matches / queries, in %. Pairs are database-queries; "
        "(S) marks the study's numbers, given for single-image matching on three pairs only. "
        "Rows named learner@metric use that distance (evaluate.extra_metrics) instead of the main one "
        "(evaluate.metric). FastICA's unmixing is orthogonal in the whitened space, so under cosine and "
        "Euclidean distances ICA matches exactly like whitened PCA with as many components (pca_whiten): "
        "a gain of ICA over PCA there comes from whitening and keeping the first components, not from "
        "independence. Under L1 (cityblock) the rotation matters, so ica@cityblock against "
        "pca_whiten@cityblock measures what independence adds.")]
    suffixes = {"": "", **{metric: f"@{metric}" for metric in extra_metrics}}
    for metric, metric_suffix in suffixes.items():
        ours = {}
        for matcher in matchers:
            labels = [method + metric_suffix + MATCHERS[matcher] for method in methods]
            ours[matcher] = fraction_correct_table({label: results[label] for label in labels}, pairs)
            distance = f", {metric} distance" if metric else ""
            blocks.append(Table(f"Fraction correct (%), {MATCHER_NAMES[matcher]}{distance}",
                                _beside_study(ours[matcher], study_table(labels, pairs))))
        if "single" in ours and "sequence" in ours:
            gain = pd.DataFrame(ours["sequence"].to_numpy() - ours["single"].to_numpy(),
                                index=[method + metric_suffix for method in methods], columns=list(pairs))
            blocks.append(Table("What sequence matching adds: fraction correct of method+seq minus method "
                                "(percentage points)", gain, float_format="{:+.1f}"))
    recall = pd.DataFrame.from_dict(
        {(pair, label): {key: 100 * results[label][pair][key] for key in RECALL_COLUMNS if key in results[label][pair]}
         for pair in pairs for label in results}, orient="index").rename(columns=RECALL_COLUMNS)
    recall.index.names = ["pair", "method"]
    blocks.append(Table("Recall@N, recall at 100% precision and area under the PR curve, all in % (AUC-PR in the "
                        "study's convention, where recall reaches 100%; AUC-PR (VPR_Tutorial) with recall = TP / "
                        "queries, which ends at the fraction correct)", recall))
    blocks.append(Image("Fraction of correct matches per pair; diamonds: the study's numbers", figure))
    for metric, png in (extra_figures or {}).items():
        blocks.append(Image(f"Fraction of correct matches per pair, {metric} distance", png))
    return Section("Fraction correct", blocks)


def pr_section(curves: Mapping[str, Png], landmarks: pd.DataFrame | None = None) -> Section:
    """One PR figure per pair (pair -> PNG), and the study's PR landmarks beside ours
    (seasonloop.reporting.summary.pr_landmarks_table) when given."""
    blocks: list[Block] = [
        Text("Queries sorted by the confidence of their best match; at each distinct confidence the queries "
             "at least that confident are accepted (tied queries together): at full recall, precision equals "
             "the fraction correct.")]
    if landmarks is not None:
        blocks.append(Table("The study's precision-recall landmarks beside ours (%), single-image matching",
                            landmarks))
    blocks += [Image(f"Precision-recall, {pair} (database-queries)", png) for pair, png in curves.items()]
    return Section("Precision-recall curves", blocks)


def similarity_section(matrices: Mapping[str, Mapping[str, Png]], pairs: Sequence[str]) -> Section:
    """Thumbnails of the similarity matrices, matrices[method][pair] -> PNG, learners x pairs."""
    return Section("Similarity matrices", [Thumbnails(
        "Query x database similarity, single-image matching (true matches on the diagonal)",
        list(matrices), list(pairs), [[matrices[method][pair] for pair in pairs] for method in matrices])])


def runtime_section(runtime: Mapping[str, Mapping[str, float]]) -> Section:
    """Fit time (study Table 6) and feature time per image (Table 7), runtime[method][key]."""
    table = _labelled(pd.DataFrame.from_dict(runtime, orient="index"), RUNTIME_COLUMNS)
    return Section("Runtimes", [Table("Fit time (study Table 6), feature time per test image (Table 7)",
                                      table, float_format="{:.4g}")])


def training_seasons_section(training_seasons: Mapping[str, Any], figure: Png) -> Section:
    """The training-season effect (study Figure 18): {"pair", "fraction_correct": {method: {seasons: value}},
    "notes": [...]}, or {"skipped": why} when the run's seasons do not allow it."""
    if "skipped" in training_seasons:
        return Section("Training-season effect", [Text(f"The training-season ablation was {training_seasons['skipped']}.")])
    pair = training_seasons["pair"]
    table = 100 * pd.DataFrame.from_dict(training_seasons["fraction_correct"], orient="index")
    return Section("Training-season effect", [
        *(Text(note) for note in training_seasons.get("notes", [])),
        Table(f"Fraction correct (%) on {pair}, single-image matching, by the seasons trained on", table),
        Image(f"Training-season effect on {pair} (study Fig. 18)", figure)])


def cae_widths_section(record: Mapping[str, Any], figure: Png) -> Section:
    """The CAE width sweep (metrics/cae_widths.json, seasonloop.ablations.cae_widths): one row per width."""
    pairs = record["pairs"]
    rows = {}
    for label, row in sorted(record["widths"].items(), key=lambda item: item[1]["width"]):
        rows[label] = {"channels": "/".join(map(str, row["channels"])),
                       "converged": row["converged"], "stop": row["stop_reason"], "epochs": row["epochs_run"],
                       "best val. loss": row["best_validation_loss"], "cos(output, input)": row["cosine_with_input"],
                       **{f"output {pair}": 100 * row["output_patchnorm"]["fraction_correct"][pair] for pair in pairs},
                       **{f"code {pair}": 100 * row["code"]["fraction_correct"][pair] for pair in pairs},
                       **{f"output = raw {pair}": 100 * row["output_patchnorm"]["agreement_with_raw"][pair]
                          for pair in pairs}}
    rows["raw_patchnorm"] = {f"output {pair}": 100 * record["raw_patchnorm"]["fraction_correct"][pair] for pair in pairs}
    table = pd.DataFrame.from_dict(rows, orient="index")
    return Section("CAE width", [
        Text("Table 5's CAE trained at fractions of its channel widths, each to its validation plateau (or "
             "marked not converged), single-image matching under " + record["metric"] + ". 'output': the "
             "patch-normalised output (the pipeline's CAE descriptor); 'code': the code vector; "
             "cos(output, input): mean cosine of the patch-normalised output with the patch-normalised "
             "input image; 'output = raw': the fraction of queries whose best match is raw_patchnorm's. "
             "Table 5 has no bottleneck, so a CAE that scores like raw_patchnorm and agrees with it may "
             "mostly measure the raw image."),
        Table("CAE width sweep (metrics/cae_widths.json): fraction correct and agreement in %", table,
              float_format="{:.4g}"),
        Image("Fraction correct against the CAE's width", figure)])


def figures_section(figures: Mapping[str, Png], autoencoder_descriptors: Mapping[str, Mapping[str, Mapping[str, float]]]) -> Section:
    """The study's other figures (caption -> PNG) and the auto-encoder descriptor comparison table.

    autoencoder_descriptors[method][descriptor][pair] is a fraction correct. Either may be empty
    when the learners they need are not in the run.
    """
    blocks: list[Block] = [Image(caption, png) for caption, png in figures.items()]
    if not figures:
        blocks.append(Text("No figure: the learners they show (pca, ica_bovw, fae, cae) are not in learners."))
    if autoencoder_descriptors:
        table = 100 * pd.DataFrame.from_dict(
            {(method, descriptor): values for method, by_descriptor in autoencoder_descriptors.items()
             for descriptor, values in by_descriptor.items()}, orient="index")
        table.index.names = ["method", "descriptor"]
        blocks.append(Table("Auto-encoder descriptors (study Fig. 19): fraction correct (%), single-image matching", table))
    return Section("The study's other figures", blocks)


def autoencoder_training_section(training: Mapping[str, Mapping[str, Any]]) -> Section:
    """How each auto-encoder's training ended, training[method][key] (metrics/autoencoder_training.json)."""
    if not training:
        return Section("Auto-encoder training", [Text("No auto-encoder (fae, cae) is in learners.")])
    table = pd.DataFrame.from_dict(training, orient="index")
    return Section("Auto-encoder training", [
        Text("Each auto-encoder trains until its loss on held-out training places stops improving "
             "(stop reason 'plateau', converged), or stops at its maximum number of epochs or its "
             "wall-clock budget (not converged); the weights of the lowest validation loss are kept. "
             "The loss curves and reconstructions are under 'The study's other figures'."),
        Table("Auto-encoder training (metrics/autoencoder_training.json)", table, float_format="{:.4g}")])


def parameters_section(params_text: str) -> Section:
    """The parameter file that produced the report, verbatim."""
    return Section("Parameters", [Text("The parameters that produced this report:"), Text(params_text, preformatted=True)])
