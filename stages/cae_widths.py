"""Stage cae_widths: the CAE width sweep (seasonloop.ablations.cae_widths).

For each width of cae_widths.widths (a fraction of Table 5's channels), a CAE with the `cae`
section's other settings is trained on the training images of train.seasons to its validation
plateau, and its code and patch-normalised output are evaluated on cae_widths.pairs (single-image
matching) beside raw_patchnorm. The width of the pipeline's own CAE (cae.channels, when cae is in
learners) is not trained again: fit@cae trained it with the same settings, images and seed, so the
stage loads models/cae. Writes metrics/cae_widths.json, plots/cae_widths.png and plots/cae_widths.md
(the table the report shows). An empty cae_widths.widths skips the sweep: the three outputs say
so, and torch is not imported.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, param, stage_main, train_seasons
from _datasets import test_images, training_images, training_places
from _ground_truth import evaluation_context, pair_truths
from seasonloop.ablations.cae_widths import run_width_sweep, width_channels, write_skipped_sweep, write_width_sweep
from seasonloop.models.cae import ConvolutionalAutoEncoder
from seasonloop.models.core.lookup import load_learner
from seasonloop.models.raw_patchnorm import RawPatchNorm
from seasonloop.params.seasons import available_pairs
from seasonloop.params.settings import CaeWidthsConfig

OUTPUTS = (Path("metrics/cae_widths.json"), Path("plots/cae_widths.png"), Path("plots/cae_widths.md"))


@stage_main
def main() -> None:
    params = load_params(
        "seed", "learners", "data.seasons", "train", "augment.copies", "evaluate", "sequence", "features",
        "cae_widths", "cae", "raw_patchnorm", "statistics",
    )  # fmt: skip
    sweep = CaeWidthsConfig.from_params(params)
    if not sweep.widths:
        write_skipped_sweep(*OUTPUTS)
        return
    seed = int(param(params, "seed"))
    cae_params = dict(param(params, "cae"))

    def new_cae(channels: list[int]) -> ConvolutionalAutoEncoder:
        return ConvolutionalAutoEncoder({**cae_params, "channels": channels}, seed=seed)

    for width in sweep.widths:  # every width and the CAE section are checked before the first fit
        new_cae(width_channels(width))
    pairs = available_pairs(data_seasons(params), sweep.pairs, "cae_widths.pairs")
    if not pairs:
        raise ValueError(f"cae_widths.pairs: none of {list(sweep.pairs)} has both seasons in data.seasons")
    seasons = sorted({season for pair in pairs for season in pair}, key=data_seasons(params).index)
    test = test_images(seasons)
    raw = RawPatchNorm(param(params, "raw_patchnorm"), seed=seed)
    raw.fit(test[seasons[0]], progress=False)  # nothing is learned; fit only records the image size
    chosen = train_seasons(params)
    fitted = {}
    if "cae" in param(params, "learners"):
        pipeline_cae = load_learner(Path("models/cae"))
        fitted = {
            width: pipeline_cae
            for width in sweep.widths
            if width_channels(width) == list(pipeline_cae.params["channels"])
            and pipeline_cae.params == new_cae(width_channels(width)).params
            and pipeline_cae.seed == seed
        }
    context = evaluation_context(params, test, pair_truths(pairs), pairs)
    training_set = (training_images(params, chosen), training_places(params, chosen))
    record = run_width_sweep(sweep.widths, new_cae, raw, training_set, context, fitted)
    write_width_sweep(record, *OUTPUTS)


if __name__ == "__main__":
    main()
