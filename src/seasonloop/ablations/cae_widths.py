"""The CAE width sweep: Table 5's convolutional auto-encoder at fractions of its channel widths.

Table 5's network costs ~9 GMAC per 32x64 image forward, which no 2-core CPU trains to a plateau
in the time a run has, so the default run uses a narrower copy (params.yaml `cae.channels`). This
sweep tells whether that matters: for each width (a fraction of Table 5's [96, 256, 384] channels)
a CAE with the `cae` section's other settings is trained to its validation plateau (or marked not
converged), and for its code and its patch-normalised output it records the fraction correct on
each pair, and how close it is to the raw image:

- cosine_with_input: the mean cosine between the patch-normalised output and the patch-normalised
  input image (1: the network has learned the identity, up to patch normalisation);
- agreement_with_raw: the fraction of queries whose best match equals raw_patchnorm's best match
  under the same distance (high: the descriptor ranks places as the raw image does).

Table 5 has no bottleneck (its code holds 8 x 16 x 384 values, 24x the 2,048 input pixels), so a
well-trained CAE can score well by reproducing the image; these two columns say how much of a
CAE row is the raw image.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.evaluation.autoencoder_descriptors import (
    autoencoder_descriptors,
    descriptor_evaluations,
    fraction_correct_record,
)
from seasonloop.evaluation.blocks import best_columns
from seasonloop.evaluation.context import EvaluationContext
from seasonloop.io import staged_file, write_json
from seasonloop.plots import percent_bands, plot_message, plot_series
from seasonloop.reporting.summary import record_cell

TABLE5_CHANNELS = (96, 256, 384)
DESCRIPTORS = ("output_patchnorm", "code")
# what the record keeps of each width's fit info, and of its run: training_seconds (None for a
# reused width: its model holds no timing, its time is fit@cae's, in metrics/fit/cae.json)
FIT_RECORD = (
    "converged",
    "stop_reason",
    "epochs_run",
    "best_epoch",
    "best_validation_loss",
    "n_train_images",
    "n_validation_images",
    "images_seen",
    "precision",
    "n_parameters",
)


def width_channels(width: float) -> list[int]:
    """Table 5's channels scaled by `width` (at least 1 each)."""
    if isinstance(width, bool) or not isinstance(width, (int, float)) or not 0 < width <= 1:
        raise ValueError(
            f"cae_widths.widths: each width must be a fraction of Table 5's channels in (0, 1], got {width!r}"
        )
    return [max(1, round(width * channels)) for channels in TABLE5_CHANNELS]


def width_label(width: float) -> str:
    """'1/8' for 0.125, '1' for 1.0."""
    return str(Fraction(width).limit_denominator(256))


def agreement(
    descriptors: tuple[np.ndarray, np.ndarray], reference: tuple[np.ndarray, np.ndarray], metric: str
) -> float:
    """Fraction of queries whose best database match is the same under both descriptors
    ((database, queries) each), with the same distance."""
    return float(np.mean(best_columns(*descriptors, metric) == best_columns(*reference, metric)))


def mean_cosine(first: np.ndarray, second: np.ndarray) -> float:
    """Mean over rows of the cosine between first[i] and second[i] (zero rows count as 0)."""
    first, second = np.asarray(first, np.float64), np.asarray(second, np.float64)
    norms = np.linalg.norm(first, axis=1) * np.linalg.norm(second, axis=1)
    cosines = np.divide(np.sum(first * second, axis=1), norms, out=np.zeros(len(first)), where=norms > 0)
    return float(np.mean(cosines))


def describe_width(learner, raw_described: Mapping[str, np.ndarray], context: EvaluationContext) -> dict[str, Any]:
    """Fraction correct with its interval, agreement with raw_patchnorm (raw_described[season]: its
    descriptors of test[season]) per descriptor and pair, and the cosine of the patch-normalised
    output with the patch-normalised input, of a fitted CAE."""
    described = autoencoder_descriptors(learner, context)
    cosines = [mean_cosine(described["output_patchnorm"][season], raw_described[season]) for season in context.test]
    record: dict[str, Any] = {"cosine_with_input": float(np.mean(cosines))}
    evaluations = descriptor_evaluations(described, context, DESCRIPTORS)
    metric = context.evaluate.metric
    for descriptor in DESCRIPTORS:
        ours = described[descriptor]
        record[descriptor] = {
            **fraction_correct_record(evaluations[descriptor], context.statistics),
            "agreement_with_raw": {
                f"{a}-{b}": agreement((ours[a], ours[b]), (raw_described[a], raw_described[b]), metric)
                for a, b in context.pairs
            },
        }
    return record


def run_width_sweep(
    widths: Sequence[float],
    new_cae: Callable[[list[int]], Any],
    raw,
    training_set: tuple[np.ndarray, np.ndarray],
    context: EvaluationContext,
    fitted: Mapping[float, Any] | None = None,
) -> dict[str, Any]:
    """The sweep's record: new_cae(channels) gives an unfitted CAE, trained on training_set
    (images, place ids); raw is a fitted raw_patchnorm, also evaluated as the reference row.
    fitted[width]: a CAE already trained at that width with the same settings, images and seed
    (the pipeline's own fit@cae), evaluated without training it again (its training_seconds: None)."""
    fitted = dict(fitted or {})
    images, image_places = training_set
    raw_test = {season: raw.describe(images) for season, images in context.test.items()}
    record: dict[str, Any] = {
        "pairs": [f"{a}-{b}" for a, b in context.pairs],
        "metric": context.evaluate.metric,
        "raw_patchnorm": fraction_correct_record(
            descriptor_evaluations({"raw": raw_test}, context, ("raw",))["raw"], context.statistics
        ),
        "widths": {},
    }
    for width in widths:
        channels = width_channels(width)
        if width in fitted:
            learner, seconds = fitted[width], None
        else:
            learner = new_cae(channels)
            seconds = learner.fit(images, progress=True, places=image_places)["training_seconds"]
        record["widths"][width_label(width)] = {
            "width": float(width),
            "channels": channels,
            "reused": width in fitted,
            **{key: learner.fit_info[key] for key in FIT_RECORD},
            "training_seconds": seconds,
            **describe_width(learner, raw_test, context),
        }
    return record


def by_width(record: Mapping[str, Any]) -> list[tuple[str, Mapping[str, Any]]]:
    """(label, row) of every width, narrowest first (a JSON record's keys come back sorted as text)."""
    return sorted(record["widths"].items(), key=lambda item: item[1]["width"])


def width_table(record: Mapping[str, Any]) -> str:
    """The sweep as a markdown table: one row per width, fraction correct (%) per pair for the
    patch-normalised output and the code, agreement with raw_patchnorm, fit facts."""
    pairs = record["pairs"]
    header = (
        ["width", "channels", "converged (epochs)", "best val. loss", "cos(out, in)"]
        + [f"out {pair}" for pair in pairs]
        + [f"code {pair}" for pair in pairs]
        + [f"out = raw {pair}" for pair in pairs]
    )
    rows = []
    for label, row in by_width(record):
        converged = f"{'yes' if row['converged'] else 'no: ' + row['stop_reason']} ({row['epochs_run']})"
        rows.append(
            [
                label,
                "/".join(map(str, row["channels"])),
                converged,
                f"{row['best_validation_loss']:.5f}",
                f"{row['cosine_with_input']:.3f}",
            ]
            + [record_cell(row["output_patchnorm"], p) for p in pairs]
            + [record_cell(row["code"], p) for p in pairs]
            + [f"{100 * row['output_patchnorm']['agreement_with_raw'][p]:.1f}" for p in pairs]
        )
    rows.append(
        ["raw_patchnorm", "", "", "", "1.000"]
        + [record_cell(record["raw_patchnorm"], p) for p in pairs]
        + [""] * len(pairs)
        + ["100.0"] * len(pairs)
    )
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


SKIPPED = "skipped: cae_widths.widths is empty"


def write_skipped_sweep(json_path: Path, figure_path: Path, table_path: Path) -> None:
    """The sweep's three outputs when cae_widths.widths is empty: each says it was skipped (a
    declared output must exist; the report shows the reason)."""
    write_json(json_path, {"skipped": SKIPPED})
    plot_message(figure_path, f"CAE width sweep {SKIPPED}")
    with staged_file(table_path) as staged:
        staged.write_text(f"The CAE width sweep was {SKIPPED}.\n")


def write_width_sweep(record: Mapping[str, Any], json_path: Path, figure_path: Path, table_path: Path) -> None:
    """metrics/cae_widths.json, its figure (fraction correct against width) and its markdown table."""
    write_json(json_path, record)
    labels = [label for label, _ in by_width(record)]
    series = {
        f"{'output' if descriptor == 'output_patchnorm' else descriptor} {pair}": (
            labels,
            [100 * record["widths"][label][descriptor]["fraction_correct"][pair] for label in labels],
        )
        for descriptor in DESCRIPTORS
        for pair in record["pairs"]
    }
    series.update(
        {
            f"raw_patchnorm {pair}": (labels, [100 * record["raw_patchnorm"]["fraction_correct"][pair]] * len(labels))
            for pair in record["pairs"]
        }
    )
    bands = {
        f"{'output' if descriptor == 'output_patchnorm' else descriptor} {pair}": percent_bands(
            [record["widths"][label][descriptor]["interval"][pair] for label in labels]
        )
        for descriptor in DESCRIPTORS
        for pair in record["pairs"]
    }
    plot_series(
        series,
        figure_path,
        title=f"CAE width (fraction of Table 5's channels), single image, {record['metric']}; bars: 95% intervals",
        xlabel="width",
        ylabel="fraction correct (%)",
        bands=bands,
    )
    with staged_file(Path(table_path)) as tmp:
        tmp.write_text(width_table(record))
