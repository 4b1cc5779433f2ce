"""Stage figures: the study's figures that need the fitted models.

Writes under plots/figures/: fig02_pca_projection.png (an image of one place in two seasons and
its projection on the first, condition-dependent principal components vs the kept ones),
fig12_patch_ica_filters.png, fig13_visual_words.png, fig19_autoencoder_descriptors.png (code vs
output vs patch-normalised output, single-image fraction correct), fig19b_autoencoder_reconstructions.png
(test inputs of every season beside the FAE's and CAE's reconstructions) and
fig19c_autoencoder_loss.png (training and validation loss per epoch); metrics/autoencoder_descriptors.json
and metrics/autoencoder_training.json (how each auto-encoder's training ended).
A figure whose learner is not in `learners` is left out, with a line saying so.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from _common import data_seasons, load_params, param, stage_main, test_images, test_places

from seasonloop.config import available_pairs, pair_name
from seasonloop.evaluation import match_pair
from seasonloop.io import staged_dir, write_json
from seasonloop.models.registry import load_learner
from seasonloop.patchnorm import patch_normalise
from seasonloop.plots import plot_image_grid, plot_loss_curves, plot_series

AE_DESCRIPTORS = ("code", "output", "output_patchnorm")
AUTOENCODERS = ("fae", "cae")
N_WORDS_SHOWN, N_EXAMPLES_SHOWN = 12, 10
FILTERS_PER_ROW = 16
N_RECONSTRUCTIONS = 2  # test places shown per season
# what metrics/autoencoder_training.json keeps of each auto-encoder's fit info
TRAINING_RECORD = ("stop_reason", "converged", "epochs_run", "best_epoch", "best_validation_loss", "final_train_loss",
                   "n_train_images", "n_validation_images", "images_seen", "training_seconds", "precision",
                   "torch_threads")


def autoencoder_descriptors(learner, test: dict[str, np.ndarray], batch_size: int) -> dict[str, dict[str, np.ndarray]]:
    """described[descriptor][season] for the three auto-encoder descriptors.

    One forward pass gives the code and the output, and the patch-normalised output is derived
    from the output: the CAE costs ~9 GMAC per image.
    """
    described: dict[str, dict[str, np.ndarray]] = {descriptor: {} for descriptor in AE_DESCRIPTORS}
    for season, images in test.items():
        code, output = learner.describe_code_and_output(images, batch_size, progress=True)
        described["code"][season] = code
        described["output"][season] = output
        described["output_patchnorm"][season] = patch_normalise(
            output.reshape(images.shape), learner.params["patch_size"]).reshape(len(images), -1)
    return described


@stage_main
def main() -> None:
    params = load_params("learners", "data.seasons", "evaluate", "sequence", "features")
    seasons = data_seasons(params)
    test = test_images(seasons)
    places = test_places()
    # the study's Figure 2 contrasts summer and winter; fall back to the first and last season present
    shown = ["summer" if "summer" in seasons else seasons[0], "winter" if "winter" in seasons else seasons[-1]]
    middle = len(places) // 2

    learners = list(param(params, "learners"))
    # each figure needs one learner's fitted model: draw those whose learner is in this run
    with staged_dir(Path("plots/figures")) as out:
        if "pca" in learners:
            pca = load_learner(Path("models/pca"))
            first, kept = int(pca.params["n_discard"]), int(pca.params["n_keep"])
            images = np.stack([test[season][middle] for season in shown])
            rows = [[image, low, high] for image, low, high in zip(
                images, pca.reconstruct(images, 0, first), pca.reconstruct(images, first, first + kept))]
            plot_image_grid(rows, out / "fig02_pca_projection.png", row_labels=[f"{s}, place {places[middle]}" for s in shown],
                            col_labels=["image", f"PCs 1-{first}", f"PCs {first + 1}-{first + kept}"],
                            title="Projection on the first vs the kept principal components (study Fig. 2)")
        else:
            print("figures: pca is not in learners: no Figure 2")

        if "ica_bovw" in learners:
            bovw = load_learner(Path("models/ica_bovw"))
            filters = bovw.filters()
            plot_image_grid([list(filters[i:i + FILTERS_PER_ROW]) for i in range(0, len(filters), FILTERS_PER_ROW)],
                            out / "fig12_patch_ica_filters.png", title="ICA filters learned on image patches (study Fig. 12)")
            examples = bovw.word_examples(test[seasons[0]], N_WORDS_SHOWN, N_EXAMPLES_SHOWN)
            plot_image_grid([[patch for patch in word if not np.isnan(patch).all()] for word in examples],
                            out / "fig13_visual_words.png", row_labels=[f"word {i + 1}" for i in range(len(examples))],
                            title=f"Patches of the {N_WORDS_SHOWN} most frequent visual words, {seasons[0]} (study Fig. 13)")
        else:
            print("figures: ica_bovw is not in learners: no Figures 12 and 13")

        pairs = available_pairs(seasons, param(params, "evaluate.pairs"))
        autoencoders = [method for method in AUTOENCODERS if method in learners]
        fraction_correct: dict[str, dict[str, dict[str, float]]] = {}
        training: dict[str, dict] = {}
        losses: dict[str, dict[str, list[float]]] = {}
        shown_places = np.linspace(0, len(places) - 1, N_RECONSTRUCTIONS + 2).astype(int)[1:-1]
        reconstructions = {season: [list(test[season][shown_places])] for season in seasons}
        for method in autoencoders:
            learner = load_learner(Path("models") / method)
            fraction_correct[method] = {}
            training[method] = {key: learner.fit_info[key] for key in TRAINING_RECORD}
            losses[method] = {"train": learner.fit_info["loss_per_epoch"],
                              "validation": learner.fit_info["validation_loss_per_epoch"]}
            described = autoencoder_descriptors(learner, test, int(param(params, "features.batch_size")))
            for season in seasons:
                reconstructions[season].append(list(
                    described["output"][season][shown_places].reshape(-1, *test[season].shape[1:])))
            for descriptor in AE_DESCRIPTORS:
                fraction_correct[method][descriptor] = {
                    pair_name(a, b): match_pair(described[descriptor][a], described[descriptor][b], places, places, "single",
                                                param(params, "evaluate"), param(params, "sequence"))[0]["fraction_correct"]
                    for a, b in pairs}
        if autoencoders:
            plot_series({f"{method} {pair_name(a, b)}": (list(AE_DESCRIPTORS),
                                                         [100 * fraction_correct[method][d][pair_name(a, b)] for d in AE_DESCRIPTORS])
                         for method in autoencoders for a, b in pairs},
                        out / "fig19_autoencoder_descriptors.png", title="Auto-encoder descriptors (study Fig. 19)",
                        xlabel="descriptor", ylabel="fraction correct (%)")
            # rows: a season's input images, then each auto-encoder's reconstructions of them
            plot_image_grid([images for season in seasons for images in zip(*reconstructions[season])],
                            out / "fig19b_autoencoder_reconstructions.png",
                            row_labels=[f"{season}, place {places[index]}" for season in seasons for index in shown_places],
                            col_labels=["input", *(f"{method} output" for method in autoencoders)],
                            title="Test images and the auto-encoders' reconstructions")
            plot_loss_curves(losses, out / "fig19c_autoencoder_loss.png",
                             title="Auto-encoder training: loss per epoch (validation on held-out training places)")
        else:
            print("figures: neither fae nor cae is in learners: no Figures 19, 19b, 19c")
    write_json(Path("metrics/autoencoder_descriptors.json"), fraction_correct)
    write_json(Path("metrics/autoencoder_training.json"), training)


if __name__ == "__main__":
    main()
