"""Stage figures: the study's figures that need the fitted models.

Writes under plots/figures/: fig02_pca_projection.png (an image of one place in two seasons and
its projection on the first, condition-dependent principal components vs the kept ones),
fig12_patch_ica_filters.png, fig12b_global_ica_basis.png (the global ICA's basis images, the study
shows only patch filters), fig13_visual_words.png, fig19_autoencoder_descriptors.png (code vs
output vs patch-normalised output, single-image fraction correct), fig19b_autoencoder_reconstructions.png
(test inputs of every season beside the FAE's and CAE's reconstructions) and
fig19c_autoencoder_loss.png (training and validation loss per epoch) and metrics/autoencoder_descriptors.json
(per auto-encoder and descriptor: fraction correct per pair with its 95% interval along the route).
A figure whose learner is not in `learners` is left out, with a line saying so (seasonloop.reporting.figures).
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, param, stage_main
from _datasets import test_images
from _ground_truth import all_pair_truths, evaluation_context
from seasonloop.io import staged_dir, write_json
from seasonloop.params.seasons import available_pairs
from seasonloop.params.settings import EvaluateConfig
from seasonloop.reporting.figures import draw_figures


@stage_main
def main() -> None:
    params = load_params("learners", "data.seasons", "evaluate", "sequence", "features", "statistics")
    seasons = data_seasons(params)
    pairs = available_pairs(seasons, EvaluateConfig.from_params(params).pairs)
    context = evaluation_context(params, test_images(seasons), all_pair_truths(seasons), pairs)
    with staged_dir(Path("plots/figures")) as out:
        records = draw_figures(Path("models"), out, list(param(params, "learners")), context)
    for note in records.notes:
        print(f"figures: {note}")
    write_json(Path("metrics/autoencoder_descriptors.json"), records.autoencoder_descriptors)


if __name__ == "__main__":
    main()
