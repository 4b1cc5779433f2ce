"""The report's sections about the learners themselves: the training-season effect, the CAE's
width, the study's figures and how each auto-encoder's training ended. Each takes result records
and figures and returns a seasonloop.reporting.html.Section."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd

from seasonloop.reporting.html import Block, Image, Png, Section, Table, Text
from seasonloop.reporting.summary import percent_cell, record_cell


def training_seasons_section(training_seasons: Mapping[str, Any], figure: Png) -> Section:
    """The training-season effect (study Figure 18): {"pair", "fraction_correct": {series: {seasons: value}},
    "notes": [...]}, a series being a learner under one distance ("<learner>@<metric>": an extra one), or {"skipped": why} when the run's seasons do not allow it."""
    if "skipped" in training_seasons:
        return Section(
            "Training-season effect", [Text(f"The training-season ablation was {training_seasons['skipped']}.")]
        )
    pair = training_seasons["pair"]
    intervals = training_seasons.get("intervals", {})
    table = pd.DataFrame.from_dict(
        {
            series: {
                seasons: percent_cell(value, intervals.get(series, {}).get(seasons))
                for seasons, value in values.items()
            }
            for series, values in training_seasons["fraction_correct"].items()
        },
        orient="index",
    )
    return Section(
        "Training-season effect",
        [
            *(Text(note) for note in training_seasons.get("notes", [])),
            *(
                Text(f"{learner} on {label}: {why}")
                for learner, by_label in training_seasons.get("not_fitted", {}).items()
                for label, why in by_label.items()
            ),
            Table(
                f"Fraction correct (%) on {pair} with its 95% interval, single-image matching, by the "
                "seasons trained on (<learner>@<metric>: under that distance)",
                table,
            ),
            Image(f"Training-season effect on {pair} (study Fig. 18)", figure),
        ],
    )


def cae_widths_section(record: Mapping[str, Any], figure: Png) -> Section:
    """The CAE width sweep (metrics/cae_widths.json, seasonloop.ablations.cae_widths): one row per width,
    or why it was skipped ({"skipped": why})."""
    if "skipped" in record:
        return Section("CAE width", [Text(f"The CAE width sweep was {record['skipped']}.")])
    pairs = record["pairs"]
    rows = {}
    for label, row in sorted(record["widths"].items(), key=lambda item: item[1]["width"]):
        rows[label] = {
            "channels": "/".join(map(str, row["channels"])),
            "converged": row["converged"],
            "stop": row["stop_reason"],
            "epochs": row["epochs_run"],
            "best val. loss": row["best_validation_loss"],
            "cos(output, input)": row["cosine_with_input"],
            **{f"output {pair}": record_cell(row["output_patchnorm"], pair) for pair in pairs},
            **{f"code {pair}": record_cell(row["code"], pair) for pair in pairs},
            **{f"output = raw {pair}": 100 * row["output_patchnorm"]["agreement_with_raw"][pair] for pair in pairs},
        }
    rows["raw_patchnorm"] = {f"output {pair}": record_cell(record["raw_patchnorm"], pair) for pair in pairs}
    table = pd.DataFrame.from_dict(rows, orient="index")
    return Section(
        "CAE width",
        [
            Text(
                "Table 5's CAE trained at fractions of its channel widths, each to its validation plateau (or "
                "marked not converged), single-image matching under " + record["metric"] + ". 'output': the "
                "patch-normalised output (the pipeline's CAE descriptor); 'code': the code vector; "
                "cos(output, input): mean cosine of the patch-normalised output with the patch-normalised "
                "input image; 'output = raw': the fraction of queries whose best match is raw_patchnorm's. "
                "Table 5 has no bottleneck, so a CAE that scores like raw_patchnorm and agrees with it may "
                "mostly measure the raw image."
            ),
            Table(
                "CAE width sweep (metrics/cae_widths.json): fraction correct (with its 95% interval) and "
                "agreement in %",
                table,
                float_format="{:.4g}",
            ),
            Image("Fraction correct against the CAE's width", figure),
        ],
    )


def figures_section(
    figures: Mapping[str, Png], autoencoder_descriptors: Mapping[str, Mapping[str, Any]], pairs: Sequence[str]
) -> Section:
    """The study's other figures (caption -> PNG) and the auto-encoder descriptor comparison table.

    autoencoder_descriptors[learner][descriptor] = {fraction_correct: {pair: value}, interval: {pair:
    {low, high}}} (metrics/autoencoder_descriptors.json); a cell shows the fraction correct with its
    interval, its columns in the run's order of pairs (the JSON's are sorted). Either may be empty
    when the learners they need are not in the run.
    """
    blocks: list[Block] = [Image(caption, png) for caption, png in figures.items()]
    if not figures:
        blocks.append(Text("No figure: no learner in learners draws one (a learner's class names its figures)."))
    if autoencoder_descriptors:
        cells = {
            (learner, descriptor): {pair: record_cell(record, pair) for pair in record["fraction_correct"]}
            for learner, by_descriptor in autoencoder_descriptors.items()
            for descriptor, record in by_descriptor.items()
        }
        table = pd.DataFrame.from_dict(cells, orient="index")
        table = table[[pair for pair in pairs if pair in table.columns]]  # the run's order, not the JSON's
        table.index.names = ["learner", "descriptor"]
        blocks.append(
            Table(
                "Auto-encoder descriptors (study Fig. 19): fraction correct (%) with its 95% interval along the route, "
                "single-image matching",
                table,
            )
        )
    return Section("The study's other figures", blocks)


def network_training_section(training: Mapping[str, Mapping[str, Any]]) -> Section:
    """How each network's training ended (the learners that train in epochs: the auto-encoders and
    the place-supervised network), training[learner][key] (metrics/network_training.json)."""
    if not training:
        return Section("Network training", [Text("No learner that trains in epochs is in learners.")])
    table = pd.DataFrame.from_dict(training, orient="index")
    return Section(
        "Network training",
        [
            Text(
                "Each network trains until its validation measure on held-out training places stops improving "
                "(stop reason 'plateau', converged), or stops at its maximum number of epochs or its "
                "wall-clock budget (not converged); the weights of the best validation measure are kept (the auto-encoders' loss; the place-supervised network's 1 - recall@1 across traverses). "
                "The auto-encoders' loss curves and reconstructions are under 'The study's other figures'."
            ),
            Table("Network training (metrics/network_training.json)", table, float_format="{:.4g}"),
        ],
    )
