"""The study's figures that need fitted models, and the auto-encoder records drawn beside them.

Figure 2 (PCA projection), 12 and 13 (patch-ICA filters, visual words), 19 (auto-encoder
descriptors: code vs output vs patch-normalised output), 19b (reconstructions), 19c (loss per
epoch). A learner names the figures its fitted model draws (its class's `figures`, keys of FIGURES);
each is drawn when a learner of the run names it; the callers pass the models folder
(<models>/<learner>), the test images and the folder to draw into.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.data.ground_truth import PairTruth
from seasonloop.evaluation.autoencoder_descriptors import (
    autoencoder_descriptors,
    descriptor_evaluations,
    fraction_correct_record,
)
from seasonloop.evaluation.context import EvaluationContext
from seasonloop.models.core.autoencoder_learner import AE_DESCRIPTORS
from seasonloop.models.core.lookup import get_learner, load_learner
from seasonloop.params.seasons import pair_name
from seasonloop.plots import plot_image_grid, plot_loss_curves, plot_series

N_WORDS_SHOWN, N_EXAMPLES_SHOWN = 12, 10
FILTERS_PER_ROW = 16
N_RECONSTRUCTIONS = 2  # test places shown per season
N_BASIS_SHOWN, BASIS_PER_ROW = 32, 8  # global ICA basis images


@dataclass(frozen=True)
class FigureRecords:
    """What the figures leave besides PNGs: fraction correct with its interval per auto-encoder,
    descriptor and pair ([learner][descriptor], as fraction_correct_record gives it);
    one line per figure left out. (How each auto-encoder's training ended is the summary stage's
    metrics/network_training.json, from the fit records: seasonloop.reporting.results.)"""

    autoencoder_descriptors: dict[str, dict[str, dict[str, Any]]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


def same_place(truths: Mapping[tuple[str, str], PairTruth], first: str, second: str, row: int) -> int:
    """The test row of `second` that shows test row `row` of `first` (its exact match; the same row
    when the seasons are aligned, or when the truth knows of none)."""
    if first == second:
        return row
    exact = int(truths[(second, first)].exact[row])
    return exact if exact >= 0 else row


def pca_projection_figure(
    pca, test: Mapping[str, np.ndarray], truths: Mapping[tuple[str, str], PairTruth], seasons: Sequence[str], path: Path
) -> None:
    """Figure 2: the middle test place in two seasons and its projection on the first,
    condition-dependent principal components vs the kept ones."""
    # the study contrasts summer and winter; fall back to the first and last season present
    shown = ["summer" if "summer" in seasons else seasons[0], "winter" if "winter" in seasons else seasons[-1]]
    middle = len(test[shown[0]]) // 2
    rows_shown = [same_place(truths, shown[0], season, middle) for season in shown]
    places = [int(truths[(shown[1], shown[0])].query_places[middle]) if shown[0] != shown[1] else middle]
    first, kept = int(pca.params["n_discard"]), int(pca.params["n_keep"])
    images = np.stack([test[season][row] for season, row in zip(shown, rows_shown)])
    rows = [
        [image, low, high]
        for image, low, high in zip(
            images, pca.reconstruct(images, 0, first), pca.reconstruct(images, first, first + kept)
        )
    ]
    plot_image_grid(
        rows,
        path,
        row_labels=[f"{s}, place {places[0]}" if i == 0 else f"{s}, same place" for i, s in enumerate(shown)],
        col_labels=["image", f"PCs 1-{first}", f"PCs {first + 1}-{first + kept}"],
        title="Projection on the first vs the kept principal components (study Fig. 2)",
    )


def ica_figures(bovw, images: np.ndarray, season: str, out: Path) -> None:
    """Figures 12 (the patch-ICA filters) and 13 (patches of the most frequent visual words in `images`)."""
    filters = bovw.filters()
    plot_image_grid(
        [list(filters[i : i + FILTERS_PER_ROW]) for i in range(0, len(filters), FILTERS_PER_ROW)],
        out / "fig12_patch_ica_filters.png",
        title="ICA filters learned on image patches (study Fig. 12)",
    )
    examples = bovw.word_examples(images, N_WORDS_SHOWN, N_EXAMPLES_SHOWN)
    plot_image_grid(
        [[patch for patch in word if not np.isnan(patch).all()] for word in examples],
        out / "fig13_visual_words.png",
        row_labels=[f"word {i + 1}" for i in range(len(examples))],
        title=f"Patches of the {N_WORDS_SHOWN} most frequent visual words, {season} (study Fig. 13)",
    )


def descriptors_figure(record: Mapping[str, Mapping[str, Any]], pairs: Sequence[tuple[str, str]], path: Path) -> None:
    """Figure 19: fraction correct of each auto-encoder's descriptors (record[learner][descriptor], as
    fraction_correct_record gives it), one line per auto-encoder and pair."""
    plot_series(
        {
            f"{name} {pair_name(a, b)}": (
                list(AE_DESCRIPTORS),
                [100 * by_descriptor[d]["fraction_correct"][pair_name(a, b)] for d in AE_DESCRIPTORS],
            )
            for name, by_descriptor in record.items()
            for a, b in pairs
        },
        path,
        title="Auto-encoder descriptors (study Fig. 19)",
        xlabel="descriptor",
        ylabel="fraction correct (%)",
    )


def autoencoder_figures(
    models_dir: Path, learners: Sequence[str], context: EvaluationContext, out: Path
) -> dict[str, dict[str, dict[str, Any]]]:
    """Figures 19, 19b and 19c of the fitted auto-encoders models_dir/<learner> of `learners` (at least
    one); record[learner][descriptor] = fraction_correct_record of its single-image evaluations."""
    test = context.test
    seasons = list(test)
    record: dict[str, dict[str, dict[str, Any]]] = {}
    losses: dict[str, dict[str, list[float]]] = {}
    shown_places = np.linspace(0, len(test[seasons[0]]) - 1, N_RECONSTRUCTIONS + 2).astype(int)[1:-1]
    reconstructions = {season: [list(test[season][shown_places])] for season in seasons}
    for name in learners:
        # loaded one at a time: loading sets the learner's torch threads for its describe
        learner = load_learner(models_dir / name)
        info = learner.fit_info
        assert info is not None, f"{models_dir / name}: a saved learner without its fit record"
        losses[name] = {"train": info["loss_per_epoch"], "validation": info["validation_loss_per_epoch"]}
        described = autoencoder_descriptors(learner, context)
        for season in seasons:
            reconstructions[season].append(
                list(described["output"][season][shown_places].reshape(-1, *test[season].shape[1:]))
            )
        evaluations = descriptor_evaluations(described, context)
        record[name] = {
            descriptor: fraction_correct_record(by_pair, context.statistics)
            for descriptor, by_pair in evaluations.items()
        }
    descriptors_figure(record, context.pairs, out / "fig19_autoencoder_descriptors.png")
    # rows: a season's input images, then each auto-encoder's reconstructions of them
    plot_image_grid(
        [images for season in seasons for images in zip(*reconstructions[season])],
        out / "fig19b_autoencoder_reconstructions.png",
        row_labels=[f"{season}, test image {index}" for season in seasons for index in shown_places],
        col_labels=["input", *(f"{name} output" for name in learners)],
        title="Test images and the auto-encoders' reconstructions",
    )
    plot_loss_curves(
        losses,
        out / "fig19c_autoencoder_loss.png",
        title="Auto-encoder training: loss per epoch (validation on held-out training places)",
    )
    return record


def ica_basis_figure(ica, path: Path) -> None:
    """The global ICA's basis images: columns of its mixing matrix (the pseudo-inverse of the
    unmixing components, so that image - mean = sum of sources x basis), those that carry the most
    pixel variance (largest norm: the sources have unit variance) first."""
    components = np.asarray(ica.estimator.components_, dtype=np.float64)
    mixing = np.linalg.pinv(components)
    order = np.argsort(-np.linalg.norm(mixing, axis=0), kind="stable")[:N_BASIS_SHOWN]
    height, width = ica.image_shape
    basis = [mixing[:, i].reshape(height, width) for i in order]
    plot_image_grid(
        [basis[i : i + BASIS_PER_ROW] for i in range(0, len(basis), BASIS_PER_ROW)],
        path,
        title=f"Global ICA basis images: {len(basis)} of {len(components)}, most pixel variance first",
    )


def one_model(draw: Callable[[Any, EvaluationContext, Path], None]) -> FigureDrawer:
    """A figure of one learner's fitted model: draw(learner, context, out)."""

    def drawn(models_dir: Path, names: Sequence[str], context: EvaluationContext, out: Path) -> dict:
        if len(names) > 1:
            raise ValueError(f"figures: {', '.join(names)} each name one figure that has room for one learner")
        draw(load_learner(models_dir / names[0]), context, out)
        return {}

    return drawn


def _pca_projection(pca, context: EvaluationContext, out: Path) -> None:
    seasons = list(context.test)
    pca_projection_figure(pca, context.test, context.truths, seasons, out / "fig02_pca_projection.png")


def _patch_ica(bovw, context: EvaluationContext, out: Path) -> None:
    first = next(iter(context.test))
    ica_figures(bovw, context.test[first], first, out)


# a figure a learner may name in its `figures` -> (what it is, for the note when no learner of the run
# draws it; how it is drawn from the models of the learners that name it: a record per learner)
FigureDrawer = Callable[[Path, Sequence[str], EvaluationContext, Path], dict]
FIGURES: dict[str, tuple[str, FigureDrawer]] = {
    "pca_projection": ("Figure 2", one_model(_pca_projection)),
    "ica_basis": (
        "the global ICA basis",
        one_model(lambda ica, context, out: ica_basis_figure(ica, out / "fig12b_global_ica_basis.png")),
    ),
    "patch_ica": ("Figures 12 and 13", one_model(_patch_ica)),
    "autoencoder": ("Figures 19, 19b, 19c", autoencoder_figures),
}


def figure_learners(learners: Sequence[str]) -> dict[str, list[str]]:
    """Each figure of FIGURES -> the learners of `learners` that name it (their classes' `figures`)."""
    named = {name: get_learner(name).figures for name in learners}
    unknown = sorted({figure for figures in named.values() for figure in figures} - set(FIGURES))
    if unknown:
        raise ValueError(f"figures: a learner names {', '.join(unknown)}, not a figure (known: {', '.join(FIGURES)})")
    return {figure: [name for name in learners if figure in named[name]] for figure in FIGURES}


def draw_figures(models_dir: Path, out: Path, learners: Sequence[str], context: EvaluationContext) -> FigureRecords:
    """Every figure into `out` that a learner of `learners` names, from the models of
    models_dir/<learner>; the context's test images are every season's."""
    notes, record = [], {}
    for figure, names in figure_learners(learners).items():
        title, draw = FIGURES[figure]
        if not names:
            notes.append(f"no learner in learners draws {title}")
            continue
        record.update(draw(models_dir, names, context, out))
    return FigureRecords(record, notes)
